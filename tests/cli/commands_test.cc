// rockcal simulate / validate end to end, as a user runs them.
#include <gtest/gtest.h>
#include <gmock/gmock.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "cli_fixture.h"

#include "rockcal/core/simulate.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {
namespace commands_test {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::Example;
using testing::FreshDir;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void ExpectStats(const nlohmann::json& s, const std::string& what) {
  for (const char* k : {"mean", "p50", "p90", "p95", "max"}) {
    ASSERT_TRUE(s.contains(k) && s[k].is_number()) << what << " lacks " << k;
    EXPECT_TRUE(std::isfinite(s[k].get<double>())) << what << "." << k;
  }
  EXPECT_EQ(s.size(), 5u) << what;
}

// The summary.json schema of docs/reference/outputs.md, key for key.
void ExpectSummarySchema(const nlohmann::json& j, int rocks) {
  const char* keys[] = {"site", "rocks", "seed", "wall_seconds", "steps", "dt_seconds",
                        "outcomes", "partitions", "runout", "energy_check"};
  EXPECT_EQ(j.size(), std::size(keys));
  for (const char* k : keys) ASSERT_TRUE(j.contains(k)) << "summary lacks " << k;
  EXPECT_EQ(j["rocks"].get<int>(), rocks);
  const auto& o = j["outcomes"];
  EXPECT_EQ(o["stopped"].get<int>() + o["left"].get<int>() + o["timeout"].get<int>(), rocks);
  for (const auto& p : j["partitions"]) {
    EXPECT_TRUE(p["id"].is_string());
    EXPECT_TRUE(p["passed"].is_number_integer());
    ExpectStats(p["height_m"], "height_m");
    ExpectStats(p["velocity_mps"], "velocity_mps");
    ExpectStats(p["energy_kj"], "energy_kj");
  }
  ExpectStats(j["runout"]["x_m"], "runout.x_m");
  EXPECT_LT(j["energy_check"]["max_relative_gain"].get<double>(), 1e-3);
  EXPECT_GT(j["dt_seconds"].get<double>(), 0.0);
}

class ExampleTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ExampleTest, SimulateWritesSummaryAndRocks) {
  const std::string out = FreshDir(GetParam());
  const RunResult run = Rockcal("simulate " + Example(GetParam()) + " --rocks 6 --seed 3 --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  ExpectSummarySchema(ReadJson(out + "/summary.json"), 6);
  std::ifstream rocks(out + "/rocks.csv");
  std::string header, line;
  std::getline(rocks, header);
  EXPECT_THAT(header, HasSubstr("rock,group,shape,size_m,mass_kg,outcome,stop_x,stop_y,stop_z"));
  int rows = 0;
  while (std::getline(rocks, line)) ++rows;
  EXPECT_EQ(rows, 6);
  EXPECT_FALSE(fs::exists(out + "/trajectories.csv"));
}

INSTANTIATE_TEST_SUITE_P(Examples, ExampleTest, ::testing::Values("tutorial", "profile2d", "authume",
                                                             "authume_gis"));

TEST(Simulate, AuthumeStopPointsLieOnTheTerrain) {
  const std::string out = FreshDir("authume_stops");
  ASSERT_EQ(Rockcal("simulate " + Example("authume") + " --rocks 8 --quiet --out " + out).status, 0);
  const sites::Site site = sites::LoadSite(Example("authume"));
  const core::Terrain terrain = core::BuildTerrain(site.scene);
  std::ifstream rocks(out + "/rocks.csv");
  std::string line;
  std::getline(rocks, line);
  int stopped = 0;
  while (std::getline(rocks, line)) {
    std::stringstream s(line);
    std::vector<std::string> f;
    for (std::string cell; std::getline(s, cell, ',');) f.push_back(cell);
    if (f[5] != "stopped") continue;
    ++stopped;
    EXPECT_TRUE(terrain.OnSlope(std::stod(f[6]), std::stod(f[7]))) << line;
  }
  EXPECT_GT(stopped, 0);
}

TEST(Simulate, TrajectoriesWhenAsked) {
  const std::string out = FreshDir("traj");
  ASSERT_EQ(Rockcal("simulate " + Example("profile2d") +
                    " --rocks 3 --trajectories 2 --sample-seconds 0.1 --quiet --out " + out)
                .status,
            0);
  std::ifstream in(out + "/trajectories.csv");
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "rock,t,x,y,z,vx,vy,vz,wx,wy,wz");
  std::set<std::string> rocks;
  while (std::getline(in, line)) rocks.insert(line.substr(0, line.find(',')));
  EXPECT_EQ(rocks, (std::set<std::string>{"0", "1"}));
}

