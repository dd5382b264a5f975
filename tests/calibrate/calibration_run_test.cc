// A calibration as one call: Calibrate's summary, its options and the
// recording it asks for.
#include "rockcal/calibrate/calibration_run.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/core/error.h"
#include "rockcal/core/statistics.h"
#include "../sites/test_files.h"
#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using testing::TwinObservations;
using testing::TwinSite;

using testing::kTruth;

// #52: the forest's capacity factor is calibrated like a material value,
// through the entry "forest": the site's bounds make a parameter
// forest.capacity_factor, and applying it rescales every stem's capacity.
TEST(CalibrationRun, TheForestsCapacityFactorIsAParameterLikeAMaterialValue) {
  sites::testing::TempDir dir;
  const std::string site_text = R"({
    "name": "forest slope", "units": "si",
    "surface": {"resolution": 2, "sphere_spacing": 2,
                "points": [[0, 0, 50], [100, 0, 0], [0, 60, 50], [100, 60, 0]]},
    "materials": [{"id": "soil", "hardness": 0.3, "roughness": 0.2,
                   "calibrate": {"hardness": [0.1, 0.6]}}],
    "rocks": [{"count": 4, "shape": "sphere", "size": [0.5, 1], "unit_weight": 26,
               "release": {"zone": [[2, 20], [8, 20], [8, 40], [2, 40]]}}],
    "simulation": {"seed": 3, "max_time": 20},
    "forest": {"trees": [{"x": 50, "y": 30, "dbh_cm": 30},
                         {"x": 60, "y": 20, "dbh_cm": 12, "species": "broadleaf"}],
               "capacity_factor": CF, "calibrate": {"capacity_factor": [0.5, 2]}}
  })";
  const auto with_factor = [&](const std::string& cf) {
    std::string text = site_text;
    text.replace(text.find("CF"), 2, cf);
    return text;
  };
  const sites::Site site = sites::LoadSite(dir.Write("site.json", with_factor("1")));
  const ParameterSpace space = ParameterSpace::FromSite(site);
  ASSERT_EQ(space.size(), 2);
  const Parameter& p = space.parameters()[1];
  EXPECT_EQ(p.label(), "forest.capacity_factor");
  EXPECT_EQ(p.kind, ParameterKind::kCapacityFactor);
  EXPECT_EQ(p.lower, 0.5);
  EXPECT_EQ(p.upper, 2.0);
  EXPECT_EQ(space.Current(site.scene), (std::vector<double>{0.3, 1.0}));

  core::Scene scene = site.scene;
  space.Apply({0.4, 1.6}, &scene);
  EXPECT_EQ(scene.materials[0].hardness, 0.4);
  EXPECT_EQ(scene.forest.capacity_factor, 1.6);
  ASSERT_EQ(scene.forest.stems.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const core::Stem& s = scene.forest.stems[k];
    EXPECT_EQ(s.capacity, core::StemCapacity(s.dbh, s.species, 1.6)) << "stem " << k;
    EXPECT_NEAR(s.capacity, 1.6 * site.scene.forest.stems[k].capacity,
                1e-12 * s.capacity)
        << "stem " << k;
  }
  EXPECT_EQ(space.Current(scene), (std::vector<double>{0.4, 1.6}));

  // parameters.json and --set reach it through the same entry.
  std::string message;
  EXPECT_EQ(sites::SetMaterialValue("forest", "capacity_factor", 0.8, sites::Units::kSI, &scene,
                                    &message),
            sites::MaterialValueFault::kNone)
      << message;
  EXPECT_EQ(scene.forest.stems[0].capacity, core::StemCapacity(0.30, core::SpeciesClass::kConifer, 0.8));
  EXPECT_EQ(sites::SetMaterialValue("soil", "capacity_factor", 0.8, sites::Units::kSI, &scene,
                                    &message),
            sites::MaterialValueFault::kField);
  EXPECT_THAT(message, HasSubstr("a value of the forest (forest.capacity_factor)"));
  EXPECT_EQ(sites::SetMaterialValue("forest", "capacity_factor", 200, sites::Units::kSI, &scene,
                                    &message),
            sites::MaterialValueFault::kValue);
  EXPECT_THAT(message, HasSubstr("expected a capacity factor in [0.01, 100]"));
  core::Scene bare = site.scene;
  bare.forest = core::Forest{};
  EXPECT_EQ(sites::SetMaterialValue("forest", "capacity_factor", 0.8, sites::Units::kSI, &bare,
                                    &message),
            sites::MaterialValueFault::kMaterial);

  // Bounds that leave out the site's value are refused, naming the key.
  sites::testing::TempDir bad;
  const std::string error = sites::testing::ErrorOf(
      [&] { sites::LoadSite(bad.Write("site.json", with_factor("3"))); });
  EXPECT_THAT(error, HasSubstr("$.forest.calibrate.capacity_factor"));
  EXPECT_THAT(error, HasSubstr("the forest's capacity_factor 3 is outside its calibrate bounds"));
}

