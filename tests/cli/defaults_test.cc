// The library owns the defaults of every command (docs/architecture.md):
// a command run without an option gives what it gives with that option set
// to its options struct's default. calibrate has its own, end-to-end check
// against calibrate::Calibrate (calibrate_command_test.cc); this one covers
// simulate, score, sensitivity, the three studies and table.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/default_table.h"
#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/core/scene.h"

namespace rockcal::cli {
namespace {

using testing::Example;
using testing::FreshDir;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

const std::string kObservations =
    std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";

// The differences between two JSON results but those of wall time (keys
// with "seconds", "wall" or "per_second", and the one-line summary that
// quotes them), as "path: a -> b" lines.
std::string Differences(const nlohmann::json& a, const nlohmann::json& b) {
  std::string out;
  for (const nlohmann::json& op : nlohmann::json::diff(a, b)) {
    const std::string path = op["path"].get<std::string>();
    if (path.find("seconds") != std::string::npos || path.find("wall") != std::string::npos ||
        path.find("per_second") != std::string::npos || path == "/summary")
      continue;
    const nlohmann::json::json_pointer at(path);
    out += path + ": " + (a.contains(at) ? a[at].dump() : "(none)") + " -> " +
           (b.contains(at) ? b[at].dump() : "(none)") + "\n";
  }
  return out;
}

// The names of the files in folder `dir`, sorted.
std::string Files(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.insert(entry.path().filename().string());
  std::string out;
  for (const std::string& n : names) out += n + " ";
  return out;
}

// `file` of the command `args` run without and with `defaults` (its
// options at their structs' values), and the files written: the two runs
// must give the same. (A seed
// left out is the site's, not a library default.)
void ExpectSameWithTheDefaultsGiven(const std::string& name, const std::string& args,
                                    const std::string& defaults, const std::string& file) {
  const std::string bare = FreshDir(name + "_bare"), given = FreshDir(name + "_given");
  const RunResult a = Rockcal(args + " --quiet --out " + bare);
  ASSERT_EQ(a.status, 0) << args << "\n" << a.err;
  const RunResult b = Rockcal(args + " " + defaults + " --quiet --out " + given);
  ASSERT_EQ(b.status, 0) << args << " " << defaults << "\n" << b.err;
  EXPECT_EQ(Files(bare), Files(given)) << name << ": other files with " << defaults;
  const std::string x = ReadFile(bare + "/" + file), y = ReadFile(given + "/" + file);
  ASSERT_FALSE(x.empty()) << name << ": no " << file;
  if (file.size() > 5 && file.compare(file.size() - 5, 5, ".json") == 0)
    EXPECT_EQ(Differences(nlohmann::json::parse(x), nlohmann::json::parse(y)), "")
        << name << ": " << file << " differs with " << defaults;
  else
    EXPECT_EQ(x, y) << name << ": " << file << " differs with " << defaults;
}

std::string Flag(const char* name, long value) {
  return std::string("--") + name + " " + std::to_string(value);
}

TEST(Defaults, SimulateRunsTheSimulationOptionsDefaults) {
  ExpectSameWithTheDefaultsGiven("simulate",
                                 "simulate " + Example("tutorial") + " --rocks 12 --seed 2",
                                 Flag("threads", core::SimulationOptions{}.threads) + " " +
                                     Flag("trajectories", calibrate::RecordingNeeds{}.trajectories),
                                 "summary.json");
}

TEST(Defaults, ScoreRunsTheScoreOptionsDefaults) {
  const calibrate::ScoreOptions o;
  ExpectSameWithTheDefaultsGiven(
      "score", "score " + Example("tutorial") + " --observations " + kObservations + " --rocks 12",
      Flag("threads", o.threads), "score.json");
}

TEST(Defaults, SensitivityRunsTheSensitivityOptionsDefaults) {
  const calibrate::SensitivityOptions o;
  // Two trajectories (the sample count is not the default under test here).
  ExpectSameWithTheDefaultsGiven(
      "sensitivity", "sensitivity " + Example("tutorial") + " --rocks 6 --samples 2",
      std::string("--method ") + calibrate::SensitivityMethodToString(o.method) + " " +
          Flag("threads", o.threads),
      "sensitivity.json");
}

TEST(Defaults, TheStudiesRunTheirOptionsDefaults) {
  const calibrate::StabilityOptions stability;
  ExpectSameWithTheDefaultsGiven(
      "stability", "study stability " + Example("profile2d"),
      Flag("rocks", stability.rocks) + " " + Flag("threads", stability.threads), "stability.json");
  const calibrate::ConvergenceOptions convergence;
  std::string steps;
  for (int n : convergence.steps_per_contact)
    steps += (steps.empty() ? "" : ",") + std::to_string(n);
  ExpectSameWithTheDefaultsGiven(
      "convergence", "study convergence " + Example("profile2d") + " --rock-counts 20,40",
      "--steps-per-contact " + steps + " --target " + std::to_string(convergence.target) + " " +
          Flag("bootstrap", convergence.bootstrap) + " " + Flag("threads", convergence.threads),
      "convergence.json");
  ExpectSameWithTheDefaultsGiven(
      "reach",
      "study reach " + Example("tutorial") + " --observations " + kObservations +
          " --rocks 6 --points 6",
      std::string("--design ") + calibrate::DesignKindToString(calibrate::ReachOptions{}.design),
      "reach.json");
}

TEST(Defaults, TableRunsTheDefaultTableOptionsDefaults) {
  const std::string cal = FreshDir("calibration");
  const RunResult run = Rockcal("calibrate " + Example("tutorial") + " --observations " +
                                kObservations + " --max-evals 2 --rocks 6 --quiet --out " + cal);
  ASSERT_EQ(run.status, 0) << run.err;
  ExpectSameWithTheDefaultsGiven(
      "table", "table " + cal,
      "--bound-tolerance " + std::to_string(calibrate::DefaultTableOptions{}.bound_fraction),
      "table.json");
}

}  // namespace
}  // namespace rockcal::cli
