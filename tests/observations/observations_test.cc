#include "rockcal/observations/observations.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "file_fixture.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/site.h"

namespace rockcal::observations {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kFt = 0.3048;

// The tutorial scene (sites/examples/tutorial), in SI: partitions BP-1 (x = 300 ft) and
// BP-2 (z = 40 ft), one rock group released from a rectangle whose centroid is
// (15, 100) ft.
core::Scene TutorialScene() {
  core::Scene scene;
  scene.name = "Tutorial slope";
  core::Partition bp1;
  bp1.id = "BP-1";
  bp1.kind = core::Partition::Kind::kX;
  bp1.value = 300 * kFt;
  core::Partition bp2;
  bp2.id = "BP-2";
  bp2.kind = core::Partition::Kind::kZ;
  bp2.value = 40 * kFt;
  scene.partitions = {bp1, bp2};
  core::RockGroup group;
  group.count = 10;
  group.release.zone = {Eigen::Vector2d(0, 60 * kFt), Eigen::Vector2d(30 * kFt, 60 * kFt),
                        Eigen::Vector2d(30 * kFt, 140 * kFt), Eigen::Vector2d(0, 140 * kFt)};
  scene.groups = {group};
  return scene;
}

// Observations files read against the tutorial scene.
class ObservationsFileTest : public testing::FileTest {
 protected:
  // Loads `json` written as obs.json; returns the error message ("" if none).
  std::string LoadError(const std::string& json) const {
    try {
      LoadObservations(Write("obs.json", json), scene_);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  core::Scene scene_ = TutorialScene();
};

const char kDesignExample[] = R"({
  "units": "UNITS",
  "tree_scars": [
    {"partition": "BP-1", "heights": [2.1, 3.0, 5.5, 1.2]},
    {"trees": [{"x": 310, "y": 95, "radius": 0.5, "heights": [1.0, 2.4]}]}
  ],
  "runout": {"stop_points": [[352, 80], [371, 102]]},
  "passing": [{"partition": "BP-2", "fraction": 0.35}],
  "error": {"height": 0.3, "runout": 5.0}
})";

std::string DesignExample(const std::string& units) {
  std::string text = kDesignExample;
  text.replace(text.find("UNITS"), 5, units);
  return text;
}

// A tree of the observations whose trunk touches a stem of the scene's
// forest is that stem: its scars are compared with the strikes on it, and
// the simulation is asked to record strikes; a tree nowhere near a stem is
// compared with passages, as without a forest.
TEST_F(ObservationsFileTest, ATreeAtAForestStemIsThatStem) {
  scene_.forest.Add(94.0, 30.0, 0.4, 20.0, core::SpeciesClass::kConifer);   // stem 0
  scene_.forest.Add(94.7, 30.0, 0.3, 20.0, core::SpeciesClass::kBroadleaf);  // stem 1
  const std::string json = R"({"units": "si", "tree_scars": [{"trees": [
      {"x": 94.6, "y": 30.0, "radius": 0.1, "heights": [1.0]},
      {"x": 94.1, "y": 30.0, "radius": 0.05, "heights": [1.5]},
      {"x": 60.0, "y": 30.0, "radius": 0.5, "heights": [0.8]}]}],
      "error": {"height": 0.2}})";
  const Observations obs = LoadObservations(Write("obs.json", json), scene_);
  const std::vector<Tree>& trees = obs.tree_scars[0].trees;
  EXPECT_EQ(trees[0].stem, 1);  // 0.1 m from stem 1's axis, 0.6 m from stem 0's (radii 0.15 + 0.1)
  EXPECT_EQ(trees[1].stem, 0);  // 0.1 m from stem 0's axis (radii 0.2 + 0.05)
  EXPECT_EQ(trees[2].stem, -1);
  EXPECT_TRUE(RequiredRecording(obs, core::RecordOptions{}).tree_strikes);
  bool noted = false;
  for (const std::string& note : obs.notes)
    noted = noted || note.find("2 of them at stems of the forest") != std::string::npos;
  EXPECT_TRUE(noted);

  scene_.forest = core::Forest{};
  const Observations bare = LoadObservations(Write("obs.json", json), scene_);
  for (const Tree& tree : bare.tree_scars[0].trees) EXPECT_EQ(tree.stem, -1);
  EXPECT_FALSE(RequiredRecording(bare, core::RecordOptions{}).tree_strikes);
}

TEST_F(ObservationsFileTest, ReadsTheDesignExampleInUsUnits) {
  const std::string path = Write("obs.json", DesignExample("us"));
  const Observations obs = LoadObservations(path, scene_);
  EXPECT_EQ(obs.path, path);
  EXPECT_EQ(obs.units, sites::Units::kUS);
  ASSERT_EQ(obs.tree_scars.size(), 2u);

  const ScarSet& at_partition = obs.tree_scars[0];
  EXPECT_TRUE(at_partition.at_partition());
  EXPECT_EQ(at_partition.partition, 0);
  EXPECT_EQ(at_partition.label, "tree_scars[0] BP-1");
  ASSERT_EQ(at_partition.heights.size(), 4u);
  EXPECT_DOUBLE_EQ(at_partition.heights[0], 2.1 * kFt);
  EXPECT_DOUBLE_EQ(at_partition.heights[2], 5.5 * kFt);

  const ScarSet& at_trees = obs.tree_scars[1];
  EXPECT_FALSE(at_trees.at_partition());
  EXPECT_EQ(at_trees.label, "tree_scars[1] trees");
  ASSERT_EQ(at_trees.trees.size(), 1u);
  EXPECT_DOUBLE_EQ(at_trees.trees[0].x, 310 * kFt);
  EXPECT_DOUBLE_EQ(at_trees.trees[0].y, 95 * kFt);
  EXPECT_DOUBLE_EQ(at_trees.trees[0].radius, 0.5 * kFt);
  EXPECT_EQ(at_trees.trees[0].probe, 0);
  EXPECT_THAT(at_trees.ObservedHeights(), ::testing::ElementsAre(::testing::DoubleEq(1.0 * kFt),
                                                                 ::testing::DoubleEq(2.4 * kFt)));

  ASSERT_TRUE(obs.runout.has_value());
  ASSERT_EQ(obs.runout->stop_points.size(), 2u);
  EXPECT_DOUBLE_EQ(obs.runout->stop_points[1].x(), 371 * kFt);
  EXPECT_DOUBLE_EQ(obs.runout->stop_points[1].y(), 102 * kFt);
  EXPECT_EQ(obs.runout->distances.size(), 2u);
  EXPECT_EQ(obs.runout->lateral.size(), 2u);

  ASSERT_EQ(obs.passing.size(), 1u);
  EXPECT_EQ(obs.passing[0].partition, 1);
  EXPECT_EQ(obs.passing[0].label, "passing[0] BP-2");
  EXPECT_DOUBLE_EQ(obs.passing[0].fraction, 0.35);

  EXPECT_DOUBLE_EQ(obs.error.height, 0.3 * kFt);
  EXPECT_DOUBLE_EQ(obs.error.runout, 5.0 * kFt);
  EXPECT_DOUBLE_EQ(obs.error.passing, 0.05);  // the default
  EXPECT_FALSE(obs.notes.empty());
}