// #52: the trunk contact's restitution and friction are calibrated as the
// capacity factor is: parameters forest.contact_restitution and
// forest.contact_friction, applied on the forest's contact law.
TEST(CalibrationRun, TheTrunkContactsRestitutionAndFrictionAreParametersLikeTheCapacityFactor) {
  sites::testing::TempDir dir;
  const sites::Site site = sites::LoadSite(dir.Write("site.json", R"({
    "name": "forest slope", "units": "si",
    "surface": {"resolution": 2, "sphere_spacing": 2,
                "points": [[0, 0, 50], [100, 0, 0], [0, 60, 50], [100, 60, 0]]},
    "materials": [{"id": "soil", "hardness": 0.3, "roughness": 0.2}],
    "rocks": [{"count": 4, "shape": "sphere", "size": [0.5, 1], "unit_weight": 26,
               "release": {"zone": [[2, 20], [8, 20], [8, 40], [2, 40]]}}],
    "simulation": {"seed": 3, "max_time": 20},
    "forest": {"trees": [{"x": 50, "y": 30, "dbh_cm": 30}],
               "contact": {"restitution": 0.3, "friction": 0.5},
               "calibrate": {"contact_restitution": [0.1, 0.6],
                             "contact_friction": [0.2, 0.9]}}
  })"));
  const ParameterSpace space = ParameterSpace::FromSite(site);
  ASSERT_EQ(space.size(), 2);
  EXPECT_EQ(space.parameters()[0].label(), "forest.contact_restitution");
  EXPECT_EQ(space.parameters()[0].kind, ParameterKind::kTrunkRestitution);
  EXPECT_EQ(space.parameters()[1].label(), "forest.contact_friction");
  EXPECT_EQ(space.parameters()[1].upper, 0.9);
  EXPECT_EQ(space.Current(site.scene), (std::vector<double>{0.3, 0.5}));
  core::Scene scene = site.scene;
  space.Apply({0.45, 0.7}, &scene);
  EXPECT_EQ(scene.forest.contact.restitution, 0.45);
  EXPECT_EQ(scene.forest.contact.friction, 0.7);
  EXPECT_EQ(scene.forest.Law().restitution, 0.45);  // what the strikes use
  EXPECT_EQ(scene.forest.Law().friction, 0.7);
  EXPECT_EQ(space.Current(scene), (std::vector<double>{0.45, 0.7}));
  std::string message;
  EXPECT_EQ(sites::SetMaterialValue("forest", "contact_restitution", 1.5, sites::Units::kSI,
                                    &scene, &message),
            sites::MaterialValueFault::kValue);
  EXPECT_THAT(message, HasSubstr("expected a trunk restitution in [0.01, 0.99]"));
  EXPECT_EQ(sites::SetMaterialValue("soil", "contact_friction", 0.4, sites::Units::kSI, &scene,
                                    &message),
            sites::MaterialValueFault::kField);
  sites::testing::TempDir bad;
  const std::string error = sites::testing::ErrorOf([&] {
    sites::LoadSite(bad.Write("site.json", R"({
      "name": "s", "units": "si",
      "surface": {"resolution": 2, "points": [[0, 0, 50], [100, 0, 0], [0, 60, 50], [100, 60, 0]]},
      "materials": [{"id": "soil", "hardness": 0.3, "roughness": 0.2}],
      "rocks": [{"count": 4, "shape": "sphere", "size": [0.5, 1], "unit_weight": 26,
                 "release": {"zone": [[2, 20], [8, 20], [8, 40], [2, 40]]}}],
      "forest": {"trees": [{"x": 50, "y": 30, "dbh_cm": 30}],
                 "calibrate": {"contact_restitution": [0, 0.5]}}
    })"));
  });
  EXPECT_THAT(error, HasSubstr("$.forest.calibrate.contact_restitution"));
  EXPECT_THAT(error, HasSubstr("expected bounds within [0.01, 0.99]"));
}

