// Twin experiments: observations drawn from a simulation at known values
// with one seed, calibration with another. Labelled "heavy": they need enough
// rocks for the Monte Carlo noise to let the parameters show, so they run in
// the optimised build, not under the sanitizers (see run.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/calibrate/reach.h"
#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace twin_heavy_test {

using testing::TwinObservations;
using testing::TwinSite;

using testing::kTruth;  // the site starts elsewhere
// 1000 rocks per evaluation keep the Monte Carlo noise of the misfit well
// below its valley's depth (at 300 BOBYQA stopped far above the truth's misfit).
constexpr int kRocks = 1000;

struct Twin {
  sites::Site site = TwinSite(kRocks);
  ParameterSpace space = ParameterSpace::FromSite(site);
  // Observations from twice the rocks and seed 11; calibration with seed 2.
  observations::Observations obs = TwinObservations(TwinSite(2 * kRocks), kTruth, 11);
  core::Scene scene = [this] {
    core::Scene s = site.scene;
    s.options.seed = 2;
    return s;
  }();
  Objective objective{scene, space, obs, {}};
};

Twin& SharedTwin() {
  static Twin twin;
  return twin;
}

double RangeError(const ParameterSpace& space, const std::vector<double>& x, int k) {
  const Parameter& p = space.parameters()[static_cast<std::size_t>(k)];
  return std::abs(x[static_cast<std::size_t>(k)] - kTruth[static_cast<std::size_t>(k)]) /
         (p.upper - p.lower);
}

std::string Describe(const MethodResult& r, const ParameterSpace& space) {
  std::string s = r.stage.name() + ": misfit " + std::to_string(r.best_misfit) + " after " +
                  std::to_string(r.evaluations) + " (" + r.termination.message +
                  "; lowest evaluated " + std::to_string(r.lowest_misfit) + "; " +
                  r.smoothed.message + ")";
  for (int k = 0; k < space.size(); ++k)
    s += "\n  " + space.parameters()[k].label() + " = " + std::to_string(r.best[k]) + " (truth " +
         std::to_string(kTruth[k]) + ", error " + std::to_string(100 * RangeError(space, r.best, k)) +
         " % of range)";
  return s;
}

// The misfit at x averaged over calibration seeds 2 to 6: one seed's misfit
// scatters by about as much as the truth's misfit itself (BOBYQA's stencil
// measured a scatter of 6.8 where the truth scored 3.4 at seed 2 and 10.1
// with an earlier engine), so a single seed compares a noise dip with a
// noise peak.
double MeanMisfit(const Twin& twin, const std::vector<double>& x) {
  double sum = 0.0;
  const int seeds = 5;
  for (int k = 0; k < seeds; ++k) {
    core::Scene scene = twin.scene;
    scene.options.seed = 2 + static_cast<std::uint64_t>(k);
    sum += Objective{scene, twin.space, twin.obs, {}}.Evaluate(x).value;
  }
  return sum / seeds;
}

// Issue 12's criterion: every parameter within 5 % of its range of the
// truth. And the optimiser reaches the noise floor: the misfit at the
// calibrated values is at most 1.5 times the misfit at the truth, both
// averaged over five seeds (MeanMisfit).
//
// The calibrated values are the smoothed estimate (MethodOptions::estimate).
// The lowest evaluation alone misses the criterion: on this rugged misfit it
// sits in a dip of the Monte Carlo noise far below the truth's misfit (BOBYQA
// 4.6, Ceres 2.9, truth 10.1 at calibration seed 2), with the runout
// hardness 20 % (BOBYQA) and 11 % (Ceres) of its range off.
bool TruthRecovered(const MethodResult& r, const Twin& twin) {
  if (!r.smoothed.used) return false;
  for (int k = 0; k < twin.space.size(); ++k)
    if (!(RangeError(twin.space, r.best, k) < 0.05)) return false;
  // The truth's is the same for every method and seed judged: once.
  static const double truth = MeanMisfit(twin, kTruth);
  const double calibrated = MeanMisfit(twin, r.best);
  std::printf("misfit over seeds 2-6: %g at the calibrated values, %g at the truth\n", calibrated,
              truth);
  return calibrated < truth * 1.5;
}
void ExpectTruthRecovered(const MethodResult& r, const Twin& twin) {
  EXPECT_TRUE(TruthRecovered(r, twin)) << r.smoothed.message << "\n" << Describe(r, twin.space);
}