TEST_F(ObservationsFileTest, ReadsSiUnitsWithoutConversion) {
  const Observations obs = LoadObservations(Write("obs.json", DesignExample("si")), scene_);
  EXPECT_EQ(obs.units, sites::Units::kSI);
  EXPECT_DOUBLE_EQ(obs.tree_scars[0].heights[0], 2.1);
  EXPECT_DOUBLE_EQ(obs.tree_scars[1].trees[0].x, 310);
  EXPECT_DOUBLE_EQ(obs.tree_scars[1].trees[0].radius, 0.5);
  EXPECT_DOUBLE_EQ(obs.runout->stop_points[0].x(), 352);
  EXPECT_DOUBLE_EQ(obs.error.height, 0.3);
  EXPECT_DOUBLE_EQ(obs.error.runout, 5.0);
  EXPECT_DOUBLE_EQ(obs.passing[0].fraction, 0.35);  // fractions have no units
}

TEST_F(ObservationsFileTest, DefaultRunoutDirectionRunsFromTheReleaseToTheMeanStop) {
  const Observations obs = LoadObservations(Write("obs.json", R"({
    "units": "si",
    "runout": {"stop_points": [[100, 95], [120, 105], [110, 103]]},
    "error": {"runout": 2}
  })"),
                                            scene_);
  const Runout& r = *obs.runout;
  // Release rectangle centroid (15, 100) ft; mean stop (110, 101) m.
  EXPECT_NEAR(r.from.x(), 15 * kFt, 1e-12);
  EXPECT_NEAR(r.from.y(), 100 * kFt, 1e-12);
  const Eigen::Vector2d expected = (Eigen::Vector2d(110, 101) - r.from).normalized();
  EXPECT_NEAR(r.direction.x(), expected.x(), 1e-12);
  EXPECT_NEAR(r.direction.y(), expected.y(), 1e-12);
  ASSERT_EQ(r.distances.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const Eigen::Vector2d d = r.stop_points[i] - r.from;
    EXPECT_NEAR(r.distances[i], d.dot(expected), 1e-9);
    EXPECT_NEAR(r.lateral[i], expected.x() * d.y() - expected.y() * d.x(), 1e-9);
  }
  // The lateral offsets of the stop points average to zero about the line
  // through their mean.
  EXPECT_NEAR(r.lateral[0] + r.lateral[1] + r.lateral[2], 0.0, 1e-9);
}

TEST_F(ObservationsFileTest, StopPointsMayStateTheirOriginAndDirection) {
  const Observations obs = LoadObservations(Write("obs.json", R"({
    "units": "us",
    "runout": {"stop_points": [[110, 20], [100, -10]], "from": [10, 0], "direction": [2, 0]},
    "error": {"runout": 2}
  })"),
                                            scene_);
  const Runout& r = *obs.runout;
  EXPECT_DOUBLE_EQ(r.direction.x(), 1.0);
  EXPECT_DOUBLE_EQ(r.direction.y(), 0.0);
  EXPECT_NEAR(r.distances[0], 100 * kFt, 1e-12);
  EXPECT_NEAR(r.distances[1], 90 * kFt, 1e-12);
  EXPECT_NEAR(r.lateral[0], 20 * kFt, 1e-12);  // left of +x is +y
  EXPECT_NEAR(r.lateral[1], -10 * kFt, 1e-12);
}

TEST_F(ObservationsFileTest, DistancesNeedOriginAndDirectionWhichIsNormalised) {
  const Observations obs = LoadObservations(Write("obs.json", R"({
    "units": "us",
    "runout": {"distances": [300, 320.5], "from": [10, 20], "direction": [3, 4]},
    "error": {"runout": 5}
  })"),
                                            scene_);
  const Runout& r = *obs.runout;
  EXPECT_TRUE(r.stop_points.empty());
  EXPECT_FALSE(r.has_lateral());
  EXPECT_DOUBLE_EQ(r.direction.x(), 0.6);
  EXPECT_DOUBLE_EQ(r.direction.y(), 0.8);
  EXPECT_DOUBLE_EQ(r.from.x(), 10 * kFt);
  EXPECT_DOUBLE_EQ(r.from.y(), 20 * kFt);
  EXPECT_THAT(r.distances, ::testing::ElementsAre(::testing::DoubleEq(300 * kFt),
                                                  ::testing::DoubleEq(320.5 * kFt)));
}

TEST_F(ObservationsFileTest, PassingErrorMayBeGiven) {
  const Observations obs = LoadObservations(Write("obs.json", R"({
    "units": "si", "passing": [{"partition": "BP-1", "fraction": 0}],
    "error": {"passing": 0.1}
  })"),
                                            scene_);
  EXPECT_DOUBLE_EQ(obs.error.passing, 0.1);
  EXPECT_DOUBLE_EQ(obs.passing[0].fraction, 0.0);
}

// Each bad file names the file, the JSON path and what was expected.
struct BadCase {
  const char* name;
  const char* json;
  const char* path;      // JSON path expected in the message
  const char* expected;  // fragment of what was expected
};

