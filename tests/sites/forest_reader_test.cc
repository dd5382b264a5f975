// The site file's "forest" (docs/reference/site-file.md, `$.forest`).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rockcal/core/simulate.h"
#include "rockcal/sites/site.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;
using Json = nlohmann::json;

// An SI site: a 100 m x 60 m plane from 50 m down to 0, grid of 2 m.
Json BaseSite() {
  return Json::parse(R"({
    "name": "forest slope",
    "units": "si",
    "surface": {"resolution": 2, "sphere_spacing": 2,
                "points": [[0, 0, 50], [100, 0, 0], [0, 60, 50], [100, 60, 0]]},
    "materials": [{"id": "soil", "hardness": 0.3, "roughness": 0.2}],
    "rocks": [{"count": 4, "shape": "sphere", "size": [0.5, 1], "unit_weight": 26,
               "release": {"zone": [[2, 20], [8, 20], [8, 40], [2, 40]]}}],
    "simulation": {"seed": 3, "max_time": 20}
  })");
}

struct Loaded {
  std::string path, error;
  Site site;
};
// Loads BaseSite() with `forest`, and `trees` written to trees.csv beside it.
Loaded Load(const Json& forest, const std::string& trees = "", bool expect_error = false) {
  TempDir dir;
  Json site = BaseSite();
  site["forest"] = forest;
  Loaded out;
  if (!trees.empty()) dir.Write("trees.csv", trees);
  out.path = dir.Write("site.json", site.dump(2));
  if (expect_error) {
    out.error = ErrorOf([&] { LoadSite(out.path); });
  } else {
    out.site = LoadSite(out.path);
  }
  return out;
}

TEST(ReadForest, TreeFileGivesItsStemsInSIWithTheirCapacities) {
  const Loaded l = Load({{"trees_file", "trees.csv"}},
                        "# a comment\nx,y,dbh_cm,species,height\n50,30,30,conifer,25\n"
                        "60,20,10,Broadleaf,12\n");
  const core::Forest& f = l.site.scene.forest;
  ASSERT_EQ(f.stems.size(), 2u);
  EXPECT_DOUBLE_EQ(f.stems[0].x, 50.0);
  EXPECT_DOUBLE_EQ(f.stems[0].dbh, 0.30);
  EXPECT_DOUBLE_EQ(f.stems[0].height, 25.0);
  EXPECT_EQ(f.stems[1].species, core::SpeciesClass::kBroadleaf);
  EXPECT_DOUBLE_EQ(f.stems[0].capacity, core::StemCapacity(0.30, core::SpeciesClass::kConifer));
  EXPECT_EQ(l.site.drawn_stems_first, 2u);  // none drawn
}

TEST(ReadForest, TreeFileErrorsNameTheFileAndLine) {
  struct Case {
    std::string text, says;
  };
  const Case cases[] = {
      {"x,y,dbh_cm\n50,30,-5\n", "trees.csv:2: dbh_cm -5"},
      {"x,y,dbh_cm\n50,30,30\n50,30,3000\n", "trees.csv:3: dbh_cm 3000"},
      {"x,y,dbh_cm\n50,30\n", "trees.csv:2: 2 fields; expected 3"},
      {"x,y,dbh_cm\n50,thirty,30\n", "trees.csv:2:"},
      {"x,y,dbh_cm\n500,30,30\n", "trees.csv:2: the stem at (500, 30) m is off the terrain"},
      {"x,y,dbh_cm,species\n50,30,30,oak\n", "trees.csv:2: species 'oak'"},
      {"x,y,diameter\n", "trees.csv:1: unknown column 'diameter'"},
      {"x,dbh_cm\n", "trees.csv:1: missing column y"},
      {"x,y,dbh_cm\n", "no stems"},
  };
  for (const Case& c : cases) {
    const Loaded l = Load({{"trees_file", "trees.csv"}}, c.text, true);
    EXPECT_THAT(l.error, HasSubstr(c.says)) << c.text;
  }
}

