// Measured impacts end to end: a calibration and a score of the tutorial
// with impacts write impacts.csv, calibration.json's "impacts" and the
// report's section; a bad impacts file is exit 2 naming file:line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../reports/report_check.h"
#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

// The tutorial (US units) with its sphere group named "s1" and four impacts
// on the talus, 3 ft above its surface points (the rock flies on to the
// ground), in `dir`.
std::string TutorialWithImpacts(const std::string& dir, const std::string& impacts) {
  const fs::path from = fs::path(ROCKCAL_SOURCE_DIR) / "sites/examples/tutorial";
  fs::create_directories(dir);
  fs::copy_file(from / "points.csv", fs::path(dir) / "points.csv");
  nlohmann::json site = nlohmann::json::parse(ReadFile((from / "site.json").string()));
  site["rocks"][0]["id"] = "s1";
  std::ofstream(dir + "/site.json") << site.dump(1);
  nlohmann::json obs = nlohmann::json::parse(ReadFile((from / "observations.json").string()));
  obs["impacts_file"] = "impacts.csv";
  obs["impact_draws"] = 4;
  obs["error"]["rebound"] = 0.1;
  std::ofstream(dir + "/observations.json") << obs.dump(1);
  std::ofstream(dir + "/impacts.csv") << impacts;
  return dir;
}

constexpr char kImpacts[] =
    "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out\n"
    "a,s1,150,100,118.9,15,0,-35,20,0,8\n"
    "b,s1,180,60,104.1,12,2,-35,18,1,10\n"
    "c,s1,200,140,88.3,20,-3,-35,25,-2,6\n"
    "d,s1,120,100,143.4,10,0,-35,12,0,12\n";

TEST(Impacts, CalibrateAndScoreWriteTheImpactsFiguresAndTheReportSection) {
  const std::string site = TutorialWithImpacts(FreshDir("site"), kImpacts);
  const std::string out = FreshDir("out");
  RunResult r =
      Rockcal("calibrate " + site + "/site.json --observations " + site +
              "/observations.json --rocks 4 --reach 0 --seed 2 --max-evals 3 --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("impacts: rebounds "));
  const std::string csv = ReadFile(out + "/impacts.csv");
  EXPECT_THAT(csv, HasSubstr("id,group,incidence_deg,vx_out,vy_out,vz_out,vx_sim,vy_sim,vz_sim,"
                             "speed_sd,normal_ratio"));
  EXPECT_THAT(csv, HasSubstr("\na,s1,"));
  EXPECT_THAT(csv, HasSubstr("\nd,s1,"));
  EXPECT_THAT(csv, HasSubstr(",20,0,8,"));  // the observed rebound in ft/s, as given
  const nlohmann::json cal = nlohmann::json::parse(ReadFile(out + "/calibration.json"));
  ASSERT_TRUE(cal.contains("impacts"));
  EXPECT_EQ(cal["impacts"]["per_impact"].size(), 4u);
  EXPECT_EQ(cal["impacts"]["per_impact"][0]["draws"].get<int>(), 4);
  EXPECT_THAT(cal["impacts"]["verdict"].get<std::string>(), HasSubstr("rebounds "));
  int impact_residuals = 0;
  for (const auto& res : cal["fit"])
    if (res["observation"].get<std::string>().rfind("impact ", 0) == 0) ++impact_residuals;
  EXPECT_EQ(impact_residuals, 8) << "a normal and a tangential ratio per impact";
  const std::string report = ReadFile(out + "/report.html");
  EXPECT_THAT(report, HasSubstr("Measured impacts"));
  EXPECT_THAT(report, HasSubstr("Rebound ratios against the impact angle"));
  // Its numbers are calibration.json's, and the page stays self-contained.
  const reports::testing::Parsed parsed = reports::testing::ParseReport(report);
  EXPECT_TRUE(reports::testing::HasSection(parsed, "impacts"));
  reports::testing::ExpectSelfContained(parsed);
  const auto seen = reports::testing::CheckNumbers(parsed, {{"calibration.json", cal}});
  ASSERT_EQ(seen.count("calibration.json"), 1u);
  EXPECT_EQ(seen.at("calibration.json").count("/impacts/per_impact/3/normal_ratio/observed"), 1u);

  const std::string scored = FreshDir("score");
  r = Rockcal("score " + site + "/site.json --observations " + site +
              "/observations.json --rocks 4 --seed 2 --parameters " + out + " --out " + scored);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("impacts: rebounds "));
  EXPECT_EQ(ReadFile(scored + "/impacts.csv").substr(0, 40), csv.substr(0, 40));
  // score.json carries the same "impacts" block as calibration.json (one
  // writer): the same fields per impact, the same observed rebounds (SI).
  const nlohmann::json score = nlohmann::json::parse(ReadFile(scored + "/score.json"));
  ASSERT_TRUE(score.contains("impacts")) << score.dump(1);
  EXPECT_THAT(score["impacts"]["verdict"].get<std::string>(), HasSubstr("rebounds "));
  ASSERT_EQ(score["impacts"]["per_impact"].size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const nlohmann::json& s = score["impacts"]["per_impact"][k];
    const nlohmann::json& c = cal["impacts"]["per_impact"][k];
    std::vector<std::string> s_keys, c_keys;
    for (const auto& [key, value] : s.items()) s_keys.push_back(key);
    for (const auto& [key, value] : c.items()) c_keys.push_back(key);
    EXPECT_EQ(s_keys, c_keys) << "impact " << k;
    EXPECT_EQ(s["id"], c["id"]);
    EXPECT_EQ(s["group"], "s1");
    EXPECT_EQ(s["observed_mps"], c["observed_mps"]) << "impact " << k;
    EXPECT_EQ(s["draws"].get<int>(), 4);
  }
}

TEST(Impacts, HoldoutDealsTheImpactsOverTheFolds) {
  const std::string site = TutorialWithImpacts(FreshDir("site"), kImpacts);
  const std::string out = FreshDir("out");
  const RunResult r =
      Rockcal("calibrate " + site + "/site.json --observations " + site +
              "/observations.json --rocks 4 --reach 0 --seed 2 --max-evals 3 --holdout 2 "
              "--quiet --out " +
              out);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json h = nlohmann::json::parse(ReadFile(out + "/holdout.json"));
  int held = 0;
  for (const auto& fold : h["per_fold"]) held += fold["held_out_values"].get<int>();
  EXPECT_EQ(held, 30 + 30 + 4) << "every scar, stop point and impact held out once";
}

TEST(Impacts, ABadImpactsFileIsExit2NamingFileAndLine) {
  const std::string site = TutorialWithImpacts(
      FreshDir("site"), std::string(kImpacts) + "e,s9,150,100,118.9,15,0,-35,20,0,8\n");
  const RunResult r =
      Rockcal("validate " + site + "/site.json --observations " + site + "/observations.json");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_THAT(r.err, HasSubstr("impacts.csv:6: column 'group': no rock group of the site has "
                               "the id 's9'"));
}

}  // namespace
}  // namespace rockcal::cli