const BadCase kBadCases[] = {
    {"unknown top-level key",
     R"({"units": "si", "colour": 1, "passing": [{"partition": "BP-1", "fraction": 0.1}]})",
     "$.colour", "unknown key 'colour'"},
    {"missing units", R"({"passing": [{"partition": "BP-1", "fraction": 0.1}]})", "obs.json: $",
     "missing required key 'units'"},
    {"unknown units", R"({"units": "metric", "passing": [{"partition": "BP-1", "fraction": 0.1}]})",
     "$.units", "allowed: us, si"},
    {"unknown partition",
     R"({"units": "si", "tree_scars": [{"partition": "BP-9", "heights": [1]}], "error": {"height": 0.1}})",
     "$.tree_scars[0].partition", "unknown partition id (partitions of the site: BP-1, BP-2)"},
    {"partition id not a string",
     R"({"units": "si", "passing": [{"partition": 1, "fraction": 0.1}]})", "$.passing[0].partition",
     "expected a string"},
    {"negative height",
     R"({"units": "si", "tree_scars": [{"partition": "BP-1", "heights": [1, -2]}], "error": {"height": 0.1}})",
     "$.tree_scars[0].heights[1]", "expected a number >= 0 (found -2)"},
    {"heights not a list",
     R"({"units": "si", "tree_scars": [{"partition": "BP-1", "heights": "3"}], "error": {"height": 0.1}})",
     "$.tree_scars[0].heights", "expected an array"},
    {"empty heights",
     R"({"units": "si", "tree_scars": [{"partition": "BP-1", "heights": []}], "error": {"height": 0.1}})",
     "$.tree_scars[0].heights", "at least 1"},
    {"empty tree_scars", R"({"units": "si", "tree_scars": [], "error": {"height": 0.1}})",
     "$.tree_scars", "at least 1"},
    {"heights and heights_file",
     R"({"units": "si", "tree_scars": [{"partition": "BP-1", "heights": [1], "heights_file": "h.csv"}], "error": {"height": 0.1}})",
     "$.tree_scars[0]", "exactly one of 'heights', 'heights_file'"},
    {"partition and trees",
     R"({"units": "si", "tree_scars": [{"partition": "BP-1", "trees": []}], "error": {"height": 0.1}})",
     "$.tree_scars[0]", "exactly one of 'partition', 'trees', 'trees_file'"},
    {"heights without partition",
     R"({"units": "si", "tree_scars": [{"heights": [1]}], "error": {"height": 0.1}})",
     "$.tree_scars[0]", "exactly one of 'partition', 'trees', 'trees_file'"},
    {"tree without radius",
     R"({"units": "si", "tree_scars": [{"trees": [{"x": 1, "y": 2, "heights": [1]}]}], "error": {"height": 0.1}})",
     "$.tree_scars[0].trees[0]", "missing required key 'radius'"},
    {"tree with unknown key",
     R"({"units": "si", "tree_scars": [{"trees": [{"x": 1, "y": 2, "diameter": 1, "heights": [1]}]}], "error": {"height": 0.1}})",
     "$.tree_scars[0].trees[0].diameter", "allowed keys: x, y, radius, heights, heights_file"},
    {"tree x not a number",
     R"({"units": "si", "tree_scars": [{"trees": [{"x": "1", "y": 2, "radius": 1, "heights": [1]}]}], "error": {"height": 0.1}})",
     "$.tree_scars[0].trees[0].x", "expected a number"},
    {"fraction above 1", R"({"units": "si", "passing": [{"partition": "BP-2", "fraction": 1.5}]})",
     "$.passing[0].fraction", "expected a number in [0, 1]"},
    {"fraction below 0", R"({"units": "si", "passing": [{"partition": "BP-2", "fraction": -0.1}]})",
     "$.passing[0].fraction", "expected a number in [0, 1]"},
    {"passing a partition twice",
     R"({"units": "si", "passing": [{"partition": "BP-2", "fraction": 0.1},
        {"partition": "BP-1", "fraction": 0.5}, {"partition": "BP-2", "fraction": 0.3}]})",
     "$.passing[2].partition",
     "partition 'BP-2' is given twice (first at $.passing[0]); expected each partition once"},
    {"passing and passing_file",
     R"({"units": "si", "passing": [{"partition": "BP-2", "fraction": 0.1}], "passing_file": "p.csv"})",
     "obs.json: $", "'passing' and 'passing_file' both given"},
    {"zero direction",
     R"({"units": "si", "runout": {"distances": [1], "from": [0, 0], "direction": [0, 0]}, "error": {"runout": 1}})",
     "$.runout.direction", "non-zero direction"},
    {"distances without from",
     R"({"units": "si", "runout": {"distances": [1], "direction": [1, 0]}, "error": {"runout": 1}})",
     "$.runout", "missing required key 'from'"},
    {"distances without direction",
     R"({"units": "si", "runout": {"distances": [1], "from": [1, 0]}, "error": {"runout": 1}})",
     "$.runout", "missing required key 'direction'"},
    {"stop point with three numbers",
     R"({"units": "si", "runout": {"stop_points": [[1, 2, 3]]}, "error": {"runout": 1}})",
     "$.runout.stop_points[0]", "expected an array of 2 numbers"},
    {"stop points and distances",
     R"({"units": "si", "runout": {"stop_points": [[1, 2]], "distances": [3]}, "error": {"runout": 1}})",
     "$.runout", "keys 'stop_points' and 'distances' both given"},
    {"mean stop at the release",
     R"({"units": "us", "runout": {"stop_points": [[10, 100], [20, 100]]}, "error": {"runout": 1}})",
     "$.runout", "cannot choose a runout direction"},
    // Issue 14: physically meaningless values.
    {"huge direction",
     R"({"units": "si", "runout": {"distances": [1], "from": [0, 0], "direction": [1e200, 1e200]}, "error": {"runout": 1}})",
     "$.runout.direction", "whose normalisation is finite"},
    {"runout error of 20 km",
     R"({"units": "si", "runout": {"stop_points": [[100, 2]]}, "error": {"runout": 2e4}})",
     "$.error.runout", "runout error 20000 m is outside the physically sensible range"},
    {"height error of 1e5 ft",
     R"({"units": "us", "tree_scars": [{"partition": "BP-1", "heights": [1]}], "error": {"height": 1e5}})",
     "$.error.height", "expected [0, 32808.39895] ft"},
    {"stop point far away",
     R"({"units": "si", "runout": {"stop_points": [[1e8, 2]]}, "error": {"runout": 1}})",
     "$.runout.stop_points[0][0]", "coordinate 100000000 m is outside"},
    {"tree far away",
     R"({"units": "si", "tree_scars": [{"trees": [{"x": 1, "y": -2e7, "radius": 1, "heights": [1]}]}], "error": {"height": 0.1}})",
     "$.tree_scars[0].trees[0].y", "outside the physically sensible range"},
    {"missing height error",
     R"({"units": "si", "tree_scars": [{"partition": "BP-1", "heights": [1]}], "error": {"runout": 1}})",
     "$.error", "missing required key 'height'"},
    {"missing error object", R"({"units": "si", "runout": {"stop_points": [[100, 2]]}})",
     "obs.json: $", "missing required key 'error'"},
    {"negative runout error",
     R"({"units": "si", "runout": {"stop_points": [[100, 2]]}, "error": {"runout": -1}})",
     "$.error.runout", "expected a number > 0"},
    {"passing error above 1",
     R"({"units": "si", "passing": [{"partition": "BP-2", "fraction": 0.1}], "error": {"passing": 2}})",
     "$.error.passing", "expected a fraction in (0, 1]"},
    {"unknown error key",
     R"({"units": "si", "passing": [{"partition": "BP-2", "fraction": 0.1}], "error": {"speed": 2}})",
     "$.error.speed", "unknown key 'speed'"},
    {"no observations", R"({"units": "si", "error": {"height": 1}})", "obs.json: $",
     "no observations"},
    {"not an object", R"([1, 2])", "obs.json: $", "expected an object"},
};

