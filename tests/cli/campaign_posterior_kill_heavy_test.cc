// rockcal campaign --posterior killed (SIGKILL) in its posterior stage or
// its final writes resumes with --resume to the files of a run that was
// not killed. Labelled heavy: it runs rockcal seven times, some 6 s in the
// optimised build, over half a minute under the sanitizers.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "campaign_posterior_args.h"
#include "kill_fixture.h"

namespace rockcal::cli {
namespace campaign_posterior_kill_heavy_test {

namespace fs = std::filesystem;
using testing::CampaignArgs;
using testing::Differences;
using testing::FreshDir;
using testing::KillPoint;
using testing::List;
using testing::Outcome;
using testing::RunAndKill;

TEST(CampaignPosterior, KilledInItsPosteriorOrItsWritesResumesToTheSameFiles) {
  const std::string work = FreshDir("work");
  fs::create_directories(work);
  const std::string log = work + "/run.log";
  const std::string reference = work + "/reference";
  const Outcome straight =
      RunAndKill(CampaignArgs(reference, false), reference, KillPoint::After(1e9), log);
  ASSERT_EQ(straight.status, 0) << straight.output;
  const std::vector<KillPoint> kills = {
      KillPoint::Holds("evaluations.jsonl", "\"method\":\"posterior\""),
      KillPoint::Written("sites/gully/parameters.json"), KillPoint::Written("summary.json")};
  int killed_runs = 0;
  for (std::size_t k = 0; k < kills.size(); ++k) {
    const std::string out = work + "/case-" + std::to_string(k);
    const Outcome killed = RunAndKill(CampaignArgs(out, false), out, kills[k], log);
    killed_runs += killed.killed;
    std::printf("killed %s: %s\n", kills[k].Describe().c_str(),
                killed.killed ? "yes" : "no, the run ended first");
    // A kill at the last file may come after the run ended: then it is whole.
    ASSERT_TRUE(killed.killed || killed.status == 0) << kills[k].Describe() << "\n"
                                                     << killed.output;
    const Outcome resumed = RunAndKill(CampaignArgs(out, true), out, KillPoint::After(1e9), log);
    ASSERT_EQ(resumed.status, 0) << kills[k].Describe() << "\n" << resumed.output;
    EXPECT_EQ(List(Differences(reference, out)), "") << "killed " << kills[k].Describe();
  }
  EXPECT_GE(killed_runs, 2) << "most kill points should be reached";
}

}  // namespace campaign_posterior_kill_heavy_test
}  // namespace rockcal::cli
