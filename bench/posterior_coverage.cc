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
//   posterior_coverage [--twins 20] [--parameters 2] [--materials 2]
//                      [--obs-rocks 60] [--rocks 120] [--threads 1] [--seed 1]
//                      [--independent 0] [--prior 0] [--truths middle]
//                      [--ranks 0] [--bootstrap 200] [--kinds both]
//                      [--error-scale 1] [--noise 0] [--search 0]
//                      [--design-points -1] [--rounds -1] [--log-sigma 0]
//                      [--run-terms both] [--max 1] [--run-spread 0.5]
//
// --bootstrap B: the residuals' correlation from B resamples of the rocks
// (PosteriorOptions::bootstrap_replicates; 0: each distribution's quantiles
// alone, the posterior before issue #54). --kinds: which observations the
// twin's field gives, any of scars (the bounce heights at the two
// partitions), stops (the stop points), passing (the share past the second
// partition) and runs (tracked runs: --obs-rocks rock groups released about
// points of their own (--run-spread), one field rock each, its stop compared with its
// group's rocks; not with stops), comma-separated; both = scars,stops.
// --error-scale f: the measurement errors (0.1 m on heights, 1 m on stop
// points, 0.05 on a passing fraction) times f. --noise 1: the field's values carry those
// errors (each value plus a normal draw of its error); 0: exact values, the
// errors declared only. --materials 3: the first 20 m of the runout is
// a third material, "toe" (the values: slope, runout and toe hardness, then
// runout, slope and toe roughness). --truths
// edges: each truth in the outer 10 % of its range at either end (--prior 1
// is --truths prior). --search N: a BOBYQA search of N evaluations from the
// box's centre first, its evaluations reused by the posterior (as rockcal
// calibrate --posterior did before this measured its cost). --design-points
// and --rounds: the posterior's (PosteriorOptions); -1, the defaults.
// --run-terms: with runs, which comparisons of them enter the misfit
// (MisfitOptions::run_terms: pooled, per_run or both, the product's default).
// --max 0: the distributions' maxima left out of the misfit
// (MisfitOptions::include_max). --run-spread r: with runs, each run's rocks
// start within a disc of r m about its release point (the tracked sites'
// position_spread; 0: at the point itself, as before 2026-12-07).
// --log-sigma 1: the likelihood with the sigmas' log term
// (PosteriorOptions::sigma_log_term, rockcal's --posterior-log-sigma). The
// twins themselves: tests/calibrate/posterior_twin.h.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "../tests/calibrate/posterior_twin.h"
#include "timing.h"

namespace {

using namespace rockcal;
using bench::Arg;
using bench::TextArg;

}  // namespace