TEST_F(ObservationsFileTest, BadFilesNameFilePathAndExpectation) {
  for (const BadCase& c : kBadCases) {
    SCOPED_TRACE(c.name);
    const std::string message = LoadError(c.json);
    ASSERT_FALSE(message.empty()) << "no error for: " << c.json;
    EXPECT_THAT(message, HasSubstr((dir_ / "obs.json").string()));
    EXPECT_THAT(message, HasSubstr(c.path));
    EXPECT_THAT(message, HasSubstr(c.expected));
  }
}

TEST_F(ObservationsFileTest, SyntaxErrorNamesFileAndLine) {
  const std::string message = LoadError("{\n  \"units\": \"si\",\n  \"passing\": [\n}\n");
  EXPECT_THAT(message, HasSubstr((dir_ / "obs.json").string() + ":4:"));
  EXPECT_THAT(message, HasSubstr("invalid JSON"));
}

TEST_F(ObservationsFileTest, MissingFileIsAnInputError) {
  const std::string path = (dir_ / "absent.json").string();
  try {
    LoadObservations(path, scene_);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path));
    EXPECT_THAT(e.what(), HasSubstr("cannot open"));
  }
}

TEST_F(ObservationsFileTest, SceneWithoutPartitionsSaysSo) {
  scene_.partitions.clear();
  EXPECT_THAT(LoadError(R"({"units": "si", "passing": [{"partition": "BP-1", "fraction": 0.1}]})"),
              HasSubstr("the site has no partitions"));
}

// --- CSV forms -------------------------------------------------------------

TEST_F(ObservationsFileTest, ReadsEveryCsvFormRelativeToTheObservationsFile) {
  std::filesystem::create_directories(dir_ / "data");
  Write("data/scars.csv", "height\n2.1\n\n3.0\r\n5.5\n");
  Write("data/tree_heights.csv", "# scars at the big pine\n1.0\n2.4\n");
  Write("data/trees.csv", "x,y,radius,height\n310,95,0.5,1.0\n320,99,0.25,0.5\n310,95,0.5,2.4\n");
  Write("data/stops.csv", "# x y, blank separated\n352 80\n371   102\n");
  Write("data/passing.csv", "partition,fraction\nBP-2,0.35\n\"BP-1\", 0.9\n");
  Write("data/distances.csv", "300\n320.5\n");
  const std::string path = Write("obs.json", R"({
    "units": "us",
    "tree_scars": [
      {"partition": "BP-1", "heights_file": "data/scars.csv"},
      {"trees": [{"x": 1, "y": 2, "radius": 0.5, "heights_file": "data/tree_heights.csv"}]},
      {"trees_file": "data/trees.csv"}
    ],
    "runout": {"stop_points_file": "data/stops.csv"},
    "passing_file": "data/passing.csv",
    "error": {"height": 0.3, "runout": 5.0}
  })");
  const Observations obs = LoadObservations(path, scene_);
  ASSERT_EQ(obs.tree_scars.size(), 3u);
  EXPECT_THAT(obs.tree_scars[0].heights,
              ::testing::ElementsAre(::testing::DoubleEq(2.1 * kFt), ::testing::DoubleEq(3.0 * kFt),
                                     ::testing::DoubleEq(5.5 * kFt)));
  EXPECT_THAT(
      obs.tree_scars[1].trees[0].heights,
      ::testing::ElementsAre(::testing::DoubleEq(1.0 * kFt), ::testing::DoubleEq(2.4 * kFt)));
  // Rows at the same (x, y) are one tree; trees keep their first-seen order.
  const std::vector<Tree>& trees = obs.tree_scars[2].trees;
  ASSERT_EQ(trees.size(), 2u);
  EXPECT_DOUBLE_EQ(trees[0].x, 310 * kFt);
  EXPECT_DOUBLE_EQ(trees[0].radius, 0.5 * kFt);
  EXPECT_EQ(trees[0].heights.size(), 2u);
  EXPECT_DOUBLE_EQ(trees[1].y, 99 * kFt);
  EXPECT_EQ(trees[1].heights.size(), 1u);
  // Probes are numbered over all tree-form sets in file order.
  EXPECT_EQ(obs.tree_scars[1].trees[0].probe, 0);
  EXPECT_EQ(trees[0].probe, 1);
  EXPECT_EQ(trees[1].probe, 2);

  ASSERT_EQ(obs.runout->stop_points.size(), 2u);
  EXPECT_DOUBLE_EQ(obs.runout->stop_points[1].x(), 371 * kFt);
  ASSERT_EQ(obs.passing.size(), 2u);
  EXPECT_EQ(obs.passing[0].partition, 1);
  EXPECT_DOUBLE_EQ(obs.passing[0].fraction, 0.35);
  EXPECT_EQ(obs.passing[1].partition, 0);
  EXPECT_EQ(obs.passing[1].label, "passing[1] BP-1");
  // Every file read, the observations file first (a calibration's log
  // fingerprints them).
  ASSERT_EQ(obs.inputs.size(), 6u);
  EXPECT_EQ(obs.inputs[0], path);
  EXPECT_EQ(obs.inputs[1], (dir_ / "data/scars.csv").string());

  const Observations d = LoadObservations(Write("obs2.json", R"({
    "units": "si",
    "runout": {"distances_file": "data/distances.csv", "from": [0, 0], "direction": [1, 0]},
    "error": {"runout": 5.0}
  })"),
                                          scene_);
  EXPECT_THAT(d.runout->distances,
              ::testing::ElementsAre(::testing::DoubleEq(300), ::testing::DoubleEq(320.5)));
}

