// The issue's criterion for joint calibration (issue 17, part 3): a two-site
// campaign of twin sites (sites/examples/twin_campaign: observations
// simulated at known values, one shared class "ground") recovers the shared
// hardness and roughness at least as well as either site alone, and better
// where one site alone cannot separate them. The fan sees only where rocks
// stop, the gully only how high they bounce: on each alone, hardness and
// roughness trade off along a valley of the misfit. Labelled "heavy": it
// needs enough rocks for the parameters to stand out of the Monte Carlo
// noise, so it runs in the optimised build.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "rockcal/calibrate/campaign.h"

namespace rockcal::calibrate {
namespace {

// The values the observations were simulated at (make_observations.sh).
const std::vector<double> kTruth = {0.45, 0.30};

struct Recovery {
  std::string what;
  std::vector<double> values;
  std::vector<double> std_error;  // empty where the Jacobian is rank deficient
  double correlation = 0.0;       // of hardness and roughness
  double seconds = 0.0;
  int evaluations = 0;
};

CalibrationOptions Options() {
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.methods = {Method::kCeres};
  options.method.max_evals = 30;
  options.method.estimate = Estimate::kSmoothed;
  options.rocks = 250;
  options.seed = 2;  // the observations were drawn with seed 11
  return options;
}

Recovery Calibrate(const std::string& what, const Campaign& campaign) {
  const auto t0 = std::chrono::steady_clock::now();
  const CampaignSummary s = RunCampaign(campaign, Options());
  const MethodResult& best = s.calibration.best_method();
  Recovery r;
  r.what = what;
  r.values = best.best;
  if (best.uncertainty.computed && !best.uncertainty.rank_deficient) {
    r.std_error = best.uncertainty.std_error;
    r.correlation = best.uncertainty.correlation[0][1];
  }
  r.evaluations = best.evaluations;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// |value - truth| as a percentage of the parameter's range.
double ErrorPercent(const ParameterSpace& space, const Recovery& r, int k) {
  const Parameter& p = space.parameters()[static_cast<std::size_t>(k)];
  return 100.0 *
         std::abs(r.values[static_cast<std::size_t>(k)] - kTruth[static_cast<std::size_t>(k)]) /
         (p.upper - p.lower);
}

double WorstPercent(const ParameterSpace& space, const Recovery& r) {
  return std::max(ErrorPercent(space, r, 0), ErrorPercent(space, r, 1));
}

TEST(CampaignTwin, JointRecoversTheSharedValuesBetterThanEitherSiteAlone) {
  const Campaign both =
      LoadCampaign(std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/twin_campaign/campaign.json");
  ASSERT_EQ(both.sites.size(), 2u);
  const ParameterSpace space = JointSpace(both).space();
  ASSERT_EQ(space.size(), 2);
  std::vector<Recovery> runs;
  for (const CampaignSite& site : both.sites) {
    Campaign alone = both;
    alone.sites = {site};
    runs.push_back(Calibrate(site.name + " alone", alone));
  }
  runs.push_back(Calibrate("joint", both));

  std::printf("truth: hardness %.3f, roughness %.3f m; errors as %% of each range\n", kTruth[0],
              kTruth[1]);
  std::printf("%-12s %9s %9s %10s %10s %9s %9s %12s %6s %7s\n", "", "hardness", "roughness",
              "err H (%)", "err R (%)", "se H", "se R", "corr(H, R)", "evals", "s");
  for (const Recovery& r : runs) {
    std::printf(
        "%-12s %9.3f %9.3f %10.1f %10.1f %9s %9s %12s %6d %7.1f\n", r.what.c_str(), r.values[0],
        r.values[1], ErrorPercent(space, r, 0), ErrorPercent(space, r, 1),
        r.std_error.empty() ? "-" : std::to_string(r.std_error[0]).substr(0, 6).c_str(),
        r.std_error.empty() ? "-" : std::to_string(r.std_error[1]).substr(0, 6).c_str(),
        r.std_error.empty() ? "rank def." : std::to_string(r.correlation).substr(0, 6).c_str(),
        r.evaluations, r.seconds);
  }
  const Recovery& fan = runs[0];
  const Recovery& gully = runs[1];
  const Recovery& joint = runs[2];
  const double worst_alone = std::max(WorstPercent(space, fan), WorstPercent(space, gully));
  const double best_alone = std::min(WorstPercent(space, fan), WorstPercent(space, gully));
  std::printf(
      "worst parameter error: fan alone %.1f %%, gully alone %.1f %%, joint %.1f %% "
      "(%.1f times better than the worse site alone, %.1f than the better)\n",
      WorstPercent(space, fan), WorstPercent(space, gully), WorstPercent(space, joint),
      worst_alone / std::max(WorstPercent(space, joint), 1e-9),
      best_alone / std::max(WorstPercent(space, joint), 1e-9));
  // At least as well as either site alone, on every parameter's worst...
  EXPECT_LE(WorstPercent(space, joint), best_alone)
      << "the joint campaign recovers the shared values worse than a site alone";
  // ... and better where a site alone cannot separate them: the site alone
  // with the larger error misses by at least twice the joint's error.
  EXPECT_GE(worst_alone, 2.0 * WorstPercent(space, joint));
  // The joint values are within 10 % of each range of the truth.
  for (int k = 0; k < 2; ++k)
    EXPECT_LT(ErrorPercent(space, joint, k), 10.0) << space.parameters()[k].label();
}

}  // namespace
}  // namespace rockcal::calibrate
