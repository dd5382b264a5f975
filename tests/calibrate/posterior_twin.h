// Posterior twins (issue #54): a truth drawn in the twin's box, "field"
// observations simulated there with their own seed, and the posterior
// sampled on the calibration objective; the truth's place in the posterior
// (inside the 90 % interval, its rank among the samples) says whether the
// posterior is honest. Shared by the heavy test
// (posterior_sbc_heavy_test.cc) and the bench that runs the scene family
// (bench/posterior_coverage.cc; bench/README.md has its figures).
//
// Simulation-based calibration: Talts, Betancourt, Simpson, Vehtari and
// Gelman (2018), Validating Bayesian inference algorithms with
// simulation-based calibration, arXiv:1804.06788. With truths drawn from the
// prior (the whole box), the rank of the truth among L posterior samples is
// uniform on 0..L when the posterior is right.
#ifndef ROCKCAL_TESTS_CALIBRATE_POSTERIOR_TWIN_H_
#define ROCKCAL_TESTS_CALIBRATE_POSTERIOR_TWIN_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/polygon.h"
#include "rockcal/core/random.h"
#include "twin_fixture.h"

namespace rockcal::calibrate::testing {

struct PosteriorTwinOptions {
  // The calibrated values, the first `parameters` of: slope hardness,
  // runout hardness, runout roughness, slope roughness (2 materials); slope
  // hardness, runout hardness, toe hardness, runout roughness, slope
  // roughness, toe roughness (3 materials).
  int parameters = 2;
  // 2: slope and runout (TwinSite); 3: the first 20 m of the runout is a
  // third material, "toe".
  int materials = 2;
  int obs_rocks = 60;  // the field's rocks
  int rocks = 120;     // per evaluation
  int threads = 1;
  std::uint64_t seed = 1;
  bool independent = false;  // every residual independent
  int bootstrap = 200;       // PosteriorOptions::bootstrap_replicates
  // PosteriorOptions::design_points and rounds; -1: the product's defaults.
  int design_points = -1;
  int rounds = -1;
  bool log_sigma = false;  // PosteriorOptions::sigma_log_term
  // What the field observed: any of "scars" (bounce heights at both
  // partitions), "stops" (stop points), "passing" (the share of rocks past
  // Q), "runs" (tracked runs: obs_rocks rock groups, each released about a
  // point of its own (run_spread), one field rock each, its stop compared with its
  // group's rocks; not with "stops"), comma-separated; "both" is
  // "scars,stops".
  std::string kinds = "both";
  double error_scale = 1.0;  // the measurement errors times this
  // Tracked runs: which comparisons enter the misfit
  // (observations::MisfitOptions::run_terms: "pooled", "per_run", "both").
  std::string run_terms = "both";
  // The maxima compared too (observations::MisfitOptions::include_max).
  bool include_max = true;
  // Tracked runs: the radius of the disc about each run's release point its
  // rocks start in, m (the tracked sites' "position_spread"; 0: the point
  // itself).
  double run_spread = 0.5;
  // The field's values carry the measurement errors they declare: each
  // height, each stop point's x and y and the passing share plus a normal
  // draw of its error (seeded by the twin). Off: exact values, errors
  // declared only.
  bool noise = false;
  // Where the truths are drawn, per value on the unit box: "middle" (the
  // middle 80 %), "prior" (the whole box) or "edges" (the outer 10 % at
  // either end).
  std::string truths = "prior";
  int ranks = 99;  // posterior samples the truth is ranked among (0: none)
  // A BOBYQA search of this many evaluations from the box's centre before
  // the posterior, whose evaluations the posterior reuses, as rockcal
  // calibrate --posterior did until the family measured what that costs
  // (bench/README.md; 0: none, the posterior alone, as it does now).
  int search = 0;
};

// Whether the field of `o` observes `kind` ("scars", "stops", "passing", "runs").
inline bool Observes(const PosteriorTwinOptions& o, const std::string& kind) {
  const std::string list = "," + (o.kinds == "both" ? std::string("scars,stops") : o.kinds) + ",";
  return list.find("," + kind + ",") != std::string::npos;
}

// Empty when valid; else what is wrong.
inline std::string Check(const PosteriorTwinOptions& o) {
  const int most = o.materials == 3 ? 6 : 4;
  if (o.materials != 2 && o.materials != 3) return "materials: 2 or 3";
  if (o.parameters < 1 || o.parameters > most)
    return "parameters: 1 to " + std::to_string(most) + " with " + std::to_string(o.materials) +
           " materials";
  if (o.obs_rocks < 10 || o.rocks < 10) return "rocks: 10 or more";
  if (o.search < 0) return "search: 0 or more evaluations";
  if (o.design_points < -1 || o.rounds < -1) return "design points, rounds: -1 (default) or more";
  if (o.truths != "middle" && o.truths != "prior" && o.truths != "edges")
    return "truths: middle, prior or edges";
  std::string rest = o.kinds == "both" ? "scars,stops" : o.kinds;
  for (std::size_t at = 0; at <= rest.size();) {
    const std::size_t comma = std::min(rest.find(',', at), rest.size());
    const std::string k = rest.substr(at, comma - at);
    if (k != "scars" && k != "stops" && k != "passing" && k != "runs")
      return "kinds: scars, stops, passing, runs";
    at = comma + 1;
  }
  if (Observes(o, "runs") && Observes(o, "stops")) return "kinds: runs are the stops (not both)";
  observations::RunTerms terms;
  if (!observations::StringToRunTerms(o.run_terms, &terms))
    return "run terms: pooled, per_run, both";
  return "";
}

// Splits the twin site's one rock group into `runs` groups (tracked runs),
// each released from a point of its own across the release zone, rocks /
// runs rocks each (at least one), within a disc of `spread` about it (as a
// tracked site's "position_spread"; 0: from the point itself).
inline void SplitIntoRuns(int runs, int rocks, double spread, sites::Site* site) {
  const core::RockGroup one = site->scene.groups[0];
  site->scene.groups.clear();
  for (int r = 0; r < runs; ++r) {
    core::RockGroup g = one;
    g.id = "run" + std::to_string(r + 1);
    g.count = std::max(1, rocks / runs);
    g.release.point = Eigen::Vector2d(2.5, 8.0 + 4.0 * (r + 0.5) / runs);
    g.release.zone.clear();
    if (spread > 0) g.release.zone = core::DiscPolygon(g.release.point, spread);
    site->scene.groups.push_back(g);
  }
}

// The twin site of `o`, with `rocks` rocks and the calibrated values of `o`.
// With tracked runs, o.obs_rocks groups (the runs: SplitIntoRuns).
inline sites::Site PosteriorTwinSite(const PosteriorTwinOptions& o, int rocks) {
  sites::Site site = TwinSite(rocks);
  if (Observes(o, "runs")) SplitIntoRuns(o.obs_rocks, rocks, o.run_spread, &site);
  std::vector<sites::ParameterBound> all = site.calibrate;  // slope h, slope r, runout h, runout r
  if (o.materials == 3) {
    core::Scene& scene = site.scene;
    core::Material toe = scene.materials[1];
    toe.id = "toe";
    scene.materials.push_back(toe);
    for (int j = 0; j < scene.grid.ny; ++j)
      for (int i = 0; i < scene.grid.nx; ++i) {
        const double x = i * scene.grid.spacing;
        if (x >= 30.0 && x < 50.0)
          scene.grid.material[static_cast<std::size_t>(j * scene.grid.nx + i)] = 2;
      }
    all.push_back({"toe", "hardness", 0.1, 0.6, "toe"});
    all.push_back({"toe", "roughness", 0.1, 0.6, "toe"});
  }
  const std::vector<int> order =
      o.materials == 3 ? std::vector<int>{0, 2, 4, 3, 1, 5} : std::vector<int>{0, 2, 3, 1};
  std::vector<sites::ParameterBound> bounds;
  for (int k = 0; k < o.parameters; ++k)
    bounds.push_back(all[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])]);
  site.calibrate = bounds;
  return site;
}

