// The campaign posterior's command line for its tests: the twin campaign
// with a hardness offset per site (3 joint values) at a handful of rocks,
// for campaign_posterior_test.cc (the files it writes) and
// campaign_posterior_kill_heavy_test.cc (killed and resumed).
#ifndef ROCKCAL_TESTS_CLI_CAMPAIGN_POSTERIOR_ARGS_H_
#define ROCKCAL_TESTS_CLI_CAMPAIGN_POSTERIOR_ARGS_H_

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace rockcal::cli::testing {

inline const std::string kCampaignExamples =
    std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/twin_campaign";

// The twin campaign with a hardness offset per site (campaign_offsets.json)
// at the command's rocks: a file beside the test's outputs.
inline std::string OffsetsCampaign() {
  const std::string file = ::testing::TempDir() + "/rockcal_campaign_posterior_offsets.json";
  std::ofstream(file)
      << "{\"name\": \"twin campaign with offsets\", \"units\": \"si\", \"sites\": ["
      << "{\"site\": \"" << kCampaignExamples << "/fan/site.json\", \"observations\": \""
      << kCampaignExamples << "/fan/observations.json\"}, {\"site\": \"" << kCampaignExamples
      << "/gully/site.json\", \"observations\": \"" << kCampaignExamples
      << "/gully/observations.json\"}], \"shared\": [\"ground\"], \"offsets\": "
         "[{\"class\": \"ground\", \"parameter\": \"hardness\", \"sigma\": 0.05}]}";
  return file;
}

inline std::vector<std::string> CampaignArgs(const std::string& out, bool resume) {
  std::vector<std::string> args = {ROCKCAL_EXE,
                                   "campaign",
                                   OffsetsCampaign(),
                                   "--rocks",
                                   "6",
                                   "--seed",
                                   "3",
                                   "--max-evals",
                                   "4",
                                   "--posterior",
                                   "--posterior-points",
                                   "10",
                                   "--posterior-rounds",
                                   "1",
                                   "--predictive",
                                   "3",
                                   "--quiet",
                                   "--out",
                                   out};
  if (resume) args.push_back("--resume");
  return args;
}

}  // namespace rockcal::cli::testing

#endif  // ROCKCAL_TESTS_CLI_CAMPAIGN_POSTERIOR_ARGS_H_
