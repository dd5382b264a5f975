// rockcal campaign: a tiny joint calibration of the twin campaign writing
// its files, a resume that gives the same result, and bad input that exits 2
// naming the file, the JSON path and what was expected, writing nothing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

std::string TwinCampaign() {
  return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/twin_campaign/campaign.json";
}

std::string Campaign(const std::string& file, const std::string& out, const std::string& extra) {
  return "campaign " + file + " --rocks 6 --seed 3 --max-evals 3 --quiet " + extra + " --out " +
         out;
}

TEST(CampaignCommand, WritesTheJointTableTheTraceAndEachSitesFit) {
  const std::string out = FreshDir("out");
  const RunResult run = Rockcal(Campaign(TwinCampaign(), out, ""));
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* file : {"parameters.json", "parameters.csv", "parameters.md", "trace.csv",
                           "sites.csv", "summary.json", "evaluations.jsonl", ".rockcal-output"})
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(out + "/summary.json"));
  EXPECT_EQ(summary["campaign"], "twin campaign");
  EXPECT_EQ(summary["evaluations"], 3);
  EXPECT_EQ(summary["rocks_per_evaluation"], 12);  // 6 per site
  ASSERT_EQ(summary["parameters"].size(), 2u);
  EXPECT_EQ(summary["parameters"][0]["class"], "ground");
  EXPECT_EQ(summary["parameters"][0]["name"], "hardness");
  EXPECT_TRUE(summary["uncertainty"]["computed"].get<bool>());
  ASSERT_EQ(summary["sites"].size(), 2u);
  EXPECT_EQ(summary["sites"][0]["name"], "fan");
  EXPECT_EQ(summary["sites"][1]["parameters"][0]["material"], "scree");
  EXPECT_EQ(summary["sites"][1]["parameters"][0]["calibrated"], summary["parameters"][0]["value"]);
  EXPECT_TRUE(summary["sites"][0]["misfit_own_start"].is_number());
  EXPECT_TRUE(summary["sites"][0]["misfit_joint"].is_number());
  // Error against run time: one row per evaluation.
  const std::string trace = ReadFile(out + "/trace.csv");
  EXPECT_THAT(trace, HasSubstr("method,evaluation,wall_seconds,misfit,best_misfit,ground.hardness,"
                               "ground.roughness,replayed\n"));
  EXPECT_EQ(std::count(trace.begin(), trace.end(), '\n'), 4);
  EXPECT_THAT(ReadFile(out + "/sites.csv"), HasSubstr("site,site_file,weight,rocks"));
  EXPECT_THAT(ReadFile(out + "/parameters.md"), HasSubstr("## Per-site fit"));
  EXPECT_THAT(ReadFile(out + "/parameters.csv"), HasSubstr("ground,ground,hardness,"));
  EXPECT_THAT(ReadFile(out + "/.rockcal-output"), HasSubstr("\"command\": \"campaign\""));

  // The folder exists: refused without --force, replaced with it.
  RunResult again = Rockcal(Campaign(TwinCampaign(), out, ""));
  EXPECT_EQ(again.status, 2);
  EXPECT_THAT(again.err, HasSubstr("output folder exists already"));
  again = Rockcal(Campaign(TwinCampaign(), out, "--force"));
  EXPECT_EQ(again.status, 0) << again.err;
}

TEST(CampaignCommand, ResumeGivesTheSameResult) {
  const std::string out = FreshDir("out");
  RunResult run = Rockcal(Campaign(TwinCampaign(), out, ""));
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json first = nlohmann::json::parse(ReadFile(out + "/summary.json"));
  run = Rockcal(Campaign(TwinCampaign(), out, "--resume"));
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json second = nlohmann::json::parse(ReadFile(out + "/summary.json"));
  EXPECT_EQ(second["calibrated"], first["calibrated"]);
  EXPECT_EQ(second["misfit_after"], first["misfit_after"]);
  EXPECT_EQ(second["methods"][0]["simulated"], 0);  // every evaluation replayed
  // A resume with other rocks is refused, naming what changed.
  run = Rockcal("campaign " + TwinCampaign() +
                " --rocks 7 --seed 3 --max-evals 3 --quiet --resume --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("fan: rocks"));
}

TEST(CampaignCommand, BadInputExitsTwoNamingTheFileAndPathAndWritesNothing) {
  const std::string dir = FreshDir("files");
  fs::create_directories(dir);
  const std::string examples = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/twin_campaign/";
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name) << text;
    return dir + "/" + name;
  };
  const std::string fan = "{\"site\": \"" + examples + "fan/site.json\", \"observations\": \"" +
                          examples + "fan/observations.json\"}";
  struct Case {
    std::string file, extra, expected;
  };
  const std::vector<Case> cases = {
      {dir + "/missing.json", "", "missing.json"},
      {write("bad_path.json", "{\"units\": \"si\", \"sites\": [" + fan +
                                  ", {\"site\": \"nowhere.json\", \"observations\": \"x.json\"}]}"),
       "", "bad_path.json: $.sites[1].site: no such file"},
      {write("bad_weight.json", "{\"units\": \"si\", \"sites\": [" + fan.substr(0, fan.size() - 1) +
                                    ", \"weight\": 0}]}"),
       "", "bad_weight.json: $.sites[0].weight"},
      {write("bad_offset.json", "{\"units\": \"si\", \"sites\": [" + fan +
                                    "], \"offsets\": [{\"class\": \"rock\", \"parameter\": "
                                    "\"hardness\", \"sigma\": 0.1}]}"),
       "", "bad_offset.json: $.offsets[0]: class 'rock' hardness: no site calibrates it"},
      {TwinCampaign(), "--method nlopt:nope",
       "argument --method: unknown method 'nlopt:nope' (allowed: nlopt:bobyqa, "},
      {TwinCampaign(), "--loss l1",
       "argument --loss: unknown loss 'l1' (allowed: none, huber, cauchy)"},
      {TwinCampaign(), "--estimate mean",
       "argument --estimate: unknown estimate 'mean' (allowed: lowest, smoothed)"},
      {TwinCampaign(), "--refine 2", "unknown option"},
  };
  for (const Case& c : cases) {
    const std::string out = FreshDir("out");
    const RunResult run = Rockcal(Campaign(c.file, out, c.extra));
    EXPECT_EQ(run.status, 2) << c.file << " " << c.extra << "\n" << run.err;
    EXPECT_THAT(run.err, HasSubstr(c.expected)) << c.file;
    EXPECT_FALSE(fs::exists(out)) << c.file;
  }
}

}  // namespace
}  // namespace rockcal::cli
