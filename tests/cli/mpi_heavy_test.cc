// rockcal under mpirun: every output the same, bit for bit, as the single
// process run with the same seed (wall times aside), and a calibration
// stopped at one rank count resumed at another.
//
// A heavy test (run.sh runs it in the optimised build): under the
// sanitizers, Open MPI's own allocations at MPI_Init (in components it
// dlopens, built without frame pointers) reach the leak check with stacks
// it cannot attribute to a library, so no suppression file can name them,
// and MPI_Init alone takes seconds per rank. The sanitized build compiles
// it with no mpirun, and it skips.
#include <unistd.h>

#include <regex>

#include "cli_fixture.h"

namespace rockcal::cli::testing {
namespace {

// mpirun with `ranks` ranks on this machine (oversubscribed: the test
// machine may have fewer cores), or "" when rockcal was built without MPI
// or with the sanitizers.
std::string Mpirun(int ranks) {
  const std::string mpiexec = ROCKCAL_MPIEXEC;
  if (mpiexec.empty()) return "";
  return mpiexec + " -np " + std::to_string(ranks) + " --oversubscribe" +
         (::getuid() == 0 ? " --allow-run-as-root" : "") + " ";
}

RunResult RockcalRanks(int ranks, const std::string& args) {
  const std::string base = ::testing::TempDir() + "/rockcal_" + TestFileName();
  const std::string out_file = base + ".stdout", err_file = base + ".stderr";
  const std::string cmd = Mpirun(ranks) + ROCKCAL_EXE + " " + args + " > " + out_file + " 2> " +
                          err_file;
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, ReadFile(out_file), ReadFile(err_file)};
}

// A file with its wall times blanked: the only values that may differ.
std::string Timeless(const std::string& path) {
  static const std::regex times("\"(seconds|elapsed|wall_seconds)\": ?[-+0-9.eE]+");
  return std::regex_replace(ReadFile(path), times, "\"$1\": T");
}

void ExpectSameFiles(const std::string& a, const std::string& b,
                     const std::vector<std::string>& files) {
  for (const std::string& f : files) {
    const std::string x = Timeless(a + "/" + f), y = Timeless(b + "/" + f);
    EXPECT_FALSE(x.empty()) << a << "/" << f << " is missing or empty";
    EXPECT_TRUE(x == y) << f << " differs between " << a << " and " << b;
  }
}

const std::vector<std::string> kSimulationFiles = {"rocks.csv", "summary.json",
                                                   "diagnostics.json"};
const std::vector<std::string> kCalibrationFiles = {
    "evaluations.jsonl", "parameters.json", "parameters.csv", "reach.json",
    "rocks.csv",         "summary.json",    "diagnostics.json"};

std::string Tutorial() {
  return Example("tutorial") + " --observations " +
         std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
}

#define SKIP_WITHOUT_MPI() \
  if (Mpirun(1).empty()) GTEST_SKIP() << "rockcal was built without MPI, or with the sanitizers"

TEST(Mpi, SimulateIsTheSameOnTwoRanks) {
  SKIP_WITHOUT_MPI();
  const std::string one = FreshDir("one"), two = FreshDir("two");
  const std::string args = "simulate " + Example("tutorial") + " --rocks 9 --threads 1 --quiet";
  const RunResult a = Rockcal(args + " --out " + one);
  ASSERT_EQ(a.status, 0) << a.err;
  const RunResult b = RockcalRanks(2, args + " --out " + two);
  ASSERT_EQ(b.status, 0) << b.err;
  ExpectSameFiles(one, two, kSimulationFiles);
}

// A short calibration (reach check over the ranks, the method's
// evaluations split by rock blocks, the misfit's noise seeds over the ranks).
void ExpectSameCalibration(const std::string& method) {
  const std::string one = FreshDir("one"), two = FreshDir("two");
  const std::string args = "calibrate " + Tutorial() + " --method " + method +
                           " --rocks 5 --max-evals 5 --reach 3 --threads 1 --quiet";
  const RunResult a = Rockcal(args + " --out " + one);
  ASSERT_EQ(a.status, 0) << a.err;
  const RunResult b = RockcalRanks(2, args + " --out " + two);
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  ExpectSameFiles(one, two, kCalibrationFiles);
}

TEST(Mpi, CalibrateBobyqaIsTheSameOnTwoRanks) {
  SKIP_WITHOUT_MPI();
  ExpectSameCalibration("nlopt:bobyqa");
}

TEST(Mpi, CalibrateDirectLIsTheSameOnTwoRanks) {
  SKIP_WITHOUT_MPI();
  ExpectSameCalibration("nlopt:direct_l");
}

TEST(Mpi, ACalibrationStartedOnTwoRanksResumesOnOne) {
  SKIP_WITHOUT_MPI();
  const std::string straight = FreshDir("straight"), resumed = FreshDir("resumed");
  const std::string args = "calibrate " + Tutorial() +
                           " --rocks 5 --reach 2 --threads 1 --quiet";
  const RunResult a = Rockcal(args + " --max-evals 6 --out " + straight);
  ASSERT_EQ(a.status, 0) << a.err;
  const RunResult b = RockcalRanks(2, args + " --max-evals 3 --out " + resumed);
  ASSERT_EQ(b.status, 0) << b.err;
  const RunResult c = Rockcal(args + " --max-evals 6 --resume --out " + resumed);
  ASSERT_EQ(c.status, 0) << c.err;
  ExpectSameFiles(straight, resumed, kCalibrationFiles);
}

TEST(Mpi, BadInputIsExitTwoOnEveryRank) {
  SKIP_WITHOUT_MPI();
  const std::string out = FreshDir("out");
  std::filesystem::create_directories(out);  // exists, no --force: rank 0 refuses
  const RunResult r = RockcalRanks(
      2, "simulate " + Example("tutorial") + " --rocks 2 --quiet --out " + out);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("rockcal: error:"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rockcal::cli::testing