TEST_F(ObservationsFileTest, BadCsvRowNamesFileAndLine) {
  Write("scars.csv", "height\n2.1\n3.0 ft\n");
  const std::string message = LoadError(R"({"units": "si",
    "tree_scars": [{"partition": "BP-1", "heights_file": "scars.csv"}], "error": {"height": 0.3}})");
  EXPECT_THAT(message, HasSubstr((dir_ / "scars.csv").string() + ":3: "));
  EXPECT_THAT(message, HasSubstr("expected 1 value per row (height), found 2"));

  Write("scars.csv", "2.1\n\nabc\n");
  EXPECT_THAT(LoadError(R"({"units": "si",
    "tree_scars": [{"partition": "BP-1", "heights_file": "scars.csv"}], "error": {"height": 0.3}})"),
              HasSubstr("scars.csv:3: expected a number for 'height' (found 'abc')"));

  Write("scars.csv", "0x10\n");
  EXPECT_THAT(LoadError(R"({"units": "si",
    "tree_scars": [{"partition": "BP-1", "heights_file": "scars.csv"}], "error": {"height": 0.3}})"),
              HasSubstr("scars.csv:1: expected a number for 'height' (found '0x10')"));

  Write("scars.csv", "2.1\n-4\n");
  EXPECT_THAT(LoadError(R"({"units": "si",
    "tree_scars": [{"partition": "BP-1", "heights_file": "scars.csv"}], "error": {"height": 0.3}})"),
              HasSubstr("scars.csv:2: expected 'height' >= 0 (found -4)"));
}

TEST_F(ObservationsFileTest, BadCsvFilesOfEachForm) {
  Write("stops.csv", "x,y\n1,2\n3\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "runout": {"stop_points_file": "stops.csv"},
                            "error": {"runout": 1}})"),
              HasSubstr("stops.csv:3: expected 2 values per row (x, y), found 1"));

  Write("passing.csv", "BP-1,0.5\nBP-7,0.5\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "passing_file": "passing.csv"})"),
              HasSubstr("passing.csv:2: unknown partition id 'BP-7' (partitions of the site: "
                        "BP-1, BP-2)"));

  Write("passing.csv", "BP-1,1.5\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "passing_file": "passing.csv"})"),
              HasSubstr("passing.csv:1: expected 'fraction' in [0, 1] (found 1.5)"));

  Write("passing.csv", "partition,fraction\nBP-1,0.5\n# the lower barrier\nBP-2,0.2\nBP-1,0.4\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "passing_file": "passing.csv"})"),
              HasSubstr("passing.csv:5: partition 'BP-1' is given twice (first on line 2); "
                        "expected each partition once"));

  Write("trees.csv", "1,2,0.5,1\n1,2,0.7,2\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "tree_scars": [{"trees_file": "trees.csv"}],
                            "error": {"height": 1}})"),
              HasSubstr("trees.csv:2: tree at (1, 2) has radius 0.7 here but a different radius "
                        "on line 1"));

  Write("empty.csv", "# nothing\nheight\n\n");
  EXPECT_THAT(LoadError(R"({"units": "si",
    "tree_scars": [{"partition": "BP-1", "heights_file": "empty.csv"}], "error": {"height": 0.3}})"),
              HasSubstr("empty.csv: no data rows"));

  const std::string missing = LoadError(R"({"units": "si",
    "runout": {"stop_points_file": "nowhere.csv"}, "error": {"runout": 1}})");
  EXPECT_THAT(missing, HasSubstr("obs.json: $.runout.stop_points_file"));
  EXPECT_THAT(missing, HasSubstr("cannot open CSV file"));
  EXPECT_THAT(missing, HasSubstr("nowhere.csv"));
}

// --- RequiredRecording and helpers -----------------------------------------

TEST(RequiredRecordingTest, RunoutOnlyRecordsNeitherPartitionsNorTrees) {
  Observations obs;
  obs.runout = Runout();
  obs.runout->distances = {1.0};
  core::RecordOptions base;
  base.partitions = true;
  base.energy_check = false;
  base.trajectories = 3;
  base.trees = {core::TreeProbe{1, 2, 3}};
  const core::RecordOptions rec = RequiredRecording(obs, base);
  EXPECT_FALSE(rec.partitions);
  EXPECT_TRUE(rec.trees.empty());
  EXPECT_FALSE(rec.energy_check);  // untouched
  EXPECT_EQ(rec.trajectories, 3);  // untouched
}