TEST(Simulate, ExistingOutputIsKeptWithoutForce) {
  const std::string out = FreshDir("keep");
  fs::create_directories(out);
  std::ofstream(out + "/mine.txt") << "precious";
  const RunResult run = Rockcal("simulate " + Example("profile2d") + " --rocks 2 --quiet --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--force"));
  EXPECT_TRUE(fs::exists(out + "/mine.txt"));
  // --force replaces only a folder rockcal wrote (one with the marker).
  fs::remove_all(out);
  EXPECT_EQ(Rockcal("simulate " + Example("profile2d") + " --rocks 2 --quiet --out " + out).status,
            0);
  EXPECT_TRUE(fs::exists(out + "/.rockcal-output"));
  std::ofstream(out + "/mine.txt") << "stale";
  EXPECT_EQ(Rockcal("simulate " + Example("profile2d") + " --rocks 2 --quiet --force --out " + out).status, 0);
  EXPECT_FALSE(fs::exists(out + "/mine.txt"));
  EXPECT_TRUE(fs::exists(out + "/summary.json"));
}

// Issue 14: --force deleted the site file and everything beside it.
TEST(Simulate, ForceNeverReplacesAFolderRockcalDidNotWriteOrOneHoldingAnInput) {
  const std::string proj = FreshDir("proj");
  fs::create_directories(proj);
  const std::string src = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/profile2d";
  fs::copy(src, proj, fs::copy_options::recursive);
  std::ofstream(proj + "/notes.txt") << "precious";
  RunResult run =
      Rockcal("simulate " + proj + "/site.json --rocks 2 --quiet --force --out " + proj);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("an input of this run"));
  EXPECT_TRUE(fs::exists(proj + "/site.json"));
  EXPECT_EQ(ReadFile(proj + "/notes.txt"), "precious");
  // The same through another spelling of the folder.
  run = Rockcal("simulate " + proj + "/site.json --rocks 2 --quiet --force --out " + proj + "/../" +
                fs::path(proj).filename().string() + "/");
  EXPECT_EQ(run.status, 2);
  EXPECT_TRUE(fs::exists(proj + "/site.json"));
  // Even marked as rockcal's, a folder holding an input is not replaced.
  std::ofstream(proj + "/.rockcal-output") << "{}";
  run = Rockcal("simulate " + proj + "/site.json --rocks 2 --quiet --force --out " + proj);
  EXPECT_EQ(run.status, 2);
  EXPECT_TRUE(fs::exists(proj + "/site.json"));
  // A folder without the marker is refused too, naming why.
  const std::string other = FreshDir("other");
  fs::create_directories(other);
  std::ofstream(other + "/mine.txt") << "precious";
  run = Rockcal("simulate " + proj + "/site.json --rocks 2 --quiet --force --out " + other);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("holds no .rockcal-output"));
  EXPECT_EQ(ReadFile(other + "/mine.txt"), "precious");
}

TEST(Simulate, EmptyOutIsRefusedBeforeAnyWork) {
  const RunResult run = Rockcal("simulate " + Example("profile2d") + " --rocks 100000 --out \"\"");
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--out"));
  EXPECT_THAT(run.err, HasSubstr("is empty"));
}

TEST(Simulate, BadInputExitsTwoAndLeavesNothing) {
  const std::string out = FreshDir("bad");
  const std::string site = ::testing::TempDir() + "/rockcal_bad_site.json";
  std::ofstream(site) << R"({"name": "x", "units": "si", "surface": {"points": [[0,0,0]]}})";
  RunResult run = Rockcal("simulate " + site + " --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(site));
  EXPECT_FALSE(fs::exists(out));
  run = Rockcal("simulate " + Example("profile2d") + " --set material.nope.hardness=0.3 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("nope"));
  run = Rockcal("simulate " + Example("profile2d") + " --rocks zero --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--rocks"));
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(::testing::TempDir()))
    EXPECT_EQ(e.path().filename().string().find("rockcal_cli_bad.tmp"), std::string::npos);
}