TEST(ReadForest, InlineTreesAndTheirErrorsNameTheJsonPath) {
  const Loaded ok = Load({{"trees", {{{"x", 40}, {"y", 30}, {"dbh_cm", 20}}}}});
  ASSERT_EQ(ok.site.scene.forest.stems.size(), 1u);
  EXPECT_DOUBLE_EQ(ok.site.scene.forest.stems[0].height, 20.0);  // the default
  const Loaded bad = Load({{"trees", {{{"x", 40}, {"y", 30}, {"dbh_cm", 0}}}}}, "", true);
  EXPECT_THAT(bad.error, HasSubstr("$.forest.trees[0]"));
  EXPECT_THAT(bad.error, HasSubstr("dbh_cm 0"));
  const Loaded key = Load({{"trees", {{{"x", 40}, {"y", 30}, {"dbh", 20}}}}}, "", true);
  EXPECT_THAT(key.error, HasSubstr("dbh"));
  const Loaded none = Load(Json::object(), "", true);
  EXPECT_THAT(none.error, HasSubstr("no stems"));
}

Json Stand(double per_ha) {
  return {{"zone", {{20, 10}, {80, 10}, {80, 50}, {20, 50}}},
          {"stems_per_ha", per_ha},
          {"dbh_mean_cm", 30},
          {"dbh_sd_cm", 10},
          {"conifer_percent", 70}};
}

TEST(ReadForest, StandsDrawTheirStemsFromTheSeed) {
  const Loaded a = Load({{"stands", {Stand(500)}}});
  const core::Forest& f = a.site.scene.forest;
  // 500 per ha on 0.24 ha: a Poisson count of mean 120.
  EXPECT_NEAR(static_cast<double>(f.stems.size()), 120.0, 4 * std::sqrt(120.0));
  EXPECT_EQ(a.site.drawn_stems_first, 0u);
  double conifers = 0, dbh = 0;
  for (const core::Stem& s : f.stems) {
    EXPECT_TRUE(s.x >= 20 && s.x <= 80 && s.y >= 10 && s.y <= 50) << s.x << ", " << s.y;
    EXPECT_GE(s.dbh, 0.05);
    conifers += s.species == core::SpeciesClass::kConifer;
    dbh += s.dbh;
  }
  const double n = static_cast<double>(f.stems.size());
  EXPECT_NEAR(conifers / n, 0.7, 4 * std::sqrt(0.21 / n));
  EXPECT_NEAR(dbh / n, 0.30, 4 * 0.10 / std::sqrt(n));
  // The same seed draws the same stand; another seed another.
  const Loaded b = Load({{"stands", {Stand(500)}}});
  ASSERT_EQ(b.site.scene.forest.stems.size(), f.stems.size());
  EXPECT_EQ(b.site.scene.forest.stems[5].x, f.stems[5].x);
}

TEST(ReadForest, ATreeFileAndAStandMix) {
  const Loaded l =
      Load({{"trees_file", "trees.csv"}, {"stands", {Stand(300)}}}, "x y dbh_cm\n50 30 30\n");
  EXPECT_EQ(l.site.drawn_stems_first, 1u);
  EXPECT_GT(l.site.scene.forest.stems.size(), 20u);
  // And the site runs through them.
  core::Scene scene = l.site.scene;
  scene.options.record.tree_strikes = true;
  const core::SimulationResult r = core::Simulate(scene);
  EXPECT_EQ(r.figures.non_finite, 0);
}

TEST(ReadForest, StandAndContactRangesAreChecked) {
  Json stand = Stand(300);
  stand["conifer_percent"] = 120;
  EXPECT_THAT(Load({{"stands", {stand}}}, "", true).error,
              HasSubstr("$.forest.stands[0].conifer_percent"));
  Json off = Stand(300);
  off["zone"] = {{20, 10}, {180, 10}, {180, 50}};
  EXPECT_THAT(Load({{"stands", {off}}}, "", true).error, HasSubstr("off the terrain"));
  EXPECT_THAT(Load({{"stands", {Stand(300)}}, {"contact", {{"restitution", 1.5}}}}, "", true).error,
              HasSubstr("$.forest.contact.restitution"));
}

}  // namespace
}  // namespace rockcal::sites
