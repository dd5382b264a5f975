#include "rockcal/reports/output_dir.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>

#include "rockcal/core/error.h"

namespace rockcal::reports {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// A fresh folder named after the running test.
std::string Fresh(const std::string& name) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir = ::testing::TempDir() + "/rockcal_output_dir_" + info->name() + "_" +
                          std::to_string(::getpid()) + "_" + name;
  fs::remove_all(dir);
  return dir;
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string InputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

// The PID of a process that has exited (and been reaped).
pid_t DeadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

TEST(OutputDir, CommitWritesTheMarkerAndForceReplacesAMarkedFolder) {
  const std::string out = Fresh("out");
  {
    OutputDir dir(out, false, {"simulate", {}});
    std::ofstream(dir.File("a.txt")) << "a";
    dir.Commit();
  }
  EXPECT_THAT(Slurp(out + "/.rockcal-output"), HasSubstr("\"command\": \"simulate\""));
  EXPECT_THAT(Slurp(out + "/.rockcal-output"), HasSubstr("\"complete\": true"));
  EXPECT_THAT(InputErrorOf([&] { OutputDir dir(out, false); }), HasSubstr("--force"));
  {
    OutputDir dir(out, true, {"simulate", {}});
    std::ofstream(dir.File("b.txt")) << "b";
    dir.Commit();
  }
  EXPECT_FALSE(fs::exists(out + "/a.txt"));
  EXPECT_TRUE(fs::exists(out + "/b.txt"));
}

TEST(OutputDir, ForceRefusesAFolderWithoutTheMarker) {
  const std::string out = Fresh("proj");
  fs::create_directories(out);
  std::ofstream(out + "/site.json") << "{}";
  const std::string msg = InputErrorOf([&] { OutputDir dir(out, true); });
  EXPECT_THAT(msg, HasSubstr(out + ": holds no .rockcal-output file"));
  EXPECT_TRUE(fs::exists(out + "/site.json"));
  // A file is no output folder either.
  EXPECT_THAT(InputErrorOf([&] { OutputDir dir(out + "/site.json", true); }),
              HasSubstr("is not a folder"));
  EXPECT_TRUE(fs::exists(out + "/site.json"));
}

TEST(OutputDir, RefusesAFolderThatIsHoldsOrLiesInsideAnInput) {
  const std::string proj = Fresh("proj");
  fs::create_directories(proj + "/data");
  std::ofstream(proj + "/site.json") << "{}";
  std::ofstream(proj + "/.rockcal-output") << "{}";  // even one marked as rockcal's
  const std::string site = proj + "/site.json";
  EXPECT_THAT(InputErrorOf([&] {
                OutputDir dir(proj, true, {"simulate", {site}});
              }),
              HasSubstr("contains " + site + ", an input of this run"));
  EXPECT_THAT(InputErrorOf([&] {
                OutputDir dir(proj + "/./data/..", true, {"simulate", {site}});
              }),
              HasSubstr("an input of this run"));
  EXPECT_THAT(InputErrorOf([&] {
                OutputDir dir(site, true, {"simulate", {site}});
              }),
              HasSubstr("is an input of this run"));
  EXPECT_THAT(InputErrorOf([&] {
                OutputDir dir(proj + "/data/out", false, {"table", {proj}});
              }),
              HasSubstr("lies inside " + proj));
  EXPECT_TRUE(fs::exists(site));
  EXPECT_THAT(InputErrorOf([&] { OutputDir dir("", false); }), HasSubstr("is empty"));
}

TEST(OutputDir, RemovesTheTemporariesOfKilledRuns) {
  const std::string out = Fresh("out");
  const std::string dead = std::to_string(DeadPid());
  const std::string alive = std::to_string(::getppid());
  fs::create_directories(out + ".tmp-" + dead);
  fs::create_directories(out + ".tmp-" + alive);
  fs::create_directories(out + "x.tmp-" + dead);  // another output's
  {
    OutputDir dir(out, false);
    dir.Commit();
  }
  EXPECT_FALSE(fs::exists(out + ".tmp-" + dead));
  EXPECT_TRUE(fs::exists(out + ".tmp-" + alive));
  EXPECT_TRUE(fs::exists(out + "x.tmp-" + dead));
  fs::remove_all(out + ".tmp-" + alive);
  fs::remove_all(out + "x.tmp-" + dead);

  std::ofstream(out + "/parameters.json.tmp-" + dead) << "half";
  EXPECT_EQ(RemoveStaleTemporaries(out, ""), 1);
  EXPECT_FALSE(fs::exists(out + "/parameters.json.tmp-" + dead));

  // Inside an output's subfolders too (a campaign's sites/<name>/), not a
  // live run's.
  fs::create_directories(out + "/sites/a");
  std::ofstream(out + "/sites/a/parameters.json.tmp-" + dead) << "half";
  std::ofstream(out + "/sites/a/posterior.csv.tmp-" + alive) << "being written";
  std::ofstream(out + "/summary.json.tmp-" + dead) << "half";
  EXPECT_EQ(RemoveStaleTemporariesInside(out), 2);
  EXPECT_FALSE(fs::exists(out + "/sites/a/parameters.json.tmp-" + dead));
  EXPECT_FALSE(fs::exists(out + "/summary.json.tmp-" + dead));
  EXPECT_TRUE(fs::exists(out + "/sites/a/posterior.csv.tmp-" + alive));
}

// A run holds the lock of its output folder for its life: a second one is
// refused with or without force, naming the holder, and the kernel releases
// the lock of a process that dies without cleaning up.
TEST(OutputLock, ASecondRunIsRefusedNamingTheHolderUntilTheFirstEnds) {
  const std::string out = Fresh("out");
  std::optional<OutputDir> first(std::in_place, out, false, OutputOrigin{"simulate", {}});
  const std::string holder = "pid " + std::to_string(::getpid()) + " on ";
  first->Commit();
  for (bool force : {false, true})
    EXPECT_THAT(InputErrorOf([&] {
                  OutputDir second(out, force, {"simulate", {}});
                }),
                HasSubstr(out + ": is in use by another rockcal run (" + holder));
  EXPECT_THAT(Slurp(out + "/" + kOutputLock), HasSubstr("rockcal simulate, since "));
  EXPECT_THAT(InputErrorOf([&] {
                ResumableOutputDir second(out, false, true, {"calibrate", {}}, "log", "done");
              }),
              HasSubstr("is in use by another rockcal run"));
  first.reset();
  EXPECT_EQ(Slurp(out + "/" + kOutputLock), "") << "a run that ends leaves no holder";
  { OutputDir second(out, true, {"simulate", {}}); }

  // A process that takes the lock and dies (no destructor runs).
  const std::string cal = Fresh("cal");
  { ResumableOutputDir made(cal, false, false, {"calibrate", {}}, "log", "done"); }
  const pid_t child = ::fork();
  if (child == 0) {
    new OutputLock(cal, cal, "calibrate");  // never released by the child
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_THAT(Slurp(cal + "/" + kOutputLock), HasSubstr("pid " + std::to_string(child)));
  { ResumableOutputDir resumed(cal, true, false, {"calibrate", {}}, "log", "done"); }
}

TEST(ResumableOutputDir, ANewFolderAppearsWholeAndResumeNeedsTheLog) {
  const std::string out = Fresh("out");
  {
    ResumableOutputDir dir(out, false, false, {"calibrate", {}}, "evaluations.jsonl", "done");
    EXPECT_TRUE(fs::exists(out + "/evaluations.jsonl"));
    EXPECT_THAT(Slurp(out + "/.rockcal-output"), HasSubstr("\"command\": \"calibrate\""));
    std::ofstream(out + "/done") << "{}";
  }
  EXPECT_THAT(
      InputErrorOf([&] {
        ResumableOutputDir dir(out, false, false, {"calibrate", {}}, "evaluations.jsonl", "done");
      }),
      HasSubstr("--resume to continue"));
  const std::string marker = Slurp(out + "/.rockcal-output");
  { ResumableOutputDir dir(out, true, false, {"calibrate", {}}, "evaluations.jsonl", "done"); }
  EXPECT_EQ(Slurp(out + "/done"), "{}") << "a resume not continued (refused) changes nothing";
  EXPECT_EQ(Slurp(out + "/.rockcal-output"), marker);
  {
    ResumableOutputDir dir(out, true, false, {"calibrate", {}}, "evaluations.jsonl", "done");
    dir.Continue();
    dir.Continue();  // once only
  }
  EXPECT_FALSE(fs::exists(out + "/done")) << "a resume continued removes the completion mark";
  EXPECT_THAT(InputErrorOf([&] {
                ResumableOutputDir dir(out, true, false, {"calibrate", {}}, "other.jsonl", "done");
              }),
              HasSubstr("nothing to resume"));
  std::ofstream(out + "/a") << "a";
  { ResumableOutputDir dir(out, false, true, {"calibrate", {}}, "evaluations.jsonl", "done"); }
  EXPECT_FALSE(fs::exists(out + "/a")) << "--force replaced it";
  EXPECT_TRUE(fs::exists(out + "/evaluations.jsonl"));
}

TEST(WriteFile, DiskFullNamesTheOutputAndTheCause) {
  try {
    WriteWholeFile("summary.json", "/dev/full", std::string(1 << 16, 'x'));
    ADD_FAILURE() << "expected a failure";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot write summary.json"));
    EXPECT_THAT(e.what(), HasSubstr("No space left on device"));
  }
  const std::string dir = Fresh("absent");
  try {
    WriteFileAtomically(dir + "/rocks.csv", "x");
    ADD_FAILURE() << "expected a failure";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot write " + dir + "/rocks.csv"));
    EXPECT_THAT(e.what(), HasSubstr("No such file or directory"));
  }
}

}  // namespace
}  // namespace rockcal::reports