// The tutorial with two barriers across the slope (site file in feet): a
// fence at x = 200 ft that records, and a dam at x = 400 ft that stops the
// rocks it catches. The tutorial's points file by its full path.
nlohmann::json TutorialWithBarriers() {
  std::ifstream in(Example("tutorial"));
  nlohmann::json site = nlohmann::json::parse(in);
  site["surface"]["points_file"] = fs::path(Example("tutorial")).parent_path() / "points.csv";
  site["barriers"] = nlohmann::json::parse(R"([
    {"id": "fence", "line": [[200, -10], [205, 100], [200, 210]], "height": 10, "energy_kj": 500},
    {"id": "dam", "line": [[400, -10], [400, 210]], "height": 30, "energy_kj": 100000, "stops": true}
  ])");
  return site;
}

// barriers.csv end to end: one row per barrier in the site's units, its
// counts those of summary.json and rocks.csv (the rocks the dam stopped end
// "stopped" on its line, at x = 400 ft).
TEST(Simulate, WritesBarriersCsvOfTheBarriersLines) {
  const std::string site = ::testing::TempDir() + "/rockcal_barriers_site.json";
  std::ofstream(site) << TutorialWithBarriers().dump(2);
  const std::string out = FreshDir("barriers");
  const RunResult run = Rockcal("simulate " + site + " --rocks 24 --seed 3 --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  std::ifstream csv(out + "/barriers.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "id,height_ft,capacity_kj,stops,reaching,passing_over,centre_above,exceeding_capacity,"
            "stopped,lowest_point_p95_ft,lowest_point_p99_ft,centre_p95_ft,centre_p99_ft,"
            "energy_p95_kj,energy_p99_kj");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::stringstream s(line);
    rows.emplace_back();
    for (std::string cell; std::getline(s, cell, ',');) rows.back().push_back(cell);
  }
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][0], "fence");
  EXPECT_EQ(rows[0][1], "10");
  EXPECT_EQ(rows[0][3], "false");
  EXPECT_EQ(rows[1][0], "dam");
  EXPECT_EQ(rows[1][3], "true");
  const nlohmann::json summary = ReadJson(out + "/summary.json");
  ASSERT_EQ(summary["barriers"].size(), 2u);
  for (std::size_t b = 0; b < 2; ++b) {
    const nlohmann::json& j = summary["barriers"][b];
    EXPECT_EQ(j["id"], rows[b][0]);
    EXPECT_EQ(std::to_string(j["reaching"].get<int>()), rows[b][4]);
    EXPECT_EQ(std::to_string(j["stopped"].get<int>()), rows[b][8]);
    // The partitions' record of the same line: partitions BP-1, BP-2, then the barriers.
    EXPECT_EQ(j["reaching"], summary["partitions"][2 + b]["passed"]);
    if (j["reaching"].get<int>() > 0) {  // site units: feet in the CSV, metres in the JSON
      EXPECT_NEAR(std::stod(rows[b][11]) * 0.3048, j["centre_m"]["p95"].get<double>(),
                  1e-6 * (1.0 + j["centre_m"]["p95"].get<double>()));
    }
  }
  EXPECT_DOUBLE_EQ(summary["barriers"][0]["height_m"].get<double>(), 10 * 0.3048);
  const int stopped = summary["barriers"][1]["stopped"].get<int>();
  ASSERT_GT(stopped, 0) << "no rock reached the dam: the test checks nothing";
  std::ifstream rocks(out + "/rocks.csv");
  std::getline(rocks, line);
  int on_dam = 0;
  while (std::getline(rocks, line)) {
    std::stringstream s(line);
    std::vector<std::string> f;
    for (std::string cell; std::getline(s, cell, ',');) f.push_back(cell);
    if (f[5] == "stopped" && std::fabs(std::stod(f[6]) - 400 * 0.3048) < 1e-6) ++on_dam;
  }
  EXPECT_EQ(on_dam, stopped);
  const std::string report = ReadFile(out + "/report.html");
  EXPECT_THAT(report, HasSubstr("<section id=\"barriers\">"));
  EXPECT_THAT(report, HasSubstr("barrier</li>"));  // the plan view's legend
}