TEST(CalibrationRun, SummaryHoldsTheBestMethodAndItsSimulation) {
  const sites::Site site = TwinSite(6);
  const observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.methods = {Method::kBobyqa, Method::kSbplx};
  options.method.max_evals = 4;
  options.seed = 3;
  int started = 0, evaluated = 0, finished = 0;
  CalibrationCallbacks callbacks;
  callbacks.started = [&](const CalibrationSummary& s) {
    ++started;
    EXPECT_EQ(s.start.size(), 4u);
    EXPECT_GT(s.misfit_before.value, 0.0);
  };
  callbacks.evaluated = [&](const Evaluation&, double) { ++evaluated; };
  callbacks.method_finished = [&](const MethodResult&) { ++finished; };
  const CalibrationSummary s = Calibrate(site, obs, options, callbacks);
  EXPECT_EQ(started, 1);
  EXPECT_EQ(finished, 2);
  EXPECT_EQ(evaluated, s.methods[0].evaluations + s.methods[1].evaluations);
  ASSERT_EQ(s.methods.size(), 2u);
  EXPECT_LE(s.best_method().best_misfit, s.methods[0].best_misfit);
  EXPECT_LE(s.best_method().best_misfit, s.methods[1].best_misfit);
  EXPECT_EQ(s.seed, 3u);
  EXPECT_EQ(s.rocks, 6);
  EXPECT_EQ(s.termination.type, s.best_method().termination.type);
  EXPECT_EQ(s.termination.message, s.best_method().termination.message);
  // Four evaluations of a budget of four: the budget ran out.
  EXPECT_EQ(s.termination.type, TerminationType::kBudgetUsed) << s.termination.message;
  // The calibrated scene carries the best values; its simulation was
  // recorded for the report, and the misfit after is that simulation's.
  const std::vector<double> values = s.space.Current(s.calibrated);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(values[k], s.best_method().best[k], 1e-12) << k;
  EXPECT_EQ(s.calibrated.options.record.trajectories, 0);
  EXPECT_EQ(static_cast<int>(s.simulation.rocks.size()), 6);
  EXPECT_FALSE(s.simulation.rocks[0].trajectory.empty());
  EXPECT_FALSE(s.misfit_after.residuals.empty());
  EXPECT_EQ(s.misfit_before.residuals.size(), s.misfit_after.residuals.size());
  EXPECT_THAT(s.BriefReport(), HasSubstr("budget used"));
}