TEST(RequiredRecordingTest, PartitionsAndTreesWhenObserved) {
  Observations obs;
  ScarSet trees;
  Tree a;
  a.x = 1;
  a.y = 2;
  a.radius = 0.3;
  a.heights = {1};
  a.probe = 0;
  Tree b = a;
  b.x = 5;
  b.probe = 1;
  trees.trees = {a, b};
  obs.tree_scars.push_back(trees);

  core::RecordOptions base;
  base.partitions = false;
  core::RecordOptions rec = RequiredRecording(obs, base);
  EXPECT_FALSE(rec.partitions);  // tree-form scars need no partitions
  ASSERT_EQ(rec.trees.size(), 2u);
  EXPECT_DOUBLE_EQ(rec.trees[0].x, 1);
  EXPECT_DOUBLE_EQ(rec.trees[0].y, 2);
  EXPECT_DOUBLE_EQ(rec.trees[0].radius, 0.3);
  EXPECT_DOUBLE_EQ(rec.trees[1].x, 5);
  EXPECT_TRUE(rec.energy_check);

  Passing passing;
  passing.partition = 0;
  obs.passing.push_back(passing);
  EXPECT_TRUE(RequiredRecording(obs, base).partitions);

  Observations at_partition;
  ScarSet set;
  set.partition = 1;
  set.heights = {1};
  at_partition.tree_scars.push_back(set);
  rec = RequiredRecording(at_partition, base);
  EXPECT_TRUE(rec.partitions);
  EXPECT_TRUE(rec.trees.empty());
}

TEST(ReleaseCentroidTest, PointZoneAndDegenerateZone) {
  core::Release point;
  point.point = Eigen::Vector2d(3, 4);
  EXPECT_EQ(ReleaseCentroid(point), Eigen::Vector2d(3, 4));

  // An L-shaped zone: unit squares at (0..2, 0..1) and (0..1, 1..2); the area
  // centroid (5/6, 5/6) differs from the vertex mean.
  core::Release l_shape;
  l_shape.zone = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const Eigen::Vector2d c = ReleaseCentroid(l_shape);
  EXPECT_NEAR(c.x(), 5.0 / 6.0, 1e-12);
  EXPECT_NEAR(c.y(), 5.0 / 6.0, 1e-12);

  core::Release line;
  line.zone = {{0, 0}, {2, 2}};
  const Eigen::Vector2d m = ReleaseCentroid(line);
  EXPECT_NEAR(m.x(), 1.0, 1e-12);
  EXPECT_NEAR(m.y(), 1.0, 1e-12);
}

// Observations with every kind of list: a partition scar set, a tree scar
// set over two trees, runout stop points and a passing fraction.
Observations FoldFixture() {
  Observations obs;
  obs.path = "obs.json";
  ScarSet at_partition;
  at_partition.label = "tree_scars[0] P";
  at_partition.partition = 0;
  at_partition.heights = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  ScarSet at_trees;
  at_trees.label = "tree_scars[1] trees";
  Tree a, b;
  a.heights = {0.1, 0.2, 0.3};
  a.probe = 0;
  b.heights = {0.4, 0.5, 0.6, 0.7};
  b.probe = 1;
  at_trees.trees = {a, b};
  obs.tree_scars = {at_partition, at_trees};
  Runout runout;
  for (int i = 0; i < 9; ++i) {
    runout.stop_points.emplace_back(10.0 + i, 1.0);
    runout.distances.push_back(10.0 + i);
    runout.lateral.push_back(1.0);
  }
  obs.runout = runout;
  obs.passing = {{"passing[0] P", 0, 0.5}};
  return obs;
}

TEST(Folds, EveryValueIsHeldOutOnceAndTrainedOnOtherwise) {
  const Observations obs = FoldFixture();
  const std::vector<Fold> folds = MakeFolds(obs, 3, 7);
  ASSERT_EQ(folds.size(), 3u);
  std::vector<double> held_heights, held_distances;
  for (const Fold& fold : folds) {
    const Observations train = Subset(obs, fold, false);
    const Observations test = Subset(obs, fold, true);
    EXPECT_EQ(train.passing.size(), 1u);  // passing fractions train in every fold
    EXPECT_TRUE(test.passing.empty());
    ASSERT_TRUE(test.runout && train.runout);
    EXPECT_EQ(test.runout->distances.size(), 3u);  // 9 dealt round-robin over 3
    EXPECT_EQ(train.runout->distances.size() + test.runout->distances.size(), 9u);
    EXPECT_EQ(test.runout->stop_points.size(), test.runout->distances.size());
    ASSERT_EQ(test.tree_scars.size(), 2u);
    for (std::size_t s = 0; s < 2; ++s) {
      const std::size_t all = obs.tree_scars[s].ObservedHeights().size();
      const std::size_t held = test.tree_scars[s].ObservedHeights().size();
      EXPECT_EQ(train.tree_scars[s].ObservedHeights().size() + held, all);
      EXPECT_LE(held, all / 3 + 1);
      EXPECT_GE(held, all / 3);
      for (double h : test.tree_scars[s].ObservedHeights()) held_heights.push_back(h);
    }
    // Tree probes are renumbered over the trees kept.
    int probe = 0;
    for (const Tree& t : test.tree_scars[1].trees) EXPECT_EQ(t.probe, probe++);
    for (double d : test.runout->distances) held_distances.push_back(d);
  }
  std::sort(held_heights.begin(), held_heights.end());
  std::vector<double> all_heights = obs.tree_scars[0].heights;
  for (double h : obs.tree_scars[1].ObservedHeights()) all_heights.push_back(h);
  std::sort(all_heights.begin(), all_heights.end());
  EXPECT_EQ(held_heights, all_heights);
  std::sort(held_distances.begin(), held_distances.end());
  EXPECT_EQ(held_distances, obs.runout->distances);
  // The same seed deals the same folds; another seed another order.
  EXPECT_EQ(MakeFolds(obs, 3, 7)[1].runout, folds[1].runout);
}

// A 100 m x 100 m terrain, two rock groups "a" (released at (10, 90)) and
// "b" (at (50, 90)).
core::Scene RunsScene() {
  core::Scene scene;
  scene.grid.spacing = 10.0;
  scene.grid.nx = scene.grid.ny = 11;
  scene.grid.z.assign(121, 0.0);
  scene.grid.material.assign(121, 0);
  core::RockGroup a, b;
  a.id = "a";
  a.release.point = Eigen::Vector2d(10, 90);
  b.id = "b";
  b.release.point = Eigen::Vector2d(50, 90);
  scene.groups = {a, b};
  return scene;
}