// A bad barrier exits 2 naming the site file and the JSON path, writing nothing.
TEST(Simulate, ABadBarrierExitsTwoNamingTheJsonPath) {
  nlohmann::json json = TutorialWithBarriers();
  json["barriers"][1]["line"] = nlohmann::json::parse("[[400, 10]]");
  const std::string site = ::testing::TempDir() + "/rockcal_bad_barrier_site.json";
  std::ofstream(site) << json.dump(2);
  const std::string out = FreshDir("bad_barrier");
  RunResult run = Rockcal("simulate " + site + " --rocks 2 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(site + ": $.barriers[1].line: expected a line: an array of at "
                                        "least 2 [x, y] vertices"));
  EXPECT_FALSE(fs::exists(out));
  json = TutorialWithBarriers();
  json["barriers"][0]["height"] = -2;
  std::ofstream(site) << json.dump(2);
  run = Rockcal("simulate " + site + " --rocks 2 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("$.barriers[0].height: expected a number > 0"));
  EXPECT_FALSE(fs::exists(out));
  json = TutorialWithBarriers();  // a vertex beyond any double, in the file's text
  json["barriers"][1]["line"][0][0] = 123456789;
  std::string text = json.dump(2);
  text.replace(text.find("123456789"), 9, "1e999");
  std::ofstream(site) << text;
  run = Rockcal("simulate " + site + " --rocks 2 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("$.barriers[1].line[0][0]: number '1e999' out of range"));
  EXPECT_FALSE(fs::exists(out));
}

// #52: --compare-bare runs the same rocks without the forest; the report's
// Forest section sets the bare runout beside the forest's, the forest's own
// run is unchanged, and the bare run is the one --no-forest makes.
TEST(Simulate, CompareBareGivesTheRunoutWithAndWithoutTheForest) {
  const std::string site = testing::ForestedTutorial();
  ASSERT_FALSE(site.empty());
  const std::string both = FreshDir("both"), bare = FreshDir("bare"), forest = FreshDir("forest");
  const std::string run = "simulate " + site + " --rocks 40 --seed 3 ";
  RunResult r = Rockcal(run + "--compare-bare --out " + both);
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_EQ(Rockcal(run + "--no-forest --quiet --out " + bare).status, 0);
  ASSERT_EQ(Rockcal(run + "--quiet --out " + forest).status, 0);
  const nlohmann::json with = nlohmann::json::parse(ReadFile(both + "/summary.json"));
  const nlohmann::json alone = nlohmann::json::parse(ReadFile(forest + "/summary.json"));
  const nlohmann::json without = nlohmann::json::parse(ReadFile(bare + "/summary.json"));
  EXPECT_EQ(with["runout"], alone["runout"]) << "the comparison leaves the forest's run alone";
  EXPECT_EQ(with["forest"], alone["forest"]);
  EXPECT_GT(with["forest"]["strikes"].get<int>(), 0) << with["forest"].dump();
  EXPECT_NE(with["runout"], without["runout"]) << "600 stems/ha change nothing?";
  // The console's figure is the --no-forest run's 90 % runout.
  const auto p90 = [](const nlohmann::json& s) {
    const nlohmann::json& v = s["runout"]["distance_m"]["p90"];
    if (!v.is_number()) return std::string("beyond the edge");
    char text[32];
    std::snprintf(text, sizeof text, "%.4g m", v.get<double>());
    return std::string(text);
  };
  EXPECT_THAT(
      r.out,
      HasSubstr("without the forest (--compare-bare, report.html's Forest section): " +
                std::to_string(without["outcomes"]["stopped"].get<int>()) + " stopped, " +
                std::to_string(without["outcomes"]["left"].get<int>()) + " left; runout 90 % " +
                p90(without) + " (with the forest " + p90(with) + ")"));
  // The report's table: rocks stopped with the forest, then bare.
  const std::string report = ReadFile(both + "/report.html");
  EXPECT_THAT(report, HasSubstr("Runout with and without the forest"));
  EXPECT_THAT(report,
              HasSubstr("<td>rocks stopped</td><td class=\"n\">" +
                        std::to_string(with["outcomes"]["stopped"].get<int>()) +
                        " of 40</td><td class=\"n\">" +
                        std::to_string(without["outcomes"]["stopped"].get<int>()) + " of 40</td>"));
  EXPECT_THAT(ReadFile(forest + "/report.html"),
              ::testing::Not(HasSubstr("Runout with and without")));
}

TEST(Simulate, CompareBareNeedsAForest) {
  const std::string out = FreshDir("out");
  RunResult r = Rockcal("simulate " + Example("tutorial") + " --compare-bare --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("argument --compare-bare: the site has no 'forest'"));
  r = Rockcal("simulate " + testing::ForestedTutorial() + " --compare-bare --no-forest --out " +
              out);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("--no-forest leaves the forest out"));
  EXPECT_FALSE(fs::exists(out));
}

// #52: the same stems give the same run whichever way the site gives them:
// a stand's drawn stems (trees.csv, written at full precision) read back as
// a trees_file, and the same stems given inline.
TEST(Simulate, TheSameStemsGiveTheSameRunFromAStandATreeFileOrInline) {
  const std::string dir = FreshDir("sites");
  fs::create_directories(dir);
  nlohmann::json site = nlohmann::json::parse(R"({
    "name": "forest plane", "units": "si",
    "surface": {"resolution": 2, "sphere_spacing": 2,
                "points": [[0, 0, 50], [100, 0, 0], [0, 60, 50], [100, 60, 0]]},
    "materials": [{"id": "soil", "hardness": 0.3, "roughness": 0.2}],
    "rocks": [{"count": 30, "shape": "sphere", "size": [0.5, 1], "unit_weight": 26,
               "release": {"zone": [[2, 20], [8, 20], [8, 40], [2, 40]]}}],
    "simulation": {"seed": 3, "max_time": 20}
  })");
  const auto run = [&](const std::string& name, const nlohmann::json& forest) {
    nlohmann::json s = site;
    s["forest"] = forest;
    std::ofstream(dir + "/" + name + ".json") << s.dump(2);
    const std::string out = FreshDir(name);
    const RunResult r =
        Rockcal("simulate " + dir + "/" + name + ".json --threads 2 --quiet --out " + out);
    EXPECT_EQ(r.status, 0) << name << ": " << r.err;
    return out;
  };
  const std::string stand = run("stand", {{"stands",
                                           {{{"zone", {{20, 2}, {98, 2}, {98, 58}, {20, 58}}},
                                             {"stems_per_ha", 600},
                                             {"dbh_mean_cm", 30},
                                             {"dbh_sd_cm", 10},
                                             {"conifer_percent", 40}}}}});
  const std::string trees_csv = ReadFile(stand + "/trees.csv");
  std::ofstream(dir + "/trees.csv") << trees_csv;
  const std::string file = run("file", {{"trees_file", "trees.csv"}});
  // The same rows as inline trees.
  nlohmann::json inline_trees = nlohmann::json::array();
  std::istringstream rows(trees_csv);
  std::string row;
  std::getline(rows, row);
  ASSERT_EQ(row, "x,y,dbh_cm,species,height");
  while (std::getline(rows, row)) {
    std::vector<std::string> f;
    std::stringstream fields(row);
    for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
    ASSERT_EQ(f.size(), 5u) << row;
    inline_trees.push_back({{"x", std::stod(f[0])},
                            {"y", std::stod(f[1])},
                            {"dbh_cm", std::stod(f[2])},
                            {"species", f[3]},
                            {"height", std::stod(f[4])}});
  }
  ASSERT_GT(inline_trees.size(), 100u) << "600 stems/ha on 0.44 ha";
  const std::string inline_run = run("inline", {{"trees", inline_trees}});
  const auto summary = [](const std::string& out) {
    nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/summary.json"));
    j.erase("wall_seconds");
    return j;
  };
  const nlohmann::json want = summary(stand);
  EXPECT_GT(want["forest"]["strikes"].get<int>(), 0) << want["forest"].dump();
  EXPECT_EQ(summary(file), want);
  EXPECT_EQ(summary(inline_run), want);
  const std::string impacts = ReadFile(stand + "/tree_impacts.csv");
  EXPECT_EQ(ReadFile(file + "/tree_impacts.csv"), impacts);
  EXPECT_EQ(ReadFile(inline_run + "/tree_impacts.csv"), impacts);
  EXPECT_FALSE(fs::exists(file + "/trees.csv")) << "no stems drawn";
}