TEST(CalibrationRun, RefiningStageSearchesOnWithMoreRocksAndNoiseIsMeasured) {
  const sites::Site site = TwinSite(6);
  const observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.method.max_evals = 12;
  options.seed = 3;
  options.refine_factor = 3;
  options.noise_seeds = 2;
  const CalibrationSummary s = Calibrate(site, obs, options);
  // Two thirds of the budget at 6 rocks, a third at 18 from the first's best.
  ASSERT_EQ(s.methods.size(), 2u);
  EXPECT_EQ(s.methods[0].evaluations, 8);
  EXPECT_EQ(s.methods[1].evaluations, 4);
  EXPECT_EQ(s.methods[1].stage.name(), "nlopt:bobyqa (18 rocks)");
  EXPECT_EQ(s.methods[1].stage.method, Method::kBobyqa);
  EXPECT_EQ(s.methods[1].stage.rocks, 18);
  EXPECT_EQ(s.best, 1);
  EXPECT_EQ(s.methods[1].trace.front().parameters, s.methods[0].best);
  EXPECT_EQ(s.rocks, 6);
  EXPECT_EQ(s.final_rocks, 18);
  EXPECT_EQ(static_cast<int>(s.simulation.rocks.size()), 18);
  // The final simulation is the refined values' at the refining stage's
  // rocks and seed: its misfit is the one the search found there.
  EXPECT_DOUBLE_EQ(s.misfit_after.value, s.methods[1].best_misfit);
  // The misfit before is the start's at those rocks too: the refining
  // stage's first evaluation is the first stage's best, not the start.
  EXPECT_EQ(s.misfit_before.residuals.size(), s.misfit_after.residuals.size());
  // The same values at seeds 4 and 5, and the spread of the three misfits.
  ASSERT_EQ(s.noise_seeds, (std::vector<std::uint64_t>{4, 5}));
  ASSERT_EQ(s.noise_misfits.size(), 2u);
  const double m[3] = {s.misfit_after.value, s.noise_misfits[0], s.noise_misfits[1]};
  const double mean = (m[0] + m[1] + m[2]) / 3;
  double ss = 0.0;
  for (double v : m) ss += (v - mean) * (v - mean);
  EXPECT_NEAR(s.misfit_noise_sd, std::sqrt(ss / 2), 1e-12);
  EXPECT_GT(s.misfit_noise_sd, 0.0);
  // A fixed rock count (refine_factor 1) is one stage.
  options.refine_factor = 1;
  options.noise_seeds = 0;
  const CalibrationSummary one = Calibrate(site, obs, options);
  EXPECT_EQ(one.methods.size(), 1u);
  EXPECT_EQ(one.final_rocks, 6);
  EXPECT_TRUE(one.noise_seeds.empty());
}

// The race before the refining stage: the first stage's best, the start
// and the design's lowest points simulated at the refining rocks; the
// refining search starts from the lowest of them.
TEST(CalibrationRun, RefiningStartsFromTheRaceWinner) {
  const sites::Site site = TwinSite(6);
  const observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.method.max_evals = 9;
  options.seed = 3;
  options.refine_factor = 2;
  options.reach_points = 6;
  options.race_points = 2;
  const CalibrationSummary s = Calibrate(site, obs, options);
  ASSERT_TRUE(s.reach.has_value());
  ASSERT_EQ(s.race.size(), 4u);
  EXPECT_EQ(s.race[0].from, "first stage");
  EXPECT_EQ(s.race[0].physical, s.methods[0].best);
  EXPECT_DOUBLE_EQ(s.race[0].misfit_before, s.methods[0].best_misfit);
  EXPECT_EQ(s.race[1].from, "start");
  EXPECT_EQ(s.race[1].physical, s.start);
  // The start at the refining rocks and seed is the misfit before.
  EXPECT_DOUBLE_EQ(s.race[1].misfit, s.misfit_before.value);
  // The design points in the order of their design misfit, none lower left out.
  const std::vector<ReachPoint>& points = s.reach->points;
  for (int k : {2, 3}) {
    ASSERT_EQ(s.race[k].from.rfind("design point ", 0), 0u) << s.race[k].from;
    const std::size_t index = std::stoul(s.race[k].from.substr(13)) - 1;
    EXPECT_EQ(s.race[k].physical, points[index].physical);
    EXPECT_DOUBLE_EQ(s.race[k].misfit_before, points[index].misfit);
  }
  EXPECT_LE(s.race[2].misfit_before, s.race[3].misfit_before);
  int below = 0;
  for (const ReachPoint& p : points) below += !p.penalised && p.misfit < s.race[3].misfit_before;
  EXPECT_LE(below, 1);
  // The winner is the lowest at the refining rocks, and the refining
  // search's first evaluation, except that BOBYQA moves a start lying within
  // its first step (refine_step of the range) of a bound inward, by at most
  // that step.
  ASSERT_GE(s.race_winner, 0);
  for (const auto& entry : s.race) EXPECT_LE(s.race[s.race_winner].misfit, entry.misfit);
  const std::vector<double>& first = s.methods[1].trace.front().parameters;
  const std::vector<double>& winner = s.race[s.race_winner].physical;
  const ParameterSpace space = ParameterSpace::FromSite(site);
  ASSERT_EQ(first.size(), winner.size());
  bool moved = false;
  for (std::size_t k = 0; k < first.size(); ++k) {
    const Parameter& p = space.parameters()[k];
    const double step = options.refine_step * (p.upper - p.lower);
    if (first[k] == winner[k]) continue;
    moved = true;
    EXPECT_LE(std::abs(first[k] - winner[k]), step + 1e-12) << p.label();
    EXPECT_LT(std::min(winner[k] - p.lower, p.upper - winner[k]), step) << p.label();
    EXPECT_LT(std::abs(first[k] - 0.5 * (p.lower + p.upper)),
              std::abs(winner[k] - 0.5 * (p.lower + p.upper)))
        << p.label() << ": moved inward";
  }
  if (!moved) {
    EXPECT_DOUBLE_EQ(s.methods[1].trace.front().misfit, s.race[s.race_winner].misfit);
  }
  // No race: the first stage's best starts it, and nothing is raced.
  options.race_points = 0;
  const CalibrationSummary plain = Calibrate(site, obs, options);
  EXPECT_TRUE(plain.race.empty());
  EXPECT_EQ(plain.race_winner, -1);
  EXPECT_EQ(plain.methods[1].trace.front().parameters, plain.methods[0].best);
}

