// Coverage of the posterior's 90 % intervals (issue #39): twin experiments at
// random truths on the small twin slope (tests/calibrate/twin_fixture.h:
// a 35-degree slope onto a flat runout, spheres, bounce heights at two
// partitions and the stop points observed). For each twin a truth is drawn
// uniformly in the middle 80 % of the box, "field" observations are
// simulated there with their own seed (never the calibration's), and the
// posterior is sampled (calibrate::SamplePosterior, its defaults) on the
// calibration objective at --rocks rocks, seed 1. Prints, per parameter,
// how many 5-95 % intervals hold the truth, the mean interval width as a
// share of the range and the median's error; then the wall time.
//
// With --prior 1 the truths are drawn from the whole box (the prior), and
// with --ranks L > 0 the program also prints simulation-based calibration
// (Talts et al. 2018, Validating Bayesian inference algorithms with
// simulation-based calibration, arXiv:1804.06788): per parameter the rank of
// the truth among L posterior samples evenly spaced through the chains (0..L),
// their histogram in 10 bins and the chi-square p-value of its uniformity.
//
//   posterior_coverage [--twins 20] [--parameters 2] [--obs-rocks 60]
//                      [--rocks 120] [--threads 1] [--seed 1] [--independent 0]
//                      [--prior 0] [--ranks 0] [--bootstrap 200] [--kinds both]
//                      [--error-scale 1]
//
// --bootstrap B: the residuals' correlation from B resamples of the rocks
// (PosteriorOptions::bootstrap_replicates; 0: each distribution's quantiles
// alone, the posterior before issue #54). --kinds scars|stops|both: which
// observations the twin's field gives (the bounce heights at the two
// partitions, the stop points, or both). --error-scale f: the measurement
// errors (0.1 m on heights, 1 m on stop points) times f.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../tests/calibrate/twin_fixture.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/random.h"
#include "timing.h"

namespace {

using namespace rockcal;
using bench::Arg;

}  // namespace