struct PosteriorTwin {
  std::vector<double> truth;  // physical
  PosteriorResult posterior;
  std::vector<int> rank;     // per value: samples below the truth, of o.ranks
  std::vector<bool> inside;  // per value: truth within the 5-95 % interval
  int residuals = 0;
};

// Twin number `t` (1, 2, ...) of `o`: its truth from the stream (seed, t),
// its field from seed 1000 + 100 seed + t, the calibration at seed `seed`.
inline PosteriorTwin RunPosteriorTwin(const PosteriorTwinOptions& o, int t) {
  const sites::Site site = PosteriorTwinSite(o, o.rocks);
  const ParameterSpace space = ParameterSpace::FromSite(site);
  const auto d = static_cast<std::size_t>(o.parameters);
  core::RandomStream rng(o.seed, 0x5457494e00000000ull + static_cast<std::uint64_t>(t));  // "TWIN"
  std::vector<double> unit(d);
  for (double& u : unit) {
    const double v = rng.Uniform();
    u = o.truths == "prior"    ? v
        : o.truths == "middle" ? 0.1 + 0.8 * v
        : v < 0.5              ? 0.2 * v
                               : 0.8 + 0.2 * v;
  }
  PosteriorTwin twin;
  twin.truth = space.ToPhysical(unit);
  sites::Site field = PosteriorTwinSite(o, o.obs_rocks);
  field.scene.options.threads = o.threads;
  const bool runs = Observes(o, "runs");
  observations::Observations obs = TwinObservations(
      field, twin.truth, 1000 + o.seed * 100 + static_cast<std::uint64_t>(t), runs);
  if (Observes(o, "passing")) {
    // The share of the field's rocks past Q: those with a scar there.
    const double past = static_cast<double>(obs.tree_scars[1].heights.size());
    obs.passing.push_back({"passing[0] Q", 1, past / static_cast<double>(o.obs_rocks)});
  }
  if (!Observes(o, "stops") && !runs) obs.runout.reset();
  if (!Observes(o, "scars")) obs.tree_scars.clear();
  // A partition no observed rock reached (few rocks) has nothing to compare.
  obs.tree_scars.erase(
      std::remove_if(obs.tree_scars.begin(), obs.tree_scars.end(),
                     [](const observations::ScarSet& s) { return s.heights.empty(); }),
      obs.tree_scars.end());
  obs.error.height *= o.error_scale;
  obs.error.runout *= o.error_scale;
  obs.error.passing *= o.error_scale;
  if (o.noise) {
    core::RandomStream draw(o.seed, 0x4e4f495345000000ull + static_cast<std::uint64_t>(t));  // "NOISE"
    for (observations::ScarSet& s : obs.tree_scars)
      for (double& h : s.heights) h += obs.error.height * draw.Normal();
    if (obs.runout) {
      observations::Runout& r = *obs.runout;
      r.distances.clear();
      r.lateral.clear();
      for (std::size_t i = 0; i < r.stop_points.size(); ++i) {
        Eigen::Vector2d& p = r.stop_points[i];
        p += obs.error.runout * Eigen::Vector2d(draw.Normal(), draw.Normal());
        if (r.has_runs()) {
          r.distances.push_back((p - r.run_origins[i]).norm());
          continue;
        }
        r.distances.push_back(r.Distance(p));
        r.lateral.push_back(r.Lateral(p));
      }
    }
    for (observations::Passing& p : obs.passing)
      p.fraction = std::clamp(p.fraction + obs.error.passing * draw.Normal(), 0.0, 1.0);
  }
  const core::Scene scene = RunScene(site, o.rocks, o.seed, o.threads);
  observations::MisfitOptions misfit;
  observations::StringToRunTerms(o.run_terms, &misfit.run_terms);
  misfit.include_max = o.include_max;
  const Objective objective(scene, space, obs, misfit);
  PosteriorOptions options;
  options.mcmc.seed = o.seed;
  options.correlated_quantiles = !o.independent;
  options.bootstrap_replicates = o.bootstrap;
  if (o.design_points >= 0) options.design_points = o.design_points;
  if (o.rounds >= 0) options.rounds = o.rounds;
  options.sigma_log_term = o.log_sigma;
  // The residuals' names (for the quantiles' correlation): one evaluation
  // at the box's centre.
  const observations::Misfit layout =
      objective.Evaluate(space.ToPhysical(std::vector<double>(d, 0.5)));
  std::vector<Evaluation> reused;
  if (o.search > 0) {
    MethodOptions search;
    search.max_evals = o.search;
    reused = RunMethod(Method::kBobyqa, objective, space.ToPhysical(std::vector<double>(d, 0.5)),
                       search, nullptr)
                 .trace;
  }
  twin.posterior = SamplePosterior(objective, reused, options, nullptr, nullptr, layout.residuals);
  twin.residuals = objective.residual_count();
  for (std::size_t k = 0; k < d; ++k) {
    const ParameterPosterior& p = twin.posterior.parameters[k];
    twin.inside.push_back(twin.truth[k] >= p.p05 && twin.truth[k] <= p.p95);
    int below = 0;
    const std::size_t n = twin.posterior.samples.size();
    for (int l = 0; l < o.ranks; ++l)
      below += twin.posterior.samples[(static_cast<std::size_t>(l) * n) /
                                      static_cast<std::size_t>(o.ranks)][k] < twin.truth[k];
    twin.rank.push_back(below);
  }
  return twin;
}