// The tutorial example (a log's fingerprint hashes the site's files), and
// one stage at 4 rocks and seed 3 with a log in `dir`.
struct Tutorial {
  static std::string Dir() { return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/"; }
  sites::Site site = sites::LoadSite(Dir() + "site.json");
  observations::Observations obs =
      observations::LoadObservations(Dir() + "observations.json", site.scene);
  static CalibrationOptions LoggedOptions(const sites::testing::TempDir& dir, int max_evals) {
    CalibrationOptions options = CalibrationOptions::SingleStage();
    options.rocks = 4;
    options.method.max_evals = max_evals;
    options.seed = 3;
    options.log_path = dir.path() + "/evaluations.jsonl";
    return options;
  }
};

// A calibration stopped anywhere in its refining stage (its log cut short,
// or not yet begun) and resumed ends where a straight run ends.
TEST(CalibrationRun, ResumesAcrossTheRefiningStage) {
  const Tutorial tutorial;
  const sites::Site& site = tutorial.site;
  const observations::Observations& obs = tutorial.obs;
  sites::testing::TempDir dir;
  CalibrationOptions options = Tutorial::LoggedOptions(dir, 12);
  options.refine_factor = 2;
  options.noise_seeds = 0;  // the noise runs are not logged: nothing to resume
  const CalibrationSummary straight = Calibrate(site, obs, options);
  const std::string refine_log = dir.path() + "/evaluations-refine.jsonl";
  ASSERT_TRUE(std::filesystem::exists(refine_log));
  std::string text;
  {
    std::ifstream in(refine_log);
    std::ostringstream all;
    all << in.rdbuf();
    text = all.str();
  }
  // Cut after the fingerprint and two evaluations; then with no refining log.
  std::size_t cut = 0;
  for (int line = 0; line < 3; ++line) cut = text.find('\n', cut) + 1;
  for (const std::string& kept : {text.substr(0, cut), std::string()}) {
    if (kept.empty())
      std::filesystem::remove(refine_log);
    else
      std::ofstream(refine_log, std::ios::binary | std::ios::trunc) << kept;
    CalibrationOptions again = options;
    again.resume = true;
    const CalibrationSummary resumed = Calibrate(site, obs, again);
    ASSERT_EQ(resumed.methods.size(), 2u);
    EXPECT_EQ(resumed.methods[0].simulated, 0);  // the first stage all replayed
    EXPECT_EQ(resumed.methods[1].evaluations, straight.methods[1].evaluations);
    EXPECT_EQ(resumed.best_method().best, straight.best_method().best);
    EXPECT_EQ(resumed.misfit_after.value, straight.misfit_after.value);
  }
}

// Issue 38: when the noise check finds the noise dominant, the search runs
// at a whole multiple of the rocks, the one that brings the ratio down or
// noise_raise times at most; its log resumes at the raised count. With
// noise_raise 1 the check only says how many rocks are needed.
TEST(CalibrationRun, DominantNoiseRaisesTheRocks) {
  const Tutorial tutorial;
  const sites::Site& site = tutorial.site;
  const observations::Observations& obs = tutorial.obs;
  sites::testing::TempDir dir;
  CalibrationOptions options = Tutorial::LoggedOptions(dir, 4);
  options.reach_points = 6;
  options.noise_check_seeds = 2;
  options.noise_check_ratio = 0.01;  // far below any Monte Carlo noise at 4 rocks
  options.noise_raise = 3;
  const CalibrationSummary s = Calibrate(site, obs, options);
  const CalibrationSummary::NoiseCheck& c = s.noise_check;
  ASSERT_TRUE(c.done);
  ASSERT_TRUE(c.noise_dominates) << c.message;
  const double factor = std::pow(c.ratio / 0.01, 2.0);
  EXPECT_EQ(c.rocks_needed, static_cast<int>(std::ceil(4 * std::min(factor, 100.0))));
  EXPECT_EQ(c.rocks_checked, 4);
  EXPECT_EQ(c.rocks_used, 4 * std::min(3, static_cast<int>(std::ceil(std::min(factor, 100.0)))));
  ASSERT_EQ(c.rocks_used, 12) << c.message;
  EXPECT_TRUE(c.still_dominates());
  EXPECT_THAT(c.message, HasSubstr("raised from 4 to 12 (3 times)"));
  EXPECT_THAT(c.message, HasSubstr("--rocks " + std::to_string(c.rocks_needed)));
  EXPECT_EQ(s.rocks, 12);
  EXPECT_EQ(s.final_rocks, 12);
  EXPECT_EQ(s.simulation.rocks.size(), 12u);
  EXPECT_EQ(s.misfit_before.residuals.size(), s.misfit_after.residuals.size());
  // The log was written at 12 rocks: a resume replays every evaluation.
  CalibrationOptions again = options;
  again.resume = true;
  const CalibrationSummary resumed = Calibrate(site, obs, again);
  EXPECT_EQ(resumed.methods[0].simulated, 0);
  EXPECT_EQ(resumed.best_method().best, s.best_method().best);
  EXPECT_EQ(resumed.misfit_after.value, s.misfit_after.value);
  // Never raised: the same check, the search at 4 rocks, the advice kept.
  options.noise_raise = 1;
  options.log_path.clear();
  const CalibrationSummary kept = Calibrate(site, obs, options);
  EXPECT_EQ(kept.noise_check.ratio, c.ratio);
  EXPECT_EQ(kept.noise_check.rocks_used, 4);
  EXPECT_EQ(kept.rocks, 4);
  EXPECT_EQ(kept.simulation.rocks.size(), 4u);
  EXPECT_THAT(kept.noise_check.message, Not(HasSubstr("raised")));
  EXPECT_THAT(kept.noise_check.message, HasSubstr("would bring the ratio to 0.01"));
  options.noise_raise = 0;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("noise_raise = 0"));
}

