// rockcal calibrate end to end: resuming a stopped calibration, and refusing
// to when what determines its evaluations changed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// A copy of the tutorial example (site, points, observations) in `dir`, so
// that a test may change its files.
std::string CopyTutorial(const std::string& dir) {
  const fs::path from = fs::path(ROCKCAL_SOURCE_DIR) / "sites/examples/tutorial";
  fs::create_directories(dir);
  for (const char* f : {"site.json", "points.csv", "observations.json"})
    fs::copy_file(from / f, fs::path(dir) / f, fs::copy_options::overwrite_existing);
  return dir;
}

std::string Calibrate(const std::string& site_dir, const std::string& out, int evals,
                      const std::string& extra = "") {
  return site_dir + "/site.json --observations " + site_dir +
         "/observations.json --rocks 4 --reach 0 --seed 2 --max-evals " + std::to_string(evals) +
         " --quiet --out " + out + " " + extra;
}

TEST(CalibrateResume, ContinuesLikeAStraightRunAndRefusesChangedInputs) {
  const std::string site = CopyTutorial(FreshDir("site"));
  const std::string straight = FreshDir("straight"), stopped = FreshDir("stopped");
  RunResult r = Rockcal("calibrate " + Calibrate(site, straight, 5));
  ASSERT_EQ(r.status, 0) << r.err;
  // A calibration stopped after 3 evaluations, resumed with the full budget.
  r = Rockcal("calibrate " + Calibrate(site, stopped, 3));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string log = stopped + "/evaluations.jsonl";
  const std::string first_line = ReadFile(log).substr(0, ReadFile(log).find('\n'));
  EXPECT_THAT(first_line, HasSubstr("\"fingerprint\""));
  EXPECT_THAT(first_line, HasSubstr("\"observations file\""));
  EXPECT_THAT(first_line, HasSubstr("\"site data file points.csv\""));  // Site::inputs
  r = Rockcal("calibrate " + Calibrate(site, stopped, 5, "--resume"));
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json a = ReadJson(straight + "/parameters.json");
  const nlohmann::json b = ReadJson(stopped + "/parameters.json");
  EXPECT_EQ(a["parameters"], b["parameters"]);
  EXPECT_EQ(a["misfit"], b["misfit"]);
  const nlohmann::json cal = ReadJson(stopped + "/calibration.json");
  EXPECT_EQ(cal["methods"][0]["simulated"].get<int>(), 2) << "3 of 5 evaluations replayed";

  // The observation error changes what every evaluation computes.
  const std::string obs = ReadFile(site + "/observations.json");
  nlohmann::json changed = nlohmann::json::parse(obs);
  changed["error"]["height"] = changed["error"]["height"].get<double>() * 2;
  std::ofstream(site + "/observations.json") << changed.dump(1);
  r = Rockcal("calibrate " + Calibrate(site, stopped, 6, "--resume"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("observations"));
  EXPECT_THAT(r.err, HasSubstr("--force"));
  std::ofstream(site + "/observations.json") << obs;  // restored

  // Another seed: named too.
  r = Rockcal("calibrate " + site + "/site.json --observations " + site +
              "/observations.json --rocks 4 --reach 0 --seed 3 --max-evals 6 --quiet --resume --out " +
              stopped);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("seed"));

  // A log without the header (an older rockcal's) is refused.
  const std::string text = ReadFile(log);
  std::ofstream(log) << text.substr(text.find('\n') + 1);
  r = Rockcal("calibrate " + Calibrate(site, stopped, 6, "--resume"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("no fingerprint header"));
}

TEST(Score, CalibratedValuesScoreAsTheCalibrationDid) {
  const std::string site = CopyTutorial(FreshDir("site"));
  const std::string cal = FreshDir("cal"), score = FreshDir("score"), sim = FreshDir("sim");
  RunResult r = Rockcal("calibrate " + Calibrate(site, cal, 3));
  ASSERT_EQ(r.status, 0) << r.err;
  r = Rockcal("score " + site + "/site.json --observations " + site +
              "/observations.json --parameters " + cal +
              "/parameters.json --rocks 4 --seed 2 --quiet --out " + score);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json s = ReadJson(score + "/score.json");
  const nlohmann::json c = ReadJson(cal + "/calibration.json");
  // The same scene, rocks and seed: the same simulation and misfit.
  EXPECT_EQ(s["misfit"].get<double>(), c["misfit_after"].get<double>());
  ASSERT_EQ(s["residuals"].size(), c["fit"].size());
  EXPECT_EQ(s["residuals"][0]["residual"], c["fit"][0]["residual"]);
  const auto& o = s["outcomes"];
  EXPECT_EQ(o["stopped"].get<int>() + o["left"].get<int>() + o["timeout"].get<int>(), 4);
  for (const char* f : {"summary.json", "rocks.csv", "report.html"})
    EXPECT_TRUE(fs::exists(score + "/" + f)) << f;

  // simulate --parameters takes the same values.
  r = Rockcal("simulate " + site + "/site.json --parameters " + cal +
              "/parameters.json --rocks 4 --seed 2 --quiet --out " + sim);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(ReadFile(sim + "/rocks.csv"), ReadFile(score + "/rocks.csv"));

  // A strict reader: an unknown material names the file and the JSON path.
  nlohmann::json bad = ReadJson(cal + "/parameters.json");
  bad["parameters"][1]["material"] = "granite";
  const std::string bad_file = FreshDir("bad") + ".json";
  std::ofstream(bad_file) << bad.dump(1);
  r = Rockcal("simulate " + site + "/site.json --parameters " + bad_file + " --rocks 4 --out " +
              FreshDir("sim2"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr(bad_file));
  EXPECT_THAT(r.err, HasSubstr("$.parameters[1].material"));
  EXPECT_THAT(r.err, HasSubstr("granite"));
  bad = ReadJson(cal + "/parameters.json");
  bad["parameters"][0]["value"] = "hard";
  std::ofstream(bad_file) << bad.dump(1);
  r = Rockcal("score " + site + "/site.json --observations " + site +
              "/observations.json --parameters " + bad_file + " --rocks 4 --out " +
              FreshDir("score2"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_THAT(r.err, HasSubstr("$.parameters[0].value"));
}

TEST(CalibrateHoldout, ScoresEachFoldOnValuesItDidNotSee) {
  const std::string site = CopyTutorial(FreshDir("site"));
  const std::string out = FreshDir("out");
  const RunResult r = Rockcal("calibrate " + Calibrate(site, out, 2, "--holdout 2"));
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json h = ReadJson(out + "/holdout.json");
  EXPECT_EQ(h["folds"].get<int>(), 2);
  ASSERT_EQ(h["per_fold"].size(), 2u);
  double mean = 0.0;
  for (const auto& f : h["per_fold"]) {
    EXPECT_GT(f["held_out_values"].get<int>(), 0);
    EXPECT_GE(f["held_out_misfit"].get<double>(), 0.0);
    EXPECT_GE(f["runout_median_abs_error_m"].get<double>(), 0.0);
    mean += 0.5 * f["held_out_misfit"].get<double>();
  }
  EXPECT_NEAR(h["mean_held_out_misfit"].get<double>(), mean, 1e-9 * (1 + mean));
  EXPECT_TRUE(h["repeat_scatter"].is_null()) << "no tracked runs, so no repeats";
  EXPECT_EQ(ReadJson(out + "/calibration.json")["holdout"], h);
  EXPECT_EQ(h["in_sample_misfit"], ReadJson(out + "/calibration.json")["misfit_after"]);
  for (const char* f : {"holdout.csv", "evaluations-fold-1.jsonl", "evaluations-fold-2.jsonl"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  EXPECT_THAT(ReadFile(out + "/evaluations-fold-2.jsonl"), HasSubstr("fold 2 of 2"));

  // A run stopped within the folds resumes: the second fold's log is gone.
  fs::remove(out + "/evaluations-fold-2.jsonl");
  const RunResult resumed = Rockcal("calibrate " + Calibrate(site, out, 2, "--holdout 2 --resume"));
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_EQ(ReadJson(out + "/holdout.json"), h);

  const RunResult bad = Rockcal("calibrate " + Calibrate(site, FreshDir("bad"), 2, "--holdout 1"));
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_THAT(bad.err, HasSubstr("--holdout"));
}

}  // namespace
}  // namespace rockcal::cli