// The counts of `ranks` (each in 0..ranks_of) in `bins` bins of equal
// probability.
inline std::vector<int> RankHistogram(const std::vector<int>& ranks, int ranks_of, int bins) {
  std::vector<int> h(static_cast<std::size_t>(bins), 0);
  for (const int q : ranks)
    ++h[static_cast<std::size_t>(std::min(bins - 1, (q * bins) / (ranks_of + 1)))];
  return h;
}

// Pearson's chi-square of a histogram against equal counts, and its p-value
// with bins - 1 degrees of freedom (the regularised upper incomplete gamma
// function Q(k/2, x/2), by the series for P).
inline double ChiSquare(const std::vector<int>& histogram) {
  double total = 0.0;
  for (const int b : histogram) total += b;
  const double expected = total / static_cast<double>(histogram.size());
  double chi = 0.0;
  for (const int b : histogram) chi += (b - expected) * (b - expected) / expected;
  return chi;
}
inline double ChiSquareP(double chi, int bins) {
  const double a = 0.5 * (bins - 1), z = 0.5 * chi;
  if (z <= 0.0) return 1.0;
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 500; ++n) {
    term *= z / (a + n);
    sum += term;
  }
  return 1.0 - std::exp(-z + a * std::log(z) - std::lgamma(a)) * sum;
}

}  // namespace rockcal::calibrate::testing

#endif  // ROCKCAL_TESTS_CALIBRATE_POSTERIOR_TWIN_H_