TEST(CalibrationRun, OptionsAreChecked) {
  CalibrationOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.methods = {static_cast<Method>(99)};
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("methods: unknown method 99 (allowed: nlopt:bobyqa, "));
  o = CalibrationOptions{};
  o.methods.clear();
  EXPECT_FALSE(o.IsValid(&error));
  o = CalibrationOptions{};
  o.rocks = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("rocks = -1"));
  o = CalibrationOptions{};
  o.resume = true;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("log_path"));
  o = CalibrationOptions{};
  o.race_points = -2;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("race_points = -2"));
  o = CalibrationOptions{};
  o.refine_factor = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("refine_factor = 0"));
  o = CalibrationOptions{};
  o.refine_share = 1.0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("refine_share = 1"));
  o = CalibrationOptions{};
  o.noise_seeds = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("noise_seeds = -1"));
  o = CalibrationOptions{};
  o.method.max_evals = 1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("max_evals = 1"));
  sites::Site no_bounds = TwinSite(2);
  no_bounds.calibrate.clear();
  EXPECT_THROW(CheckCalibration(no_bounds, CalibrationOptions{}), InputError);
}

TEST(Recording, EachReaderAddsWhatItNeeds) {
  const sites::Site site = TwinSite(50);
  const observations::Observations obs = TwinObservations(TwinSite(10), kTruth, 5);
  RecordingNeeds none;
  const core::RecordOptions bare = RecordingFor(site.scene, none);
  EXPECT_FALSE(bare.partitions);
  EXPECT_FALSE(bare.energy_check);
  EXPECT_FALSE(bare.passages);
  EXPECT_EQ(bare.trajectories, 0);
  RecordingNeeds misfit;
  misfit.observations = &obs;  // scar heights at partitions
  EXPECT_TRUE(RecordingFor(site.scene, misfit).partitions);
  RecordingNeeds report;
  report.report = true;
  const core::RecordOptions r = RecordingFor(site.scene, report);
  EXPECT_TRUE(r.passages);
  // 30 of the 50 rocks, spread over every group, not the first 30.
  EXPECT_EQ(r.trajectories, 0);
  std::vector<int> counts;
  for (const core::RockGroup& g : site.scene.groups) counts.push_back(g.count);
  EXPECT_EQ(r.trajectory_rocks, core::SpreadOverGroups(counts, 30));
  EXPECT_EQ(r.trajectory_rocks.size(), 30u);
  report.trajectories = 5;  // asked for: kept
  report.sample_seconds = 0.2;
  EXPECT_EQ(RecordingFor(site.scene, report).trajectories, 5);
  EXPECT_EQ(RecordingFor(site.scene, report).sample_seconds, 0.2);
}

