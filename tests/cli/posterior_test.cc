// rockcal calibrate --posterior end to end on the tutorial site (4 values):
// the files and keys it adds, a resume that replays the posterior stage,
// and its options' errors.
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

TEST(CalibratePosterior, WritesTheIntervalsSamplesAndBandsAndResumes) {
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
  const std::string report = ReadFile(out + "/report.html");
  EXPECT_THAT(report, HasSubstr("id=\"posterior\""));
  EXPECT_THAT(report, HasSubstr("Pairwise plot"));
  EXPECT_THAT(ReadFile(out + "/parameters.md"), HasSubstr("Posterior (uniform prior"));

  // Resumed: every posterior evaluation replayed, the same samples.
  r = Rockcal(Args(out, "--resume"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream again_in(out + "/calibration.json");
  const nlohmann::json again = nlohmann::json::parse(again_in);
  EXPECT_EQ(again["posterior"]["simulated"].get<int>(), 0);
  EXPECT_EQ(again["posterior"]["posterior_evaluations"], post["posterior_evaluations"]);
  EXPECT_EQ(again["posterior"]["parameters"], post["parameters"]);
}

TEST(CalibratePosterior, ItsOptionsNeedTheFlagAndAKnownStage) {
  const std::string site = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  RunResult r = Rockcal("calibrate " + site + "/site.json --observations " + site +
                        "/observations.json --predictive 3 --out " + FreshDir("no_flag"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("need --posterior"));
  r = Rockcal(Args(FreshDir("stage"), "--posterior-stage middle"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("--posterior-stage"));
  EXPECT_THAT(r.err, HasSubstr("'middle'"));
}

}  // namespace
}  // namespace rockcal::cli
