// The table of observation kinds (observations/src/kinds/kinds.cc): every
// kind once, each file key and each residual kind owned by one kind, and the
// keys ObservationsFileKeys() gives the reader (and the reference) exactly
// those of the table.
#include "kinds/kinds.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "rockcal/observations/file_keys.h"

namespace rockcal::observations::kinds {
namespace {

std::vector<std::string> Strings(const std::vector<const char*>& keys) {
  return std::vector<std::string>(keys.begin(), keys.end());
}

TEST(KindsTest, TheTableListsEveryKindOnceInResidualOrder) {
  std::vector<std::string> names;
  for (const Kind& kind : Kinds()) names.emplace_back(kind.name);
  EXPECT_EQ(names, (std::vector<std::string>{"tree_scars", "runout", "runs", "passing",
                                             "tracks_file", "impacts"}));
  for (const Kind& kind : Kinds()) {
    EXPECT_NE(kind.read, nullptr) << kind.name << " has no reader";
    EXPECT_NE(kind.misfit, nullptr) << kind.name << " has no misfit terms";
    ASSERT_FALSE(kind.root_keys.empty()) << kind.name;
    EXPECT_EQ(std::string(kind.root_keys.front()), kind.name)
        << kind.name << ": its first key at $ is " << kind.root_keys.front();
  }
}

// ResidualId::Parse reads back what the kinds print (reach.json and
// score.json are read through it), each kind's text by the kind itself.
TEST(KindsTest, EveryKindReadsBackTheTextItPrints) {
  const ResidualId ids[] = {
      ResidualId::Of(ObservationKind::kTreeScars, 2, "tree_scars[2] BP-1")
          .With(Statistic::kQuantile, 0.9),
      ResidualId::Of(ObservationKind::kTreeScars, 0, "tree_scars[0] x").With(Statistic::kMax),
      ResidualId::Of(ObservationKind::kRunoutDistance).With(Statistic::kQuantile, 0.025),
      ResidualId::Of(ObservationKind::kRunoutMassClass, -1, "10-40")
          .With(Statistic::kQuantile, 0.5),
      ResidualId::Of(ObservationKind::kRunoutLateral).With(Statistic::kQuantile, 0.1),
      ResidualId::Of(ObservationKind::kRunoutStopped).With(Statistic::kShare),
      ResidualId::Of(ObservationKind::kRun, -1, "v083").With(Statistic::kRunout),
      ResidualId::Of(ObservationKind::kPassing, 1, "passing[1] BP-2").With(Statistic::kFraction),
      ResidualId::Of(ObservationKind::kTracks, 1, "jump length").With(Statistic::kQuantile, 0.75),
      ResidualId::Of(ObservationKind::kImpact, -1, "i7").With(Statistic::kNormalRatio),
      ResidualId::Of(ObservationKind::kImpact, -1, "i7").With(Statistic::kTangentialRatio),
      ResidualId::Of(ObservationKind::kImpactsNormal).With(Statistic::kQuantile, 0.5),
      ResidualId::Of(ObservationKind::kImpactsTangential).With(Statistic::kQuantile, 0.5),
      ResidualId{}};
  for (const ResidualId& id : ids) {
    const ResidualId back = ResidualId::Parse(id.observation(), id.quantity());
    EXPECT_TRUE(back == id) << "'" << id.observation() << "' '" << id.quantity()
                            << "' read back as '" << back.observation() << "' '" << back.quantity()
                            << "' (index " << back.index << ", name '" << back.name << "')";
  }
  EXPECT_THROW(ResidualId::Parse("runout somewhere", "p10"), std::invalid_argument);
  EXPECT_THROW(ResidualId::Parse("runout distance", "median"), std::invalid_argument);
}

TEST(KindsTest, EveryResidualKindHasOneKindAndItsText) {
  std::map<ObservationKind, std::string> owner;
  for (const Kind& kind : Kinds()) {
    ASSERT_NE(kind.observation_text, nullptr) << kind.name;
    for (const ObservationKind k : kind.residual_kinds) {
      EXPECT_TRUE(owner.emplace(k, kind.name).second)
          << "residual kind " << static_cast<int>(k) << " listed by " << owner[k] << " and "
          << kind.name;
      EXPECT_FALSE(kind.observation_text(ResidualId::Of(k, 0, "x")).empty())
          << kind.name << ": residual kind " << static_cast<int>(k) << " has no text";
    }
  }
  // Every kind of ResidualId but none and a campaign's prior.
  for (const ObservationKind k :
       {ObservationKind::kTreeScars, ObservationKind::kRunoutDistance,
        ObservationKind::kRunoutMassClass, ObservationKind::kRunoutLateral,
        ObservationKind::kRunoutStopped, ObservationKind::kRun, ObservationKind::kPassing,
        ObservationKind::kTracks, ObservationKind::kImpact, ObservationKind::kImpactsNormal,
        ObservationKind::kImpactsTangential})
    EXPECT_EQ(owner.count(k), 1u) << "residual kind " << static_cast<int>(k) << " has no kind";
  EXPECT_EQ(owner.size(), 11u);
  EXPECT_EQ(owner.count(ObservationKind::kNone), 0u);
  EXPECT_EQ(owner.count(ObservationKind::kPrior), 0u);
}

TEST(KindsTest, TheFileKeysAreTheTablesEachOwnedByOneKind) {
  const std::vector<sites::FileObjectKeys>& file = ObservationsFileKeys();
  // "$": units, then every kind's keys in table order, then error.
  std::vector<std::string> root = {"units"};
  std::vector<std::string> error;
  std::map<std::string, std::vector<std::string>> objects;
  std::set<std::string> seen_root;
  for (const Kind& kind : Kinds()) {
    for (const char* key : kind.root_keys) {
      EXPECT_TRUE(seen_root.insert(key).second) << key << " at $ belongs to two kinds";
      root.emplace_back(key);
    }
    for (const char* key : kind.error_keys) error.emplace_back(key);
    for (const sites::FileObjectKeys& object : kind.objects)
      EXPECT_TRUE(objects.emplace(object.path, Strings(object.keys)).second)
          << object.path << " belongs to two kinds";
  }
  root.emplace_back("error");
  EXPECT_EQ(Strings(ObservationsKeysAt("$")), root);
  EXPECT_EQ(Strings(ObservationsKeysAt("$.error")), error);
  EXPECT_EQ(std::set<std::string>(error.begin(), error.end()).size(), error.size())
      << "an error key belongs to two kinds";
  // Every other object of the file is one kind's, with its keys, and back.
  std::size_t others = 0;
  for (const sites::FileObjectKeys& object : file) {
    if (object.path == "$" || object.path == "$.error") continue;
    ++others;
    ASSERT_EQ(objects.count(object.path), 1u) << object.path << " belongs to no kind";
    EXPECT_EQ(Strings(object.keys), objects[object.path]) << object.path;
  }
  EXPECT_EQ(others, objects.size());
  EXPECT_EQ(file.size(), objects.size() + 2);
  // The keys as the reader has always taken them (docs/reference/observations-file.md).
  EXPECT_EQ(root, (std::vector<std::string>{"units", "tree_scars", "runout", "runs", "runs_file",
                                            "passing", "passing_file", "tracks_file", "impacts",
                                            "impacts_file", "impact_draws", "error"}));
  EXPECT_EQ(error, (std::vector<std::string>{"height", "runout", "passing", "track", "impact_speed",
                                             "rebound"}));
}

}  // namespace
}  // namespace rockcal::observations::kinds
