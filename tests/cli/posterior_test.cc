// rockcal calibrate --posterior end to end on the tutorial site (4 values):
// the files and keys it adds (with the predictive bands of every
// partition), a resume that replays the posterior stage, and its options'
// errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

std::string Args(const std::string& out, const std::string& extra) {
  const std::string site = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  return "calibrate " + site + "/site.json --observations " + site +
         "/observations.json --rocks 8 --reach 0 --seed 2 --max-evals 6 --quiet --posterior "
         "--posterior-points 12 --posterior-rounds 1 --predictive 3 --out " + out + " " + extra;
}

// rockcal simulate --parameters of the calibration `cal` (with a posterior)
// draws from it; rockcal table shows its intervals.
void SimulateDrawsFromItAndTableShowsItsIntervals(const std::string& cal) {
  RunResult r;
  const std::string site = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/site.json";
  const std::string simulate = "simulate " + site + " --parameters " + cal + " --rocks 12 --quiet ";
  const std::string one = FreshDir("draws_one"), two = FreshDir("draws_two");
  r = Rockcal(simulate + "--draws 4 --rasters --threads 1 --out " + one);
  ASSERT_EQ(r.status, 0) << r.err;
  r = Rockcal(simulate + "--draws 4 --rasters --threads 2 --out " + two);
  ASSERT_EQ(r.status, 0) << r.err;
  // The seed fixes the draws and the rocks at any thread count.
  EXPECT_EQ(ReadFile(one + "/rocks.csv"), ReadFile(two + "/rocks.csv"));
  EXPECT_EQ(ReadFile(one + "/draws.csv"), ReadFile(two + "/draws.csv"));
  std::ifstream in(one + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  const nlohmann::json& used = summary["parameters"];
  EXPECT_EQ(used["use"], "posterior draws") << used.dump();
  EXPECT_EQ(used["draws"].get<int>(), 4);
  EXPECT_EQ(used["samples"].get<int>(), 4000);
  EXPECT_EQ(used["rocks_per_draw"]["min"].get<int>(), 3);
  const nlohmann::json& p90 = used["bands"]["runout"]["x_m"]["p90"];
  EXPECT_LE(p90["p05"].get<double>(), p90["median"].get<double>()) << p90.dump();
  EXPECT_LE(p90["median"].get<double>(), p90["p95"].get<double>()) << p90.dump();
  ASSERT_FALSE(used["bands"]["partitions"].empty());
  EXPECT_TRUE(used["bands"]["partitions"][0].contains("energy_kj")) << used.dump();
  // draws.csv: a header and one line per draw, each with its rocks.
  std::istringstream draws(ReadFile(one + "/draws.csv"));
  std::string line;
  std::getline(draws, line);
  EXPECT_EQ(line, "draw,sample,rocks,talus.hardness,talus.roughness,soil.hardness,soil.roughness");
  int lines = 0;
  while (std::getline(draws, line)) ++lines;
  EXPECT_EQ(lines, 4);
  EXPECT_TRUE(std::filesystem::exists(one + "/rasters/reach_probability_q95.asc"));
  EXPECT_TRUE(std::filesystem::exists(one + "/rasters/energy_p95_q05.asc"));
  EXPECT_THAT(ReadFile(one + "/report.html"), HasSubstr("id=\"posterior-draws\""));

  // --point-values: the calibrated values only, and the summary says so.
  const std::string point = FreshDir("draws_point");
  r = Rockcal(simulate + "--point-values --out " + point);
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream pin(point + "/summary.json");
  EXPECT_EQ(nlohmann::json::parse(pin)["parameters"]["use"], "point values");
  EXPECT_FALSE(std::filesystem::exists(point + "/draws.csv"));
  // More draws than rocks, or --draws with the point values: exit 2, named.
  r = Rockcal(simulate + "--draws 13 --out " + FreshDir("draws_many"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("argument --draws: 13 draws for 12 rocks"));
  r = Rockcal(simulate + "--draws 3 --point-values --out " + FreshDir("draws_point2"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("argument --draws"));

  // rockcal table: the posterior columns and intervals.
  const std::string table = FreshDir("draws_table");
  r = Rockcal("table " + cal + " --quiet --out " + table);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(ReadFile(table + "/table.csv"), HasSubstr(",posterior_p05,posterior_p95\n"));
  EXPECT_THAT(ReadFile(table + "/values.csv"),
              HasSubstr(",posterior_median,posterior_p05,posterior_p95,determined\n"));
  EXPECT_THAT(ReadFile(table + "/table.md"), HasSubstr("posterior 5 % – 95 %"));
}

TEST(CalibratePosterior, WritesTheIntervalsSamplesAndBandsResumesAndSimulateDrawsFromIt) {
  const std::string out = FreshDir("posterior");
  RunResult r = Rockcal(Args(out, ""));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(out + "/parameters.json");
  const nlohmann::json params = nlohmann::json::parse(in);
  ASSERT_EQ(params["parameters"].size(), 4u);
  for (const auto& p : params["parameters"]) {
    ASSERT_TRUE(p.contains("posterior")) << p.dump();
    const double lo = p["lower"], hi = p["upper"];
    const double p05 = p["posterior"]["p05"], med = p["posterior"]["median"],
                 p95 = p["posterior"]["p95"];
    EXPECT_LE(lo, p05) << p.dump();
    EXPECT_LE(p05, med) << p.dump();
    EXPECT_LE(med, p95) << p.dump();
    EXPECT_LE(p95, hi) << p.dump();
  }
  // posterior.csv: the labels, then 4 chains x 4000 / 4 samples.
  std::istringstream csv(ReadFile(out + "/posterior.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "talus.hardness,talus.roughness,soil.hardness,soil.roughness");
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 4000);
  std::ifstream cin(out + "/calibration.json");
  const nlohmann::json cal = nlohmann::json::parse(cin);
  const nlohmann::json& post = cal["posterior"];
  EXPECT_EQ(post["predictive"]["draws"].get<int>(), 3);
  EXPECT_FALSE(post["predictive"]["bands"].empty());
  const int simulated = post["simulated"];
  EXPECT_GT(simulated, 0);
  // The same draws' bands of the runout and of both partitions: at BP-1 the
  // height's maximum is the statistic the tree scars there compare.
  const nlohmann::json& stats = post["predictive"]["statistics"];
  ASSERT_EQ(stats["partitions"].size(), 2u) << stats.dump();
  EXPECT_EQ(stats["partitions"][0]["id"], "BP-1");
  for (const auto& partition : stats["partitions"]) {
    const nlohmann::json& passed = partition["passed_fraction"];
    EXPECT_LE(0.0, passed["p05"].get<double>()) << partition.dump();
    EXPECT_LE(passed["p05"].get<double>(), passed["median"].get<double>()) << partition.dump();
    EXPECT_LE(passed["median"].get<double>(), passed["p95"].get<double>()) << partition.dump();
    EXPECT_LE(passed["p95"].get<double>(), 1.0) << partition.dump();
    EXPECT_TRUE(partition["energy_kj"].contains("p95")) << partition.dump();
  }
  EXPECT_TRUE(stats["runout"]["x_m"].contains("p90")) << stats.dump();
  bool compared = false;
  for (const auto& b : post["predictive"]["bands"])
    if (b["observation"] == "tree_scars[0] BP-1" && b["quantity"] == "max") {
      compared = true;
      const nlohmann::json& height = stats["partitions"][0]["height_m"]["max"];
      EXPECT_EQ(height["p05"], b["p05"]);
      EXPECT_EQ(height["median"], b["median"]);
      EXPECT_EQ(height["p95"], b["p95"]);
    }
  EXPECT_TRUE(compared) << "no band of the tree scars' maximum at BP-1";
  const std::string report = ReadFile(out + "/report.html");
  EXPECT_THAT(report, HasSubstr("id=\"posterior\""));
  EXPECT_THAT(report, HasSubstr("Pairwise plot"));
  EXPECT_THAT(report, HasSubstr("Predictive bands of the runout and of every partition"));
  EXPECT_THAT(ReadFile(out + "/parameters.md"), HasSubstr("Posterior (uniform prior"));

  // Resumed: every posterior evaluation replayed, the same samples.
  r = Rockcal(Args(out, "--resume"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream again_in(out + "/calibration.json");
  const nlohmann::json again = nlohmann::json::parse(again_in);
  EXPECT_EQ(again["posterior"]["simulated"].get<int>(), 0);
  EXPECT_EQ(again["posterior"]["posterior_evaluations"], post["posterior_evaluations"]);
  EXPECT_EQ(again["posterior"]["parameters"], post["parameters"]);
  SimulateDrawsFromItAndTableShowsItsIntervals(out);
}

TEST(CalibratePosterior, ItsOptionsNeedTheFlagAndAKnownStage) {
  const std::string site = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  RunResult r = Rockcal("calibrate " + site + "/site.json --observations " + site +
                        "/observations.json --predictive 3 --out " + FreshDir("no_flag"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("need --posterior"));
  r = Rockcal("calibrate " + site + "/site.json --observations " + site +
              "/observations.json --posterior-log-sigma --out " + FreshDir("no_flag_log"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--posterior-log-sigma"));
  r = Rockcal(Args(FreshDir("stage"), "--posterior-stage middle"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--posterior-stage"));
  EXPECT_THAT(r.err, HasSubstr("'middle'"));
}

}  // namespace
}  // namespace rockcal::cli
