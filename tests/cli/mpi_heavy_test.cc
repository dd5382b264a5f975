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

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

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

// The posterior on two ranks: every rank must emulate the same design
// (EvaluateAll's misfits, not rank 0's callback), or their refining rounds
// pick other points and the ranks part (a hang, or a worker simulating its
// own points for rank 0's).
TEST(Mpi, ThePosteriorIsTheSameOnTwoRanks) {
  SKIP_WITHOUT_MPI();
  const std::string one = FreshDir("one"), two = FreshDir("two");
  const std::string args = "calibrate " + Tutorial() +
                           " --rocks 5 --max-evals 5 --reach 3 --posterior --posterior-rounds 3 "
                           "--predictive 2 --threads 1 --quiet";
  const RunResult a = Rockcal(args + " --out " + one);
  ASSERT_EQ(a.status, 0) << a.err;
  const RunResult b = RockcalRanks(2, args + " --out " + two);
  ASSERT_EQ(b.status, 0) << b.err;
  ExpectSameFiles(one, two, {"posterior.csv", "parameters.json"});
  // The posterior's points are logged as they finish: the same lines, in
  // another order on two ranks.
  auto lines = [](const std::string& path) {
    std::istringstream in(Timeless(path));
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);) out.push_back(line);
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(lines(one + "/evaluations.jsonl"), lines(two + "/evaluations.jsonl"));
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

// A joint campaign of two sites: each evaluation's site simulations spread
// over the ranks as (point, site) tasks; the same files at 1 and 2 ranks,
// and a campaign started on two ranks resumes on one as a straight run goes.
TEST(Mpi, ACampaignIsTheSameOnTwoRanksAndResumesOnOne) {
  SKIP_WITHOUT_MPI();
  const std::string one = FreshDir("one"), two = FreshDir("two"), resumed = FreshDir("resumed");
  const std::string args = "campaign " + std::string(ROCKCAL_SOURCE_DIR) +
                           "/sites/examples/twin_campaign/campaign.json --rocks 12 --seed 3 "
                           "--threads 1 --quiet";
  const std::vector<std::string> files = {"evaluations.jsonl", "parameters.json", "parameters.csv",
                                          "sites.csv", "summary.json"};
  const RunResult a = Rockcal(args + " --max-evals 6 --out " + one);
  ASSERT_EQ(a.status, 0) << a.err;
  const RunResult b = RockcalRanks(2, args + " --max-evals 6 --out " + two);
  ASSERT_EQ(b.status, 0) << b.err;
  ExpectSameFiles(one, two, files);
  const RunResult c = RockcalRanks(2, args + " --max-evals 3 --out " + resumed);
  ASSERT_EQ(c.status, 0) << c.err;
  const RunResult d = Rockcal(args + " --max-evals 6 --resume --out " + resumed);
  ASSERT_EQ(d.status, 0) << d.err;
  // All but summary.json, which counts the evaluations simulated (3 of 6 resumed).
  ExpectSameFiles(one, resumed, {"evaluations.jsonl", "parameters.json", "parameters.csv", "sites.csv"});
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

// A rank that stops answering (SIGSTOP, after the first evaluations are in
// the log) is named by rank 0 with its host, the job ends with exit status
// 1, and the log it leaves resumes on one rank as a straight run would go.
TEST(Mpi, AHungRankIsNamedAndTheLogResumes) {
  SKIP_WITHOUT_MPI();
  const std::string hung = FreshDir("hung"), straight = FreshDir("straight");
  const std::string args = "calibrate " + Tutorial() + " --rocks 150 --reach 0 --threads 1 --quiet";
  const std::string base = ::testing::TempDir() + "/rockcal_" + TestFileName();
  // The run is long (40 evaluations); rank 1 is stopped once two are logged.
  const std::string script =
      "ROCKCAL_RANK_TIMEOUT=3 " + Mpirun(2) + ROCKCAL_EXE + " " + args +
      " --max-evals 40 --out " + hung + " > " + base + ".stdout 2> " + base + ".stderr & m=$!\n" +
      "for i in $(seq 1200); do [ \"$(cat " + hung +
      "/evaluations.jsonl 2>/dev/null | grep -c .)\" -ge 3 ] && break; sleep 0.1; done\n"
      "stopped=\n"
      "for p in $(pgrep -f -- '--out " + hung + "'); do\n"
      "  tr '\\0' '\\n' < /proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1 &&"
      " kill -STOP $p && stopped=\"$stopped $p\"\n"
      "done\n"
      "wait $m; status=$?\n"
      "for p in $stopped; do kill -KILL $p 2>/dev/null; rm -rf \"${TMPDIR:-/tmp}/rockcal-rank1-$p\"; done\n"
      "exit $status\n";
  std::ofstream(base + ".sh") << script;
  const int raw = std::system(("timeout 300 bash " + base + ".sh").c_str());
  const std::string err = ReadFile(base + ".stderr");
  ASSERT_TRUE(WIFEXITED(raw)) << err;
  EXPECT_EQ(WEXITSTATUS(raw), 1) << err;
  EXPECT_NE(err.find("rockcal: failed: rank 1 (host "), std::string::npos) << err;
  EXPECT_NE(err.find("did not answer within 3 s"), std::string::npos) << err;
  // The log holds whole evaluations only: a resume on one rank with the
  // budget of what was logged replays them and finishes as a straight run.
  const RunResult resumed = Rockcal(args + " --max-evals 2 --resume --out " + hung);
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  const RunResult a = Rockcal(args + " --max-evals 2 --out " + straight);
  ASSERT_EQ(a.status, 0) << a.err;
  ExpectSameFiles(straight, hung, {"parameters.json", "rocks.csv", "summary.json"});
}

}  // namespace
}  // namespace rockcal::cli::testing