int main(int argc, char** argv) {
  const int twins = static_cast<int>(Arg(argc, argv, "twins", 20));
  const int parameters = static_cast<int>(Arg(argc, argv, "parameters", 2));
  const int obs_rocks = static_cast<int>(Arg(argc, argv, "obs-rocks", 60));
  const int rocks = static_cast<int>(Arg(argc, argv, "rocks", 120));
  const int threads = static_cast<int>(Arg(argc, argv, "threads", 1));
  const std::uint64_t seed = static_cast<std::uint64_t>(Arg(argc, argv, "seed", 1));
  // --independent 1: every residual independent (PosteriorOptions::correlated_quantiles off).
  const bool independent = Arg(argc, argv, "independent", 0) != 0;
  // --bootstrap B: the residuals' correlation from B bootstrap resamples
  // (PosteriorOptions::bootstrap_replicates; 0: the quantiles' alone).
  const int bootstrap = static_cast<int>(Arg(argc, argv, "bootstrap", 200));
  std::string kinds = "both";
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--kinds") kinds = argv[i + 1];
  const double error_scale = Arg(argc, argv, "error-scale", 1.0);
  if (kinds != "both" && kinds != "scars" && kinds != "stops") {
    std::fprintf(stderr, "posterior_coverage: --kinds scars, stops or both\n");
    return 2;
  }
  const bool prior = Arg(argc, argv, "prior", 0) != 0;
  const int ranks = static_cast<int>(Arg(argc, argv, "ranks", 0));
  if (parameters < 1 || parameters > 4 || twins < 1 || obs_rocks < 10 || rocks < 10) {
    std::fprintf(stderr, "posterior_coverage: --parameters 1..4, --twins >= 1, rocks >= 10\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  sites::Site site = calibrate::testing::TwinSite(rocks);
  // Slope hardness, runout hardness, runout roughness, slope roughness.
  const std::vector<int> order = {0, 2, 3, 1};
  std::vector<sites::ParameterBound> bounds;
  for (int k = 0; k < parameters; ++k)
    bounds.push_back(site.calibrate[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])]);
  site.calibrate = bounds;
  const calibrate::ParameterSpace space = calibrate::ParameterSpace::FromSite(site);
  std::vector<int> covered(static_cast<std::size_t>(parameters), 0);
  // rank[k]: the truth's rank among `ranks` samples, per twin.
  std::vector<std::vector<int>> rank(static_cast<std::size_t>(parameters));
  std::vector<double> width(static_cast<std::size_t>(parameters), 0.0),
      error(static_cast<std::size_t>(parameters), 0.0);
  double max_rhat = 0.0;
  int simulations = 0;
  std::printf("twin | truth | median | 5 %% | 95 %% | covered | R-hat | correlation | s\n");
  for (int t = 1; t <= twins; ++t) {
    const auto t0 = std::chrono::steady_clock::now();
    core::RandomStream rng(seed, 0x5457494e00000000ull + static_cast<std::uint64_t>(t));  // "TWIN"
    std::vector<double> unit(static_cast<std::size_t>(parameters));
    for (double& u : unit) u = prior ? rng.Uniform() : 0.1 + 0.8 * rng.Uniform();
    const std::vector<double> truth = space.ToPhysical(unit);
    sites::Site field = calibrate::testing::TwinSite(obs_rocks);
    field.calibrate = bounds;
    field.scene.options.threads = threads;
    observations::Observations obs = calibrate::testing::TwinObservations(
        field, truth, 1000 + seed * 100 + static_cast<std::uint64_t>(t));
    if (kinds == "scars") obs.runout.reset();
    if (kinds == "stops") obs.tree_scars.clear();
    // A partition no observed rock reached (few rocks) has nothing to compare.
    obs.tree_scars.erase(std::remove_if(obs.tree_scars.begin(), obs.tree_scars.end(),
                                        [](const observations::ScarSet& s) { return s.heights.empty(); }),
                         obs.tree_scars.end());
    obs.error.height *= error_scale;
    obs.error.runout *= error_scale;
    const core::Scene scene = calibrate::RunScene(site, rocks, seed, threads);
    const calibrate::Objective objective(scene, space, obs, {});
    calibrate::PosteriorOptions options;
    options.mcmc.seed = seed;
    options.correlated_quantiles = !independent;
    options.bootstrap_replicates = bootstrap;
    // The residuals' names (for the quantiles' correlation): one evaluation
    // at the box's centre.
    const observations::Misfit layout = objective.Evaluate(
        space.ToPhysical(std::vector<double>(static_cast<std::size_t>(parameters), 0.5)));
    const calibrate::PosteriorResult r =
        calibrate::SamplePosterior(objective, {}, options, nullptr, nullptr, layout.residuals);
    simulations += r.simulated;
    max_rhat = std::max(max_rhat, r.max_rhat);
    std::string line = std::to_string(t);
    std::string cols[5];
    for (int k = 0; k < parameters; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const auto& p = r.parameters[kk];
      const auto& par = space.parameters()[kk];
      const bool in = truth[kk] >= p.p05 && truth[kk] <= p.p95;
      covered[kk] += in;
      if (ranks > 0) {
        int below = 0;
        const std::size_t n = r.samples.size();
        for (int l = 0; l < ranks; ++l)
          below +=
              r.samples[(static_cast<std::size_t>(l) * n) / static_cast<std::size_t>(ranks)][kk] <
              truth[kk];
        rank[kk].push_back(below);
      }
      width[kk] += (p.p95 - p.p05) / (par.upper - par.lower) / twins;
      error[kk] += std::abs(p.median - truth[kk]) / (par.upper - par.lower) / twins;
      char buf[64];
      const char* sep = k ? ", " : "";
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, truth[kk]);
      cols[0] += buf;
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, p.median);
      cols[1] += buf;
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, p.p05);
      cols[2] += buf;
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, p.p95);
      cols[3] += buf;
      cols[4] += std::string(sep) + (in ? "yes" : "NO");
    }
    std::printf("%d | %s | %s | %s | %s | %s | %.3f | %s, %.1f of %d | %.1f\n", t, cols[0].c_str(),
                cols[1].c_str(), cols[2].c_str(), cols[3].c_str(), cols[4].c_str(), r.max_rhat,
                r.correlation_source.c_str(), r.effective_residuals, objective.residual_count(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::fflush(stdout);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "\n%d twins, %d parameters, %d observed rocks, %d rocks per evaluation, %d thread(s), "
      "%s residuals (bootstrap %d), observed %s, errors x%g, %d simulations, %.0f s; max R-hat "
      "%.3f\n\n",
      twins, parameters, obs_rocks, rocks, threads, independent ? "independent" : "correlated",
      bootstrap, kinds.c_str(), error_scale, simulations, seconds, max_rhat);
  std::printf(
      "| parameter | 90 %% intervals holding the truth | mean width / range | mean |median - "
      "truth| / range |\n|---|---|---|---|\n");
  for (int k = 0; k < parameters; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    std::printf("| %s | %d of %d | %.3f | %.3f |\n", space.parameters()[kk].label().c_str(),
                covered[kk], twins, width[kk], error[kk]);
  }
  int all = 0;
  for (const int c : covered) all += c;
  std::printf("| all | %d of %d | | |\n", all, twins * parameters);
  if (ranks > 0) {
    // Uniform ranks 0..L in 10 bins of equal probability; Pearson's
    // chi-square with 9 degrees of freedom, its p-value by the regularised
    // upper incomplete gamma function Q(9/2, x/2) (a series for P).
    auto p_value = [](double x) {
      const double a = 4.5, z = 0.5 * x;
      double term = 1.0 / a, sum = term;
      for (int n = 1; n < 500; ++n) {
        term *= z / (a + n);
        sum += term;
      }
      return 1.0 - std::exp(-z + a * std::log(z) - std::lgamma(a)) * sum;
    };
    std::printf(
        "\nSimulation-based calibration (%d samples per posterior, %s truths): rank "
        "histogram in 10 bins, chi-square (9 d.o.f.) p-value\n",
        ranks, prior ? "prior" : "middle-80 %");
    for (int k = 0; k < parameters; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      std::vector<int> bins(10, 0);
      for (const int q : rank[kk])
        ++bins[static_cast<std::size_t>(std::min(9, (q * 10) / (ranks + 1)))];
      const double expected = static_cast<double>(rank[kk].size()) / 10.0;
      double chi = 0.0;
      std::string line;
      for (const int b : bins) {
        chi += (b - expected) * (b - expected) / expected;
        line += " " + std::to_string(b);
      }
      std::printf("| %s |%s | chi-square %.1f, p = %.3g |\n",
                  space.parameters()[kk].label().c_str(), line.c_str(), chi, p_value(chi));
    }
  }
  return 0;
}
