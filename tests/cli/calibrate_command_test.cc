// rockcal calibrate's output folder: --force, leftovers of killed runs and
// the completion that rockcal table checks (issue 14).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_fixture.h"
#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

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

// An evaluation log's lines without their wall times (seconds, elapsed).
std::vector<nlohmann::json> LogWithoutTimes(const std::string& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    nlohmann::json j = nlohmann::json::parse(line);
    j.erase("seconds");
    j.erase("elapsed");
    lines.push_back(std::move(j));
  }
  return lines;
}

// Issue 38: with --rocks N the noise check only advises (a NOISE: line and
// the rocks needed); --noise-raise F lets it raise the count to a whole
// multiple of N, at most F times; --noise-raise 0 is refused.
TEST(CalibrateCommand, RocksKeepTheirCountUnlessNoiseRaiseIsGiven) {
  const std::string obs =
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
  const std::string base = "calibrate " + Example("tutorial") + " --observations " + obs +
                           " --rocks 6 --seed 2 --reach 6 --max-evals 4 --quiet";
  const std::string kept = FreshDir("kept"), raised = FreshDir("raised");
  const RunResult a = Rockcal(base + " --out " + kept);
  ASSERT_EQ(a.status, 0) << a.err;
  const nlohmann::json ka = nlohmann::json::parse(ReadFile(kept + "/calibration.json"));
  const nlohmann::json& check = ka["noise_check"];
  ASSERT_TRUE(check["noise_dominates"].get<bool>()) << check.dump();
  EXPECT_EQ(check["rocks"], 6);
  EXPECT_EQ(check["rocks_used"], 6);
  EXPECT_EQ(ka["rocks_per_evaluation"], 6);
  EXPECT_THAT(a.out, HasSubstr("NOISE: noise dominates"));
  const RunResult b = Rockcal(base + " --noise-raise 3 --out " + raised);
  ASSERT_EQ(b.status, 0) << b.err;
  const nlohmann::json kb = nlohmann::json::parse(ReadFile(raised + "/calibration.json"));
  EXPECT_EQ(kb["noise_check"]["ratio"], check["ratio"]) << "the same check at the same rocks";
  const double factor = std::pow(check["ratio"].get<double>() / 0.25, 2.0);
  const int multiple = std::min(3, static_cast<int>(std::ceil(std::min(factor, 100.0))));
  ASSERT_GT(multiple, 1) << factor;
  EXPECT_EQ(kb["noise_check"]["rocks_used"], 6 * multiple);
  EXPECT_EQ(kb["rocks_per_evaluation"], 6 * multiple);
  EXPECT_EQ(kb["rocks_final"], 6 * multiple);
  const RunResult c = Rockcal(base + " --noise-raise 0 --out " + FreshDir("zero"));
  EXPECT_EQ(c.status, 2);
  EXPECT_THAT(c.err, HasSubstr("argument --noise-raise"));
}

// Issue 55: the console piped into another program tells one story, line
// by line: each line arrives when it is printed (stdout is line-buffered in
// a pipe, not written in one block at exit), the start's misfit says its
// rocks, one NOISE: line, the out-of-reach advice at most once, and the
// misfits before and after at the same rocks.
TEST(CalibrateCommand, TheConsolePipedTellsOneStoryLineByLine) {
  const std::string obs =
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
  const std::string out = FreshDir("piped"), times = out + ".times";
  // Each line stamped with the time the pipe delivered it; the run's start
  // and end stamped around it.
  const RunResult run = testing::Run(
      "(date +%s.%N > " + times + "; " + std::string(ROCKCAL_EXE) + " calibrate " +
      Example("tutorial") + " --observations " + obs +
      " --rocks 6 --seed 2 --reach 6 --max-evals 6 --out " + out +
      " | while IFS= read -r line; do printf '%s %s\n' \"$(date +%s.%N)\" \"$line\"; done; "
      "date +%s.%N >> " +
      times + ")");
  std::istringstream stamps(ReadFile(times));
  double start = 0, end = 0;
  stamps >> start >> end;
  std::vector<std::pair<double, std::string>> lines;
  std::istringstream in(run.out);
  for (std::string line; std::getline(in, line);) {
    const std::size_t space = line.find(' ');
    lines.push_back({std::stod(line.substr(0, space)), line.substr(space + 1)});
  }
  ASSERT_GE(lines.size(), 5u) << run.out << run.err;
  EXPECT_THAT(lines.back().second, HasSubstr("wrote ")) << run.out << run.err;
  // The first line (after the first evaluation) well before the end.
  EXPECT_THAT(lines.front().second, HasSubstr("misfit at the start"));
  EXPECT_THAT(lines.front().second, HasSubstr("(at 6 rocks)"));
  EXPECT_LT(lines.front().first - start, 0.5 * (end - start))
      << "the first line came " << lines.front().first - start << " s into a run of " << end - start
      << " s";
  int noise = 0, advice = 0;
  for (const auto& [t, text] : lines) {
    noise += text.rfind("NOISE:", 0) == 0;
    advice += text.find("iden the box") != std::string::npos;  // Widen, widen
  }
  EXPECT_EQ(noise, 1) << run.out;
  EXPECT_LE(advice, 1) << run.out;
  EXPECT_THAT(run.out, HasSubstr(" after, both at 6 rocks"));
}