int main(int argc, char** argv) {
  const int twins = static_cast<int>(Arg(argc, argv, "twins", 20));
  calibrate::testing::PosteriorTwinOptions o;
  o.parameters = static_cast<int>(Arg(argc, argv, "parameters", 2));
  o.materials = static_cast<int>(Arg(argc, argv, "materials", 2));
  o.obs_rocks = static_cast<int>(Arg(argc, argv, "obs-rocks", 60));
  o.rocks = static_cast<int>(Arg(argc, argv, "rocks", 120));
  o.threads = static_cast<int>(Arg(argc, argv, "threads", 1));
  o.seed = static_cast<std::uint64_t>(Arg(argc, argv, "seed", 1));
  // --independent 1: every residual independent (PosteriorOptions::correlated_quantiles off).
  o.independent = Arg(argc, argv, "independent", 0) != 0;
  o.bootstrap = static_cast<int>(Arg(argc, argv, "bootstrap", 200));
  o.kinds = TextArg(argc, argv, "kinds", "both");
  o.run_terms = TextArg(argc, argv, "run-terms", "both");
  o.include_max = Arg(argc, argv, "max", 1) != 0;
  o.run_spread = bench::RealArg(argc, argv, "run-spread", 0.5);
  o.error_scale = bench::RealArg(argc, argv, "error-scale", 1.0);
  o.noise = Arg(argc, argv, "noise", 0) != 0;
  o.truths = TextArg(argc, argv, "truths", Arg(argc, argv, "prior", 0) != 0 ? "prior" : "middle");
  o.ranks = static_cast<int>(Arg(argc, argv, "ranks", 0));
  o.search = static_cast<int>(Arg(argc, argv, "search", 0));
  o.design_points = static_cast<int>(Arg(argc, argv, "design-points", -1));
  o.rounds = static_cast<int>(Arg(argc, argv, "rounds", -1));
  o.log_sigma = Arg(argc, argv, "log-sigma", 0) != 0;
  if (const std::string bad = calibrate::testing::Check(o); !bad.empty() || twins < 1) {
    std::fprintf(stderr, "posterior_coverage: %s\n", bad.empty() ? "--twins >= 1" : bad.c_str());
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  const calibrate::ParameterSpace space =
      calibrate::ParameterSpace::FromSite(calibrate::testing::PosteriorTwinSite(o, o.rocks));
  const auto d = static_cast<std::size_t>(o.parameters);
  std::vector<int> covered(d, 0);
  std::vector<std::vector<int>> rank(d);  // per value, the truth's rank per twin
  std::vector<double> width(d, 0.0), error(d, 0.0);
  double max_rhat = 0.0;
  int simulations = 0;
  std::printf("twin | truth | median | 5 %% | 95 %% | covered | R-hat | correlation | s\n");
  for (int t = 1; t <= twins; ++t) {
    const auto t0 = std::chrono::steady_clock::now();
    const calibrate::testing::PosteriorTwin twin = calibrate::testing::RunPosteriorTwin(o, t);
    const calibrate::PosteriorResult& r = twin.posterior;
    simulations += r.simulated;
    max_rhat = std::max(max_rhat, r.max_rhat);
    std::string cols[5];
    for (std::size_t k = 0; k < d; ++k) {
      const auto& p = r.parameters[k];
      const auto& par = space.parameters()[k];
      covered[k] += twin.inside[k];
      if (o.ranks > 0) rank[k].push_back(twin.rank[k]);
      width[k] += (p.p95 - p.p05) / (par.upper - par.lower) / twins;
      error[k] += std::abs(p.median - twin.truth[k]) / (par.upper - par.lower) / twins;
      char buf[64];
      const char* sep = k ? ", " : "";
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, twin.truth[k]);
      cols[0] += buf;
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, p.median);
      cols[1] += buf;
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, p.p05);
      cols[2] += buf;
      std::snprintf(buf, sizeof buf, "%s%.3f", sep, p.p95);
      cols[3] += buf;
      cols[4] += std::string(sep) + (twin.inside[k] ? "yes" : "NO");
    }
    std::printf("%d | %s | %s | %s | %s | %s | %.3f | %s, %.1f of %d | %.1f\n", t, cols[0].c_str(),
                cols[1].c_str(), cols[2].c_str(), cols[3].c_str(), cols[4].c_str(), r.max_rhat,
                r.correlation_source.c_str(), r.effective_residuals, twin.residuals,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::fflush(stdout);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "\n%d twins, %d parameters, %d materials, %d observed rocks, %d rocks per evaluation, %d "
      "thread(s), %s residuals (bootstrap %d), observed %s (run terms %s), errors x%g%s, "
      "truths %s, search %d, design points %d, rounds %d (-1: default), log sigma %d, maxima %d, "
      "run spread %g m, "
      "%d simulations, %.0f s; max R-hat %.3f\n\n",
      twins, o.parameters, o.materials, o.obs_rocks, o.rocks, o.threads,
      o.independent ? "independent" : "correlated", o.bootstrap, o.kinds.c_str(),
      o.run_terms.c_str(), o.error_scale, o.noise ? " (in the values)" : " (declared)",
      o.truths.c_str(), o.search, o.design_points, o.rounds, o.log_sigma ? 1 : 0,
      o.include_max ? 1 : 0, o.run_spread, simulations, seconds, max_rhat);
  std::printf(
      "| parameter | 90 %% intervals holding the truth | mean width / range | mean |median - "
      "truth| / range |\n|---|---|---|---|\n");
  for (std::size_t k = 0; k < d; ++k)
    std::printf("| %s | %d of %d | %.3f | %.3f |\n", space.parameters()[k].label().c_str(),
                covered[k], twins, width[k], error[k]);
  int all = 0;
  for (const int c : covered) all += c;
  std::printf("| all | %d of %d | | |\n", all, twins * o.parameters);
  if (o.ranks > 0) {
    std::printf(
        "\nSimulation-based calibration (%d samples per posterior, %s truths): rank "
        "histogram in 10 bins, chi-square (9 d.o.f.) p-value\n",
        o.ranks, o.truths.c_str());
    for (std::size_t k = 0; k < d; ++k) {
      const std::vector<int> bins = calibrate::testing::RankHistogram(rank[k], o.ranks, 10);
      const double chi = calibrate::testing::ChiSquare(bins);
      std::string line;
      for (const int b : bins) line += " " + std::to_string(b);
      std::printf("| %s |%s | chi-square %.1f, p = %.3g |\n", space.parameters()[k].label().c_str(),
                  line.c_str(), chi, calibrate::testing::ChiSquareP(chi, 10));
    }
  }
  return 0;
}
