// rockcal campaign --posterior end to end on the twin campaign with a
// hardness offset per site (3 joint values): the joint posterior, each
// offset's and each site's, the samples, the per-site predictive check,
// the site folders read back by rockcal table and rockcal simulate
// --parameters. Killed and resumed: campaign_posterior_kill_heavy_test.cc.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "campaign_posterior_args.h"
#include "kill_fixture.h"

namespace rockcal::cli {
namespace campaign_posterior_test {

using testing::CampaignArgs;
using testing::FreshDir;
using testing::Joined;
using testing::kCampaignExamples;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

nlohmann::json ReadJson(const std::string& path) { return nlohmann::json::parse(ReadFile(path)); }

// The header and the number of lines after it.
std::pair<std::string, int> CsvShape(const std::string& path) {
  std::istringstream in(ReadFile(path));
  std::string header, line;
  std::getline(in, header);
  int lines = 0;
  while (std::getline(in, line)) ++lines;
  return {header, lines};
}

// parameters.json's posterior of every value within its bounds, in order.
void ExpectOrderedIntervals(const std::string& file) {
  const nlohmann::json params = ReadJson(file);
  ASSERT_FALSE(params["parameters"].empty()) << file;
  EXPECT_EQ(params["posterior_samples"], "posterior.csv") << file;
  for (const auto& p : params["parameters"]) {
    ASSERT_TRUE(p.contains("posterior")) << file << ": " << p.dump();
    const double lo = p["lower"], hi = p["upper"];
    const double p05 = p["posterior"]["p05"], med = p["posterior"]["median"],
                 p95 = p["posterior"]["p95"];
    EXPECT_LE(lo, p05) << file << ": " << p.dump();
    EXPECT_LE(p05, med) << file << ": " << p.dump();
    EXPECT_LE(med, p95) << file << ": " << p.dump();
    EXPECT_LE(p95, hi) << file << ": " << p.dump();
  }
}

// The files of a finished campaign with a posterior, and how they agree.
void ExpectPosteriorFiles(const std::string& out) {
  ExpectOrderedIntervals(out + "/parameters.json");
  EXPECT_EQ(CsvShape(out + "/posterior.csv"),
            std::make_pair(
                std::string("ground.hardness,ground.roughness,fan:ground.hardness_offset"), 4000));
  const nlohmann::json summary = ReadJson(out + "/summary.json");
  const nlohmann::json& post = summary["posterior"];
  EXPECT_EQ(post["samples"], 4000);
  EXPECT_EQ(post["predictive"]["draws"], 3);
  // The offsets sum to zero at every sample: the gully's is minus the fan's.
  const nlohmann::json& offsets = post["offsets"];
  ASSERT_EQ(offsets.size(), 2u) << offsets.dump();
  EXPECT_EQ(offsets[0]["label"], "fan:ground.hardness_offset");
  EXPECT_EQ(offsets[1]["label"], "gully:ground.hardness_offset");
  EXPECT_NEAR(offsets[0]["median"].get<double>(), -offsets[1]["median"].get<double>(), 1e-12);
  EXPECT_NEAR(offsets[0]["p05"].get<double>(), -offsets[1]["p95"].get<double>(), 1e-12);
  EXPECT_LE(offsets[0]["p05"].get<double>(), offsets[0]["median"].get<double>());
  EXPECT_LE(offsets[0]["median"].get<double>(), offsets[0]["p95"].get<double>());
  // Each site: its own values' posterior and the bands of its own statistics.
  const std::vector<std::string> sites = {"fan", "gully"};
  const std::vector<std::string> materials = {"talus", "scree"};
  for (std::size_t k = 0; k < sites.size(); ++k) {
    const nlohmann::json& site = summary["sites"][k];
    EXPECT_EQ(site["folder"], "sites/" + sites[k]);
    const std::string dir = out + "/sites/" + sites[k];
    ExpectOrderedIntervals(dir + "/parameters.json");
    EXPECT_EQ(CsvShape(dir + "/posterior.csv"),
              std::make_pair(materials[k] + ".hardness," + materials[k] + ".roughness", 4000));
    // The roughness is shared, without an offset: the joint value's posterior.
    EXPECT_EQ(site["posterior"]["parameters"][1]["median"], post["parameters"][1]["median"]);
    const nlohmann::json& bands = site["posterior"]["predictive"]["bands"];
    ASSERT_FALSE(bands.empty()) << site.dump();
    for (const auto& b : bands) {
      EXPECT_EQ(b["observation"].get<std::string>().find(sites[k] + ": "), std::string::npos);
      EXPECT_LE(b["p05"].get<double>(), b["p95"].get<double>()) << b.dump();
    }
  }
  EXPECT_THAT(ReadFile(out + "/sites.csv"),
              ::testing::HasSubstr(",predictive_inside,predictive_bands\n"));
  EXPECT_THAT(ReadFile(out + "/parameters.md"),
              ::testing::HasSubstr("## Each site's offset: posterior"));
}

TEST(CampaignPosterior, WritesEveryIntervalAndTheSitesFilesThatTableAndSimulateRead) {
  const std::string out = FreshDir("out");
  RunResult r = Rockcal(Joined(CampaignArgs(out, false)));
  ASSERT_EQ(r.status, 0) << r.err;
  ExpectPosteriorFiles(out);

  // rockcal table pools the two sites' values with their intervals.
  const std::string table = FreshDir("table");
  r = Rockcal("table " + out + "/sites/fan " + out + "/sites/gully --quiet --out " + table);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(ReadFile(table + "/table.csv"),
              ::testing::HasSubstr(",posterior_p05,posterior_p95\n"));
  // rockcal simulate --parameters of a site draws from its posterior.
  const std::string draws = FreshDir("draws");
  r = Rockcal("simulate " + kCampaignExamples + "/gully/site.json --parameters " + out +
              "/sites/gully --rocks 6 --draws 3 --quiet --out " + draws);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json used = ReadJson(draws + "/summary.json")["parameters"];
  EXPECT_EQ(used["use"], "posterior draws") << used.dump();
  EXPECT_EQ(used["draws"], 3);
}

}  // namespace campaign_posterior_test
}  // namespace rockcal::cli