TEST_F(ObservationsFileTest, RunsTieEachStopToItsOwnRelease) {
  scene_ = RunsScene();
  const Observations obs = LoadObservations(
      Write("obs.json", R"({"units": "si", "error": {"runout": 2},
        "runs": [{"id": "a", "stop": [10, 60]}, {"id": "r2", "group": "b", "stop": [90, 60]}]})"),
      scene_);
  ASSERT_TRUE(obs.runout && obs.runout->has_runs());
  EXPECT_EQ(obs.runout->run_groups, (std::vector<int>{0, 1}));
  EXPECT_DOUBLE_EQ(obs.runout->distances[0], 30.0);
  EXPECT_DOUBLE_EQ(obs.runout->distances[1], 50.0);
  EXPECT_THAT(obs.notes.back(), HasSubstr("2 tracked runs, each measured from its own"));
  // The CSV form: a header names the columns, other columns are ignored.
  Write("runs.csv", "run,block_id,stop_x_m,stop_y_m\na,1,10,60\nb,2,90,60\n");
  const Observations csv = LoadObservations(
      Write("obs.json", R"({"units": "si", "error": {"runout": 2}, "runs_file": "runs.csv"})"),
      scene_);
  EXPECT_EQ(csv.runout->distances, obs.runout->distances);
  EXPECT_EQ(csv.runout->run_ids, (std::vector<std::string>{"a", "b"}));
}

TEST_F(ObservationsFileTest, BadRunsNameTheFileAndRow) {
  scene_ = RunsScene();
  EXPECT_THAT(LoadError(R"({"units": "si", "error": {"runout": 2},
        "runs": [{"id": "a", "stop": [10, 60]}, {"id": "c", "stop": [10, 60]}]})"),
              AllOf(HasSubstr("$.runs[1]"), HasSubstr("no rock group of the site has the id 'c'"),
                    HasSubstr("ids: a, b")));
  EXPECT_THAT(LoadError(R"({"units": "si", "error": {"runout": 2},
        "runs": [{"id": "a", "stop": [10, 160]}]})"),
              AllOf(HasSubstr("$.runs[0]"), HasSubstr("stop point (10, 160) m is off the terrain")));
  Write("runs.csv", "id,stop_x,stop_y\na,10,60\nb,90,-5\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "error": {"runout": 2}, "runs_file": "runs.csv"})"),
              AllOf(HasSubstr("runs.csv:3"), HasSubstr("off the terrain")));
  Write("runs.csv", "id,stop_x,stop_y\na,10,60\nd,90,50\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "error": {"runout": 2}, "runs_file": "runs.csv"})"),
              AllOf(HasSubstr("runs.csv:3"), HasSubstr("run 'd'")));
  Write("runs.csv", "x,y\n10,60\n");
  EXPECT_THAT(LoadError(R"({"units": "si", "error": {"runout": 2}, "runs_file": "runs.csv"})"),
              AllOf(HasSubstr("runs.csv:1"), HasSubstr("'stop_x'")));
  EXPECT_THAT(LoadError(R"({"units": "si", "error": {"runout": 2}, "runs_file": "runs.csv",
        "runout": {"stop_points": [[1, 2]]}})"),
              HasSubstr("at most one of 'runout'"));
}

// Two runs from one release point to one stop point are most likely one run
// written twice: a warning names both. Another stop, or another release, is
// no copy.
TEST_F(ObservationsFileTest, ARunWrittenTwiceIsNamed) {
  scene_ = RunsScene();
  scene_.groups.push_back(scene_.groups[0]);
  scene_.groups.back().id = "a2";  // released where "a" is
  const Observations obs = LoadObservations(
      Write("obs.json", R"({"units": "si", "error": {"runout": 2}, "runs": [
        {"id": "r1", "group": "a", "stop": [10, 60]}, {"id": "r2", "group": "b", "stop": [10, 60]},
        {"id": "r3", "group": "a2", "stop": [10, 60]}, {"id": "r4", "group": "a2", "stop": [10, 61]}]})"),
      scene_);
  const std::vector<std::string> warnings = DuplicateRunWarnings(obs);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], AllOf(HasSubstr("runs 'r1' and 'r3'"), HasSubstr("(10, 60) m"),
                                 HasSubstr("counts twice")));
  EXPECT_TRUE(DuplicateRunWarnings(Observations{}).empty());
}