TEST(Validate, PrintsWhatItFound) {
  EXPECT_EQ(Rockcal("validate " + Example("tutorial")).status, 0);
  EXPECT_EQ(Rockcal("validate /nonexistent/site.json").status, 2);
}

// Issue 55: an imperial site is printed in its own units (feet, pounds),
// and the calibration bounds carry units.
TEST(Validate, PrintsAnImperialSiteInItsUnits) {
  const RunResult r = Rockcal("validate " + Example("tutorial"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("calibrate: talus.hardness [0.1, 0.7], talus.roughness [0.5, 6] ft, "
                               "soil.hardness [0.05, 0.5], soil.roughness [0.15, 4] ft"));
  EXPECT_THAT(r.out, HasSubstr("  BP-1       x = 300 ft\n"));
  EXPECT_THAT(r.out, HasSubstr("roughness 2 ft (sphere r "));
  EXPECT_THAT(r.out, HasSubstr("sphere      size 1 ft to 4 ft  mass "));
  EXPECT_THAT(r.out, HasSubstr(" lb  contact step"));
  EXPECT_THAT(r.out, HasSubstr("grid: 51 x 17 nodes at 12 ft spacing"));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr(" m ")));
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr(" kg")));
}

// Issue 55: without --out, a new folder named after the site and the
// command, in the working directory, never one that exists; the command
// says which.
TEST(Simulate, WithoutOutWritesANewFolderNamedAfterTheSite) {
  const std::string dir = FreshDir("cwd");
  fs::create_directories(dir);
  const std::string run = "cd " + dir + " && " + std::string(ROCKCAL_EXE) + " simulate " +
                          Example("tutorial") + " --rocks 2";
  RunResult r = testing::Run(run);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("output folder: tutorial-simulate (no --out given)"));
  EXPECT_THAT(r.out, HasSubstr("wrote tutorial-simulate/summary.json"));
  EXPECT_TRUE(fs::exists(dir + "/tutorial-simulate/summary.json"));
  const std::string first = ReadFile(dir + "/tutorial-simulate/rocks.csv");
  r = testing::Run(run + " --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "output folder: tutorial-simulate-2 (no --out given)\n");
  EXPECT_TRUE(fs::exists(dir + "/tutorial-simulate-2/summary.json"));
  EXPECT_EQ(ReadFile(dir + "/tutorial-simulate/rocks.csv"), first) << "the first run untouched";
  fs::create_directories(dir + "/tutorial-simulate-3");  // not rockcal's: skipped too
  r = testing::Run(run + " --quiet");
  EXPECT_EQ(r.out, "output folder: tutorial-simulate-4 (no --out given)\n");
  // A file not called site.json is named by its stem; --resume needs --out.
  fs::copy_file(Example("profile2d"), dir + "/my-slope.json");
  r = testing::Run("cd " + dir + " && " + std::string(ROCKCAL_EXE) +
                   " study stability my-slope.json --rocks 1 --cases site --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/my-slope-stability/stability.json"));
  r = testing::Run("cd " + dir + " && " + std::string(ROCKCAL_EXE) + " calibrate " +
                   Example("tutorial") + " --observations " + std::string(ROCKCAL_SOURCE_DIR) +
                   "/sites/examples/tutorial/observations.json --resume");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("argument --resume: continues the calibration in the folder --out "
                               "names; expected --out DIR"));
}