// Where a calibration's search starts: as Calibrate does with a reach check,
// the design point of lowest misfit when it beats the site's values. The
// site's values lose many rocks off the slope, where the stopped share and
// the censored runout make the misfit steep and lumpy.
std::vector<double> SearchStart(Twin& twin, const Objective& objective) {
  const std::vector<double> site = twin.space.Current(twin.scene);
  ReachOptions options;
  options.points = 20;
  options.seed = 2;
  const ReachResult reach = RunReach(objective, options);
  const ReachPoint& best = reach.points[static_cast<std::size_t>(reach.best_point)];
  return best.misfit < objective.Evaluate(site).value ? best.physical : site;
}
std::vector<double> SearchStart(Twin& twin) { return SearchStart(twin, twin.objective); }

TEST(Calibration, TwinExperimentBobyqa) {
  Twin& twin = SharedTwin();
  MethodOptions options;
  options.estimate = Estimate::kSmoothed;
  // BOBYQA reads the misfit alone, not its residuals: on this rugged
  // four-parameter misfit it needs about 150 evaluations (with 100 it stopped
  // at 1.9 and 2.7 times the truth's misfit for calibration seeds 2 and 3).
  options.max_evals = 150;
  const MethodResult r =
      RunMethod(Method::kBobyqa, twin.objective, SearchStart(twin), options, nullptr);
  std::printf("%s\n", Describe(r, twin.space).c_str());
  ExpectTruthRecovered(r, twin);
}

// Ceres reads the residuals: 60 evaluations. A calibration at one seed
// stands on that seed's Monte Carlo noise: at seed 2 the search may end in a
// dip of it far below the truth's misfit (2.0 against 5.7 averaged over
// seeds, with #15's fifth-round engine), where the smoothed estimate does
// not hold and the lowest evaluation is off by 7 % of a range, while at
// seeds 3 and 4 every parameter came within 1.6 %. So the method is judged
// on three calibration seeds (2, 3, 4), as a user repeating a calibration
// would: at least two must recover the truth, and every one must give
// finite, positive standard errors.
TEST(Calibration, TwinExperimentCeresWithUncertainty) {
  Twin& twin = SharedTwin();
  MethodOptions options;
  options.estimate = Estimate::kSmoothed;
  options.max_evals = 60;
  int recovered = 0;
  for (const std::uint64_t seed : {2, 3, 4}) {
    core::Scene scene = twin.scene;
    scene.options.seed = seed;
    const Objective objective{scene, twin.space, twin.obs, {}};
    const MethodResult r =
        RunMethod(Method::kCeres, objective, SearchStart(twin, objective), options, nullptr);
    std::printf("seed %d: %s\n", static_cast<int>(seed), Describe(r, twin.space).c_str());
    const bool ok = TruthRecovered(r, twin);
    recovered += ok;
    std::printf("seed %d: truth %s\n", static_cast<int>(seed), ok ? "recovered" : "missed");
    ASSERT_TRUE(r.uncertainty.computed) << r.uncertainty.message;
    ASSERT_FALSE(r.uncertainty.rank_deficient) << r.uncertainty.message;
    for (int k = 0; k < twin.space.size(); ++k) {
      const double se = r.uncertainty.std_error[static_cast<std::size_t>(k)];
      std::printf("  %s standard error %g\n", twin.space.parameters()[k].label().c_str(), se);
      EXPECT_GT(se, 0.0);
      EXPECT_TRUE(std::isfinite(se));
    }
    for (int a = 0; a < twin.space.size(); ++a)
      EXPECT_NEAR(r.uncertainty.correlation[a][a], 1.0, 1e-9);
  }
  EXPECT_GE(recovered, 2) << "of 3 calibration seeds";
}

}  // namespace twin_heavy_test
}  // namespace rockcal::calibrate