// Repeats: the same rocks released within 2 m of one another. Each run of
// a set of at least 3 is compared with the set's median and with the median
// of the set's other runs; other rocks, a release farther away and sets of
// fewer than 3 are left out.
TEST_F(ObservationsFileTest, RepeatedRunsGiveTheCampaignsOwnScatter) {
  scene_ = RunsScene();  // "a" at (10, 90), "b" at (50, 90): the same rocks
  core::RockGroup g = scene_.groups[0];
  for (const char* id : {"a2", "a3"}) {
    g.id = id;
    scene_.groups.push_back(g);
  }
  g.id = "a4";
  g.release.point = Eigen::Vector2d(11.5, 90);  // within 2 m of "a"
  scene_.groups.push_back(g);
  g.id = "other";  // from "a"'s point, but another rock
  g.release.point = Eigen::Vector2d(10, 90);
  g.size_max = 2.0;
  scene_.groups.push_back(g);
  const Observations obs = LoadObservations(
      Write("obs.json", R"({"units": "si", "error": {"runout": 2}, "runs": [
        {"id": "r1", "group": "a", "stop": [10, 60]}, {"id": "r2", "group": "a2", "stop": [10, 50]},
        {"id": "r3", "group": "b", "stop": [50, 10]}, {"id": "r4", "group": "a3", "stop": [10, 40]},
        {"id": "r5", "group": "a4", "stop": [11.5, 20]}, {"id": "r6", "group": "other", "stop": [10, 10]},
        {"id": "r7", "group": "b", "stop": [50, 20]}]})"),
      scene_);
  const std::optional<RepeatScatter> scatter = RunRepeatScatter(obs, scene_);
  ASSERT_TRUE(scatter);
  // The set {r1, r2, r4, r5}: runouts 30, 40, 50 and 70 m, median 45 m;
  // the other runs' medians 50, 50, 40 and 40 m. {r3, r7} is too small.
  EXPECT_EQ(scatter->sets, 1);
  EXPECT_EQ(scatter->runs, 4);
  EXPECT_DOUBLE_EQ(scatter->own_median_error_m, (15.0 + 5 + 5 + 25) / 4);
  EXPECT_DOUBLE_EQ(scatter->others_median_error_m, (20.0 + 10 + 10 + 30) / 4);
  EXPECT_THAT(scatter->Sentence(), AllOf(HasSubstr("4 runs in 1 sets"), HasSubstr("12.5 m"),
                                         HasSubstr("17.5 m")));
  // Moved 2.5 m away, r5 no longer repeats r1: its set is 3 runs.
  scene_.groups[4].release.point = Eigen::Vector2d(12.5, 90);
  const Observations moved = LoadObservations(
      Write("obs.json", R"({"units": "si", "error": {"runout": 2}, "runs": [
        {"id": "r1", "group": "a", "stop": [10, 60]}, {"id": "r2", "group": "a2", "stop": [10, 50]},
        {"id": "r4", "group": "a3", "stop": [10, 40]}, {"id": "r5", "group": "a4", "stop": [12.5, 20]}]})"),
      scene_);
  ASSERT_TRUE(RunRepeatScatter(moved, scene_));
  EXPECT_EQ(RunRepeatScatter(moved, scene_)->runs, 3);
  EXPECT_FALSE(RunRepeatScatter(Observations{}, scene_));
}

TEST_F(ObservationsFileTest, FoldsOverRunsKeepEachRunWithItsRelease) {
  scene_ = RunsScene();
  const Observations obs = LoadObservations(
      Write("obs.json", R"({"units": "si", "error": {"runout": 2}, "runs": [
        {"id": "r1", "group": "a", "stop": [10, 60]}, {"id": "r2", "group": "b", "stop": [90, 60]},
        {"id": "r3", "group": "a", "stop": [10, 40]}, {"id": "r4", "group": "b", "stop": [50, 20]}]})"),
      scene_);
  const std::vector<Fold> folds = MakeFolds(obs, 2, 3);
  std::vector<std::string> held;
  for (const Fold& f : folds) {
    const Observations test = Subset(obs, f, true), train = Subset(obs, f, false);
    ASSERT_EQ(test.runout->run_ids.size(), 2u);
    ASSERT_EQ(train.runout->run_ids.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      const auto& r = *test.runout;
      const std::size_t k = static_cast<std::size_t>(
          std::find(obs.runout->run_ids.begin(), obs.runout->run_ids.end(), r.run_ids[i]) -
          obs.runout->run_ids.begin());
      EXPECT_EQ(r.run_groups[i], obs.runout->run_groups[k]);
      EXPECT_EQ(r.distances[i], obs.runout->distances[k]);
      held.push_back(r.run_ids[i]);
    }
  }
  std::sort(held.begin(), held.end());
  EXPECT_EQ(held, (std::vector<std::string>{"r1", "r2", "r3", "r4"}));
}

// The bundled Tschamut 2014 example: each of its 62 runs is measured from
// its own rock group's release, and that distance is the campaign's own
// runout_m (runs.csv, horizontal distance from release to stop; the site
// gives the release points to the millimetre).
TEST(TschamutExample, EachRunIsMeasuredFromItsOwnRelease) {
  const std::string dir = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tschamut/";
  const sites::Site site = sites::LoadSite(dir + "site.json");
  EXPECT_TRUE(sites::IdenticalCopyWarnings(site.scene).empty());
  const Observations obs = LoadObservations(dir + "observations.json", site.scene);
  ASSERT_TRUE(obs.runout && obs.runout->has_runs());
  const Runout& r = *obs.runout;
  ASSERT_EQ(r.run_ids.size(), 62u);
  // The campaign's table holds one run twice under two ids.
  const std::vector<std::string> copies = DuplicateRunWarnings(obs);
  ASSERT_EQ(copies.size(), 1u);
  EXPECT_THAT(copies[0], HasSubstr("runs 'v033' and 'v034'"));
  // Its repeats (the same block from one point, within 2 m): 48 runs in
  // 12 sets, which scatter by 10-15 m about their medians.
  const std::optional<RepeatScatter> scatter = RunRepeatScatter(obs, site.scene);
  ASSERT_TRUE(scatter);
  EXPECT_EQ(scatter->sets, 12);
  EXPECT_EQ(scatter->runs, 48);
  EXPECT_NEAR(scatter->own_median_error_m, 10.8, 0.05);
  EXPECT_NEAR(scatter->others_median_error_m, 14.4, 0.05);
  std::ifstream csv(dir + "data/runs.csv");
  std::string line;
  std::getline(csv, line);  // header; runout_m is the last column
  for (std::size_t i = 0; std::getline(csv, line); ++i) {
    ASSERT_LT(i, r.run_ids.size());
    EXPECT_EQ(line.substr(0, line.find(',')), r.run_ids[i]);
    EXPECT_EQ(site.scene.groups[static_cast<std::size_t>(r.run_groups[i])].id, r.run_ids[i]);
    const double runout_m = std::stod(line.substr(line.rfind(',') + 1));
    EXPECT_NEAR(r.distances[i], runout_m, 1e-3) << r.run_ids[i];
  }
}

TEST(Folds, TooFewValuesOrFoldsAreRefused) {
  const Observations obs = FoldFixture();
  EXPECT_THROW(MakeFolds(obs, 1, 1), InputError);
  try {
    MakeFolds(obs, 8, 1);  // the first tree set has 7 heights
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("tree_scars[1] trees"));
    EXPECT_THAT(e.what(), HasSubstr("fewer than the 8 folds"));
  }
}

}  // namespace
}  // namespace rockcal::observations