// --write-impacts: the impacts found in the observations' tracks, as an
// impacts file. Two hops of run v004 of the Tschamut example, off its grid
// (no ground: the track alone decides), one impact at t = 1 s.
TEST(Validate, WritesTheTracksImpacts) {
  const std::string dir = FreshDir("tracks");
  fs::create_directories(dir);
  {
    std::ofstream tracks(dir + "/tracks.csv");
    tracks << "run,t,x,y,z\n";
    for (int k = 0; k <= 40; ++k) {
      const double t = 0.05 * k, tau = t < 1.0 ? t : t - 1.0;
      tracks << "v004," << t << "," << -500 + 5 * t << ",0," << 4.9 * tau - 4.903325 * tau * tau
             << "\n";
    }
    std::ofstream obs(dir + "/obs.json");
    obs << R"({"units": "si", "runs_file": ")" << ROCKCAL_SOURCE_DIR
        << R"(/sites/examples/tschamut/data/runs.csv", "tracks_file": "tracks.csv",
          "error": {"runout": 2, "track": 0.02, "impact_speed": 0.5}})";
  }
  const std::string site = Example("tschamut"), impacts = dir + "/impacts.csv";
  RunResult run = Rockcal("validate " + site + " --observations " + dir +
                          "/obs.json --write-impacts " + impacts);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("2 flights and 1 impacts found"));
  const std::string csv = testing::ReadFile(impacts);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out");
  EXPECT_THAT(csv, HasSubstr("\nv004-1,v004,-495.00"));
  // Without tracks, or without observations: exit 2, nothing written.
  run = Rockcal("validate " + site + " --observations " + std::string(ROCKCAL_SOURCE_DIR) +
                "/sites/examples/tschamut/observations.json --write-impacts " + dir + "/none.csv");
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("no 'tracks_file'"));
  run = Rockcal("validate " + site + " --write-impacts " + dir + "/none.csv");
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("expected --observations"));
  EXPECT_FALSE(fs::exists(dir + "/none.csv"));
}

}  // namespace commands_test
}  // namespace rockcal::cli
