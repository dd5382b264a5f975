// Kill anywhere: a calibration killed (SIGKILL) at seeded random moments, while
// it starts, searches or writes its final files, and then resumed with
// --resume ends in a complete folder whose results are those of an
// uninterrupted run, wall times aside (issue 14). ROCKCAL_KILL_SEED=S replays
// another set of kill moments. Labelled heavy: it runs rockcal some twenty
// times, 20-30 s in the optimised build but many minutes under the sanitizers.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "kill_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::Differences;
using testing::FileNames;
using testing::FreshDir;
using testing::Joined;
using testing::KillPoint;
using testing::List;
using testing::Outcome;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunAndKill;
using testing::RunResult;

// The files a finished calibration of the tutorial writes after its search,
// calibration.json last: the targets of the kills "during the final writes".
const std::vector<std::string> kFinalFiles = {
    "summary.json", "rocks.csv",      "diagnostics.json", "parameters.json", "parameters.csv",
    "parameters.md", "trace.csv",     "reach.json",       "report.html",      "calibration.json"};

std::vector<std::string> CalibrateArgs(const std::string& out, bool resume) {
  const std::string tutorial = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  std::vector<std::string> args = {ROCKCAL_EXE,     "calibrate",
                                   tutorial + "/site.json", "--observations",
                                   tutorial + "/observations.json",
                                   "--rocks",       "4",
                                   "--seed",        "2",
                                   "--max-evals",   "6",
                                   "--reach",       "4",
                                   "--quiet",       "--out",
                                   out};
  if (resume) args.push_back("--resume");
  return args;
}

// --- The test ----------------------------------------------------------------

TEST(CalibrateKill, KilledAnywhereResumesToTheUninterruptedResult) {
  unsigned seed = 14;
  if (const char* s = std::getenv("ROCKCAL_KILL_SEED")) seed = static_cast<unsigned>(std::atoi(s));
  std::mt19937 rng(seed);
  const std::string work = FreshDir("work");
  fs::create_directories(work);
  const std::string log = work + "/run.log";

  // The uninterrupted run, and how long it takes here.
  const std::string reference = work + "/reference";
  const auto t0 = std::chrono::steady_clock::now();
  const Outcome straight =
      RunAndKill(CalibrateArgs(reference, false), reference, KillPoint::After(1e9), log);
  const double run_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(straight.status, 0) << straight.output;
  for (const std::string& f : kFinalFiles) ASSERT_TRUE(fs::exists(reference + "/" + f)) << f;

  // Each case kills a calibration once or twice (the first run, then its
  // resume) and lets a last resume finish. The kill points: the folder's
  // appearance, the log's, four of the final files (calibration.json always)
  // and, in a third of the kills, a random moment of a run.
  std::vector<KillPoint> targets;
  targets.push_back(KillPoint::Written(""));
  targets.push_back(KillPoint::Written("evaluations.jsonl"));
  targets.push_back(KillPoint::Written("calibration.json"));
  std::vector<std::string> finals;
  std::sample(kFinalFiles.begin(), kFinalFiles.end() - 1, std::back_inserter(finals), 3, rng);
  for (const std::string& f : finals) targets.push_back(KillPoint::Written(f));
  std::shuffle(targets.begin(), targets.end(), rng);
  std::uniform_real_distribution<double> moment(0.0, run_seconds);
  std::size_t next_target = 0;
  int kills = 0, cases = 0;
  while (next_target < targets.size()) {
    ++cases;
    const std::string out = work + "/case-" + std::to_string(cases);
    std::vector<KillPoint> plan;
    const int kills_in_case = 1 + static_cast<int>(rng() % 2);
    for (int k = 0; k < kills_in_case; ++k) {
      if (rng() % 3 == 0 || next_target >= targets.size())
        plan.push_back(KillPoint::After(moment(rng)));
      else
        plan.push_back(targets[next_target++]);
    }
    std::string history = "seed " + std::to_string(seed) + ", case " + std::to_string(cases) +
                          " (rockcal " + Joined(CalibrateArgs(out, false)) + "):";
    for (const KillPoint& point : plan) {
      std::error_code ec;
      const bool resume = fs::exists(out, ec);  // a run killed before its folder starts afresh
      const std::vector<std::string> args = CalibrateArgs(out, resume);
      const Outcome o = RunAndKill(args, out, point, log);
      history += std::string(resume ? " resume" : " run") + " killed " + point.Describe() +
                 (o.killed ? "" : " (finished first, status " + std::to_string(o.status) + ")");
      if (o.killed) {
        history += ", leaving {";
        for (const std::string& f : FileNames(out)) history += " " + f;
        history += " };";
      }
      if (o.killed) ++kills;
      ASSERT_TRUE(o.killed || o.status == 0) << history << "\n" << o.output;
      // A folder that says it is finished (calibration.json) is finished.
      if (fs::exists(out + "/calibration.json", ec)) {
        EXPECT_EQ(List(Differences(reference, out)), "")
            << history << ": a folder with calibration.json must be complete";
      }
    }
    std::error_code ec;
    const bool resume = fs::exists(out, ec);
    const std::vector<std::string> args = CalibrateArgs(out, resume);
    const Outcome last = RunAndKill(args, out, KillPoint::After(1e9), log);
    history += std::string(resume ? " resume" : " run") + " to the end.";
    ASSERT_EQ(last.status, 0) << history << "\n" << last.output;
    EXPECT_EQ(List(Differences(reference, out)), "") << history;
    const RunResult table = Rockcal("table " + out + " --quiet --out " + work + "/table-" +
                                    std::to_string(cases));
    EXPECT_EQ(table.status, 0) << history << "\n" << table.err;
    std::printf("%s\n", history.c_str());
    if (HasFailure()) break;
  }
  std::printf("kill test, seed %u: %d kills in %d cases; an uninterrupted run takes %.2f s\n", seed,
              kills, cases, run_seconds);
  EXPECT_GE(kills, static_cast<int>(targets.size()) / 2) << "most kill points should be reached";
}

}  // namespace
}  // namespace rockcal::cli
