// rockcal calibrate's output folder: --force, leftovers of killed runs and
// the completion that rockcal table checks (issue 14).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::Example;
using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

std::string Calibrate(const std::string& out, const std::string& extra) {
  const std::string obs =
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
  return "calibrate " + Example("tutorial") + " --observations " + obs + " --rocks 4 --reach 0 --quiet " +
         extra + " --out " + out;
}

// The PID of a process that has exited (and been reaped).
pid_t DeadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

TEST(CalibrateCommand, KilledRunsLeaveNothingBehindAndTableRefusesAnUnfinishedFolder) {
  const std::string cal = FreshDir("cal");
  RunResult run = Rockcal(Calibrate(cal, "--max-evals 2"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(ReadFile(cal + "/.rockcal-output"), HasSubstr("\"command\": \"calibrate\""));
  EXPECT_TRUE(fs::exists(cal + "/calibration.json"));

  // A resumed run killed before it finished: its calibration.json is gone
  // (removed when the run started), the old parameters.json is stale, and a
  // file was half written.
  const std::string stale = cal + "/parameters.json.tmp-" + std::to_string(DeadPid());
  std::ofstream(stale) << "{\"half";
  fs::remove(cal + "/calibration.json");
  const std::string table = FreshDir("table");
  run = Rockcal("table " + cal + " --out " + table);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(cal + ": incomplete calibration: no calibration.json"));
  EXPECT_FALSE(fs::exists(table));

  // --resume removes the leftovers of the killed run and finishes it.
  run = Rockcal(Calibrate(cal, "--max-evals 3 --resume"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(cal + "/calibration.json"));
  run = Rockcal("table " + cal + " --quiet --out " + table);
  EXPECT_EQ(run.status, 0) << run.err;

  // --force replaces the calibration rockcal wrote ...
  std::ofstream(cal + "/mine.txt") << "stale";
  run = Rockcal(Calibrate(cal, "--max-evals 2 --force"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_FALSE(fs::exists(cal + "/mine.txt"));
  // ... but never a folder it did not write.
  const std::string other = FreshDir("other");
  fs::create_directories(other);
  std::ofstream(other + "/mine.txt") << "precious";
  run = Rockcal(Calibrate(other, "--max-evals 2 --force"));
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("holds no .rockcal-output file"));
  EXPECT_EQ(ReadFile(other + "/mine.txt"), "precious");
}

}  // namespace
}  // namespace rockcal::cli