TEST(Objective, ResidualCountComesFromTheObservations) {
  const sites::Site site = TwinSite(4);
  const observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  const Objective objective(site.scene, ParameterSpace::FromSite(site), obs, {});
  // Two scar sets and the runout distance and lateral offset: 4 x (9 + max),
  // and the share of rocks that stopped.
  EXPECT_EQ(objective.residual_count(), 41);
}

}  // namespace
}  // namespace rockcal::calibrate

namespace rockcal::calibrate {
namespace {

// The library owns the defaults `rockcal calibrate` runs: a reach design
// of DefaultReachPoints, a refining stage at 4 times the rocks with a race
// of the best twelfth of the design (at least 2), the noise from 3 seeds
// and the noise check at 3; the automatic fields resolve per run.
TEST(CalibrationOptions, DefaultsResolvePerRun) {
  const CalibrationOptions o;
  EXPECT_EQ(o.refine_factor, 4);
  EXPECT_EQ(o.noise_seeds, 3);
  EXPECT_EQ(o.noise_check_seeds, 3);
  EXPECT_EQ(o.method.max_evals, 100);
  const CalibrationOptions r = o.Resolved(2);
  EXPECT_EQ(r.reach_points, 50) << "half of 100 evaluations";
  EXPECT_EQ(r.race_points, 4) << "50 / 12";
  CalibrationOptions small;
  small.method.max_evals = 6;
  EXPECT_EQ(small.Resolved(1).reach_points, 8) << "4 (n + 1)";
  EXPECT_EQ(small.Resolved(1).race_points, 2) << "at least 2";
  small.refine_factor = 1;
  EXPECT_EQ(small.Resolved(1).race_points, 0) << "no race without a refining stage";
  small.reach_points = 0;
  small.race_points = 5;
  EXPECT_EQ(small.Resolved(1).reach_points, 0) << "given values are kept";
  EXPECT_EQ(small.Resolved(1).race_points, 5) << "given values are kept";
  const CalibrationOptions one = CalibrationOptions::SingleStage();
  EXPECT_EQ(one.Resolved(3).reach_points, 0);
  EXPECT_EQ(one.refine_factor, 1);
  EXPECT_EQ(one.Resolved(3).race_points, 0);
  EXPECT_EQ(one.noise_seeds + one.noise_check_seeds, 0);
}

// Issue 38: the reach design, the global stage, grows with the evaluation
// budget: 4 (n + 1) points or half of max_evals, whichever is more.
TEST(CalibrationOptions, DefaultReachDesignGrowsWithTheBudget) {
  EXPECT_EQ(CalibrationOptions::DefaultReachPoints(2, 10), 12);
  EXPECT_EQ(CalibrationOptions::DefaultReachPoints(2, 60), 30);
  EXPECT_EQ(CalibrationOptions::DefaultReachPoints(2, 100), 50);
  EXPECT_EQ(CalibrationOptions::DefaultReachPoints(9, 63), 40);  // the Authume main job, as before
  CalibrationOptions o;
  std::string error;
  o.noise_check_seeds = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("noise_check_seeds = -1"), std::string::npos) << error;
  o.noise_check_seeds = 3;
  o.noise_check_ratio = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("noise_check_ratio = 0"), std::string::npos) << error;
}