// The library owns the defaults: rockcal calibrate with no flags but the
// budget runs what calibrate::Calibrate runs with CalibrationOptions{} and
// that budget (the reach design, the noise check, the refining stage with
// its race, the noise seeds): the same evaluations, in the same logs.
TEST(CalibrateCommand, RunsTheLibrarysDefaults) {
  const std::string dir = FreshDir("defaults");
  fs::create_directories(dir);
  const std::string fan = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/twin_campaign/fan/";
  nlohmann::json site_json = nlohmann::json::parse(ReadFile(fan + "site.json"));
  for (auto& group : site_json["rocks"]) group["count"] = 2;  // a small scene
  for (auto& material : site_json["materials"])  // one value: a reach design of 8
    if (material.contains("calibrate")) material["calibrate"].erase("roughness");
  const std::string site_path = dir + "/site.json";
  std::ofstream(site_path) << site_json.dump(1);
  const std::string obs_path = fan + "observations.json";
  const std::string out = dir + "/cli";
  const RunResult run = Rockcal("calibrate " + site_path + " --observations " + obs_path +
                                " --max-evals 6 --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;

  const sites::Site site = sites::LoadSite(site_path);
  const observations::Observations obs = observations::LoadObservations(obs_path, site.scene);
  calibrate::CalibrationOptions options;
  options.method.max_evals = 6;
  fs::create_directories(dir + "/library");
  options.log_path = dir + "/library/evaluations.jsonl";
  const calibrate::CalibrationSummary summary = calibrate::Calibrate(site, obs, options);
  ASSERT_TRUE(summary.reach.has_value()) << "the default reach design";
  EXPECT_EQ(summary.final_rocks, 4 * summary.rocks) << "the default refining stage";
  EXPECT_EQ(summary.noise_seeds.size(), 3u) << "the default noise seeds";
  for (const char* log : {"evaluations.jsonl", "evaluations-refine.jsonl"}) {
    const std::vector<nlohmann::json> cli = LogWithoutTimes(out + "/" + log);
    const std::vector<nlohmann::json> library = LogWithoutTimes(dir + "/library/" + log);
    EXPECT_GT(cli.size(), 1u) << log;
    ASSERT_EQ(cli.size(), library.size()) << log;
    for (std::size_t k = 0; k < cli.size(); ++k)
      EXPECT_EQ(cli[k], library[k]) << log << " line " << k + 1;
  }
}

// #52: calibrate --no-forest on a forested site evaluates exactly what the
// same site without its forest evaluates; a resume must make the same
// choice (the log's fingerprint counts the stems).
TEST(CalibrateCommand, NoForestCalibratesTheSiteBare) {
  const std::string obs =
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
  const std::string forested = testing::ForestedTutorial();
  ASSERT_FALSE(forested.empty());
  const std::string args = " --observations " + obs + " --rocks 6 --seed 2 --max-evals 3 --quiet";
  const std::string bare = FreshDir("bare"), cleared = FreshDir("cleared");
  RunResult r = Rockcal("calibrate " + Example("tutorial") + args + " --out " + bare);
  ASSERT_EQ(r.status, 0) << r.err;
  r = Rockcal("calibrate " + forested + args + " --no-forest --out " + cleared);
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<nlohmann::json> a = LogWithoutTimes(bare + "/evaluations.jsonl");
  std::vector<nlohmann::json> b = LogWithoutTimes(cleared + "/evaluations.jsonl");
  ASSERT_GT(a.size(), 1u);
  EXPECT_EQ(a[0]["fingerprint"].count("forest stems"), 0u) << a[0].dump();
  EXPECT_EQ(b[0]["fingerprint"].count("forest stems"), 0u) << b[0].dump();
  a.erase(a.begin()), b.erase(b.begin());  // the headers hash different site files
  EXPECT_EQ(a, b);
  EXPECT_FALSE(fs::exists(cleared + "/tree_impacts.csv"));

  r = Rockcal("calibrate " + forested + args + " --resume --out " + cleared);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("forest stems"));
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
