// Calibration bookkeeping: resume, the evaluation log, budgets, penalties and
// options (the twin experiments are in twin_heavy_test.cc).
#include "rockcal/calibrate/calibration.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using ::testing::HasSubstr;
using testing::TwinObservations;
using testing::TwinSite;

// Known values inside the bounds (slope hardness, slope roughness, runout
// hardness, runout roughness).
const std::vector<double> kTruth = {0.65, 0.25, 0.2, 0.45};

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "/rockcal_calibration_" + name;
}

// A small, quick objective for the bookkeeping tests (they also run under
// the sanitizers): few rocks.
struct Small {
  sites::Site site = TwinSite(6);
  ParameterSpace space = ParameterSpace::FromSite(site);
  observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  Objective objective{site.scene, space, obs, {}};
};

TEST(Calibration, ResumeEndsLikeAStraightRunWithFewerSimulations) {
  Small small;
  MethodOptions options;
  options.max_evals = 14;
  const std::string straight_log = TempPath("straight.jsonl");
  EvaluationLog straight_log_file(straight_log, false, small.space, 1, 6);
  const MethodResult straight = RunMethod("nlopt:bobyqa", small.objective,
                                          small.space.Current(small.site.scene), options,
                                          &straight_log_file);
  // Stop after k = 6 evaluations, then resume with the full budget.
  const std::string log_path = TempPath("resumed.jsonl");
  MethodOptions first = options;
  first.max_evals = 6;
  {
    EvaluationLog log(log_path, false, small.space, 1, 6);
    RunMethod("nlopt:bobyqa", small.objective, small.space.Current(small.site.scene), first, &log);
  }
  EvaluationLog log(log_path, true, small.space, 1, 6);
  EXPECT_EQ(log.size(), 6);
  const MethodResult resumed = RunMethod("nlopt:bobyqa", small.objective,
                                         small.space.Current(small.site.scene), options, &log);
  EXPECT_EQ(resumed.best, straight.best);
  EXPECT_EQ(resumed.best_misfit, straight.best_misfit);
  EXPECT_EQ(resumed.evaluations, straight.evaluations);
  EXPECT_EQ(resumed.simulated, straight.simulated - 6);
  for (std::size_t k = 0; k < resumed.trace.size(); ++k) {
    EXPECT_EQ(resumed.trace[k].parameters, straight.trace[k].parameters) << "evaluation " << k + 1;
    EXPECT_EQ(resumed.trace[k].replayed, k < 6);
  }
}

TEST(Calibration, LogOfAnotherCalibrationIsRefused) {
  Small small;
  const std::string path = TempPath("other.jsonl");
  {
    EvaluationLog log(path, false, small.space, 1, 6);
    MethodOptions options;
    options.max_evals = 2;
    RunMethod("nlopt:sbplx", small.objective, small.space.Current(small.site.scene), options, &log);
  }
  try {
    EvaluationLog log(path, true, small.space, 7, 6);  // another seed
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ":1"));
    EXPECT_THAT(e.what(), HasSubstr("another calibration"));
  }
  std::ofstream(path, std::ios::app) << "{\"method\": \"nlopt:sb";  // a torn last line
  EvaluationLog log(path, true, small.space, 1, 6);
  EXPECT_EQ(log.size(), 2);
}

TEST(Calibration, EveryMethodRunsWithinItsBudget) {
  Small small;
  MethodOptions options;
  options.max_evals = 5;
  for (const std::string& method : MethodNames()) {
    const MethodResult r =
        RunMethod(method, small.objective, small.space.Current(small.site.scene), options, nullptr);
    EXPECT_LE(r.evaluations, 5) << method;
    EXPECT_GE(r.evaluations, 2) << method;
    EXPECT_TRUE(std::isfinite(r.best_misfit)) << method;
    EXPECT_EQ(r.best.size(), 4u) << method;
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(r.best[k], small.space.parameters()[k].lower) << method;
      EXPECT_LE(r.best[k], small.space.parameters()[k].upper) << method;
    }
  }
  EXPECT_THROW(RunMethod("nlopt:nope", small.objective, small.space.Current(small.site.scene),
                         options, nullptr),
               InputError);
}

TEST(Calibration, NonFiniteSimulationIsAFinitePenalty) {
  Small small;
  core::Scene scene = small.site.scene;
  scene.groups[0].release.zone.clear();
  scene.groups[0].release.point = Eigen::Vector2d(-100, -100);  // off the grid: every rock leaves
  Objective objective(scene, small.space, small.obs, {});
  const observations::Misfit m = objective.Evaluate(small.space.Current(scene));
  EXPECT_TRUE(std::isfinite(m.value));
  EXPECT_TRUE(m.penalised);
  EXPECT_EQ(static_cast<int>(m.residuals.size()), objective.residual_count());
  for (const auto& r : m.residuals) EXPECT_TRUE(std::isfinite(r.value));
}

TEST(Calibration, OptionsAreChecked) {
  MethodOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error));
  o.max_evals = 1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("max_evals = 1"));
  o = MethodOptions{};
  o.ceres_loss = "l1";
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("none, huber or cauchy"));
}

TEST(ParameterSpace, UnitBoxRoundTripAndApply) {
  const sites::Site site = TwinSite(4);
  const ParameterSpace space = ParameterSpace::FromSite(site);
  ASSERT_EQ(space.size(), 4);
  const std::vector<double> x = {0.5, 0.35, 0.1, 0.6};
  const std::vector<double> u = space.ToUnit(x);
  EXPECT_NEAR(u[0], 0.5, 1e-15);
  EXPECT_NEAR(u[2], 0.0, 1e-15);
  EXPECT_NEAR(u[3], 1.0, 1e-15);
  const std::vector<double> back = space.ToPhysical(u);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(back[k], x[k], 1e-15);
  core::Scene scene = site.scene;
  space.Apply(x, &scene);
  EXPECT_EQ(scene.materials[0].hardness, 0.5);
  EXPECT_EQ(scene.materials[0].roughness_m, 0.35);
  EXPECT_EQ(scene.materials[1].hardness, 0.1);
  EXPECT_EQ(space.Current(scene), x);
  EXPECT_FALSE(space.SameTerrain(x, {0.5, 0.36, 0.1, 0.6}));
  EXPECT_TRUE(space.SameTerrain(x, {0.4, 0.35, 0.2, 0.6}));
}

TEST(ParameterSpace, RoughnessBoundAtZeroIsRefused) {
  sites::Site site = TwinSite(4);
  site.calibrate[1].lower = 0.0;
  try {
    ParameterSpace::FromSite(site);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("slope"));
    EXPECT_THAT(e.what(), HasSubstr("must be > 0"));
  }
}

}  // namespace
}  // namespace rockcal::calibrate