// A dip of the own seed's noise: below the others' one-sided 97.5 %
// prediction bound. Others 9.0, 9.17, 9.09: mean 9.0867, sd 0.085049,
// t(2) 4.303, bound 9.0867 - 4.303 * 0.085049 * sqrt(4 / 3) = 8.6641.
TEST(NoiseDip, BelowTheOtherSeedsPredictionBound) {
  EXPECT_FALSE(NoiseDip(8.70, {9.0, 9.17, 9.09}));
  EXPECT_TRUE(NoiseDip(8.66, {9.0, 9.17, 9.09}));
  EXPECT_TRUE(NoiseDip(14.6, {53.0, 45.9, 45.0}));
  EXPECT_FALSE(NoiseDip(40.0, {53.0, 45.9, 45.0}));
  EXPECT_FALSE(NoiseDip(1.0, {53.0})) << "one other seed gives no spread";
  EXPECT_FALSE(NoiseDip(1.0, {}));
}

// The noise check's yardstick is the spread among the design's best quarter
// (at least 4 points): a far point changes nothing, and with fewer than 4
// points all count.
TEST(NoiseCheck, ComparesWithTheSpreadOfTheDesignsBestQuarter) {
  std::vector<double> design;
  for (int i = 40; i >= 1; --i) design.push_back(i);  // 1 ... 40, unsorted
  ContenderSpread s = SpreadOfContenders(design);
  EXPECT_EQ(s.points, 10);
  // 1 ... 10: variance (10^2 - 1) / 12 * 10 / 9 = 9.1667.
  EXPECT_NEAR(s.spread, std::sqrt(55.0 / 6.0), 1e-12);
  design.push_back(1e6);  // a far point: 41 misfits, the best 11
  s = SpreadOfContenders(design);
  EXPECT_EQ(s.points, 11);
  EXPECT_NEAR(s.spread, std::sqrt(11.0), 1e-12);  // 1 ... 11: (121 - 1) / 12 * 11 / 10
  s = SpreadOfContenders({5.0, 1.0, 3.0});
  EXPECT_EQ(s.points, 3);
  EXPECT_NEAR(s.spread, 2.0, 1e-12);
  s = SpreadOfContenders({7.0});
  EXPECT_EQ(s.points, 0);
  EXPECT_EQ(s.spread, 0.0);
}

}  // namespace
}  // namespace rockcal::calibrate
