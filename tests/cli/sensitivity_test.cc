// rockcal sensitivity end to end, as a user runs it: the files it writes,
// what it prints, and bad input (exit 2, nothing written).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::Example;
using testing::FreshDir;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

// profile2d with only the talus hardness calibrated (the terrain is built
// once per study) and 15 s per rock: quick under the sanitizers.
std::string HardnessOnlySite() {
  const std::string site = ::testing::TempDir() + "/rockcal_sensitivity_hardness_only.json";
  nlohmann::json j = nlohmann::json::parse(ReadFile(Example("profile2d")));
  for (auto& m : j["materials"])
    if (m.contains("calibrate")) m["calibrate"].erase("roughness");
  j["simulation"]["max_time"] = 15;  // down the 100 m profile; bounds the cost of a rock
  std::ofstream(site) << j.dump();
  return site;
}

TEST(Sensitivity, MorrisWritesTablesAndReport) {
  const std::string out = FreshDir("morris");
  const RunResult run = Rockcal("sensitivity " + Example("profile2d") +
                                " --samples 2 --rocks 2 --threads 2 --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out,
              HasSubstr("wrote " + out + "/sensitivity.json, sensitivity.csv, report.html"));
  const nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/sensitivity.json"));
  EXPECT_EQ(j["method"], "morris");
  EXPECT_EQ(j["simulations"], 2 * 3 + 1);  // r (k + 1) + the current parameters
  EXPECT_EQ(j["parameters"].size(), 2u);   // talus hardness and roughness
  const std::size_t outputs = j["outputs"].size();
  EXPECT_EQ(outputs, 3u + 3u);  // P-talus: height p50, p90, passing; runout p50, p90; stopped
  EXPECT_EQ(j["entries"].size(), 2 * outputs);
  const std::string csv = ReadFile(out + "/sensitivity.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), 1 + 2 * outputs);
  EXPECT_THAT(csv, HasSubstr("morris,talus.hardness,P-talus.height.p50,m,"));
  const std::string html = ReadFile(out + "/report.html");
  EXPECT_THAT(html, HasSubstr("<section id=\"sensitivity\">"));
  EXPECT_THAT(html, HasSubstr("data-json=\"sensitivity.json#/entries/0/mu_star\""));
}

TEST(Sensitivity, SobolWithObservationsHasTheMisfit) {
  const std::string out = FreshDir("sobol");
  const std::string obs = ::testing::TempDir() + "/rockcal_sensitivity_profile2d_obs.json";
  std::ofstream(obs) << R"({"units": "si",
    "tree_scars": [{"partition": "P-talus", "heights": [0.5, 1.0, 1.5, 2.2]}],
    "runout": {"distances": [40, 55, 60, 70], "from": [4, 0.5], "direction": [1, 0]},
    "error": {"height": 0.1, "runout": 2.0}})";
  // One bound, few rocks: N (k + 2) + 1 = 4 * 3 + 1 runs.
  const RunResult run = Rockcal("sensitivity " + HardnessOnlySite() +
                                " --method sobol --samples 4 --rocks 3 --observations " + obs +
                                " --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("sobol, N = 4: 13 simulations of 3 rocks"));
  const nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/sensitivity.json"));
  EXPECT_EQ(j["outputs"].back()["name"], "misfit");
  EXPECT_THAT(j["outputs"][3]["description"].get<std::string>(),
              HasSubstr("along the observed runout direction"));
  EXPECT_TRUE(j["entries"][0].contains("total_high"));
}

TEST(Sensitivity, BadInputExitsTwoAndNamesTheProblem) {
  const std::string out = FreshDir("bad");
  RunResult run = Rockcal("sensitivity " + Example("profile2d") + " --method fast --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("unknown method 'fast' (allowed: morris, sobol)"));
  run = Rockcal("sensitivity " + Example("profile2d") + " --samples 1 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--samples: '1' is not a whole number in [2, 100000]"));
  run = Rockcal("sensitivity " + Example("profile2d") + " --method sobol --samples 3 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("in [4, 100000]"));
  run = Rockcal("sensitivity " + Example("profile2d") + " --samples x --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("'x'"));
  EXPECT_FALSE(fs::exists(out));

  // A site without calibrate bounds.
  const std::string site = ::testing::TempDir() + "/rockcal_sensitivity_no_bounds.json";
  nlohmann::json j = nlohmann::json::parse(ReadFile(Example("profile2d")));
  for (auto& m : j["materials"]) m.erase("calibrate");
  std::ofstream(site) << j.dump();
  run = Rockcal("sensitivity " + site + " --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(site + ": no \"calibrate\" bounds"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(Sensitivity, AnExistingFolderIsNotOverwritten) {
  const std::string out = FreshDir("exists");
  fs::create_directories(out);
  std::ofstream(out + "/keep.txt") << "mine";
  const std::string args =
      "sensitivity " + HardnessOnlySite() + " --samples 2 --rocks 2 --quiet --out " + out;
  RunResult run = Rockcal(args);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--force"));
  EXPECT_EQ(ReadFile(out + "/keep.txt"), "mine");
  EXPECT_FALSE(fs::exists(out + "/sensitivity.json"));
  // Nor with --force: rockcal did not write it.
  run = Rockcal(args + " --force");
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(".rockcal-output"));
  EXPECT_EQ(ReadFile(out + "/keep.txt"), "mine");
  fs::remove_all(out);
  ASSERT_EQ(Rockcal(args).status, 0);
  std::ofstream(out + "/keep.txt") << "stale";
  run = Rockcal(args + " --force");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::exists(out + "/sensitivity.json"));
  EXPECT_FALSE(fs::exists(out + "/keep.txt"));
}

}  // namespace
}  // namespace rockcal::cli
