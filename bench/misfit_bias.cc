// Is the expected misfit smallest at the truth? (issue #54.) Twin
// observations on the two-material twin slope (tests/calibrate/twin_fixture.h:
// a 35-degree slope onto a flat runout; every crossing rock's bounce height
// at x = 20 m and 40 m, every stopped rock's stop point, the stopped share),
// simulated at a fixed truth with K seeds of their own; the calibration
// objective (the misfit of calibrate::Objective's scene, observations'
// ComputeMisfit) evaluated along each parameter's axis through the truth at C
// calibration seeds. Each point is simulated once per calibration seed and
// scored against all K observation sets (the first checked against
// Objective::Evaluate, bit for bit).
//
// Prints, at the truth, each residual's mean, its standard error and its mean
// square over the C x K pairs (a statistic whose simulated and observed
// versions differ in expectation shows as a mean away from 0; a sigma too
// small as a mean square above 1), and along each axis where the mean misfit
// of each group of residuals (per observation: low, middle and high
// quantiles, the maximum, the share) is smallest, in % of the range from the
// truth (a parabola through the lowest grid point and its neighbours).
//
//   misfit_bias [--obs-seeds 16] [--cal-seeds 4] [--truth-seeds 0] [--points 11] [--span 25]
//               [--obs-rocks 120] [--rocks 120] [--threads 1] [--scars 2] [--error-scale 1]
//               [--truth a,b,c,d] [--max 1] [--runs 0] [--run-spread 0.5]
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "../tests/calibrate/posterior_twin.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/calibrate/residual_correlation.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/terrain.h"
#include "rockcal/parallel/parallel.h"
#include "timing.h"

namespace {

using namespace rockcal;
using bench::Arg;

// The group of a residual: its observation and which of its statistics.
std::string Group(const observations::Residual& r) {
  using observations::Statistic;
  std::string what;
  if (r.id.statistic == Statistic::kQuantile)
    what = r.id.level < 0.35 ? "p10-p30" : r.id.level < 0.65 ? "p40-p60" : "p70-p90";
  else
    what = r.id.quantity();
  return r.id.observation() + " " + what;
}

// Mean and standard error of x[c][k] over a crossed design (C calibration
// seeds by K observation seeds): var(mean) ~ var(row means) / C +
// var(column means) / K.
struct Moments {
  double mean = 0.0, se = 0.0, square = 0.0;
};
Moments Crossed(const std::vector<std::vector<double>>& x) {
  const std::size_t C = x.size(), K = x[0].size();
  std::vector<double> rows(C, 0.0), cols(K, 0.0);
  Moments m;
  for (std::size_t c = 0; c < C; ++c)
    for (std::size_t k = 0; k < K; ++k) {
      rows[c] += x[c][k] / K;
      cols[k] += x[c][k] / C;
      m.mean += x[c][k] / (C * K);
      m.square += x[c][k] * x[c][k] / (C * K);
    }
  auto var = [&](const std::vector<double>& v) {
    if (v.size() < 2) return 0.0;
    double s = 0.0;
    for (double a : v) s += (a - m.mean) * (a - m.mean);
    return s / static_cast<double>(v.size() - 1);
  };
  m.se = std::sqrt(var(rows) / C + var(cols) / K);
  return m;
}

// Position of the minimum of y over the grid x (a parabola through the
// lowest point and its neighbours; the end point when the lowest is one).
// `low`, when given, gets the parabola's lowest value.
double ArgMin(const std::vector<double>& x, const std::vector<double>& y, double* low = nullptr) {
  const std::size_t i = static_cast<std::size_t>(std::min_element(y.begin(), y.end()) - y.begin());
  if (low) *low = y[i];
  if (i == 0 || i + 1 == y.size()) return x[i];
  const double a = y[i - 1], b = y[i], c = y[i + 1], h = x[i + 1] - x[i];
  const double denominator = a - 2 * b + c;
  if (!(denominator > 0)) return x[i];
  if (low) *low = b - (a - c) * (a - c) / (8 * denominator);
  return x[i] + 0.5 * h * (a - c) / denominator;
}

}  // namespace

int main(int argc, char** argv) {
  const int K = static_cast<int>(Arg(argc, argv, "obs-seeds", 16));
  const int C = static_cast<int>(Arg(argc, argv, "cal-seeds", 4));
  // More calibration seeds, simulated at the truth only (its table).
  const int T = static_cast<int>(Arg(argc, argv, "truth-seeds", 0));
  const int points = static_cast<int>(Arg(argc, argv, "points", 11));
  const double span = Arg(argc, argv, "span", 25) / 100.0;
  const int obs_rocks = static_cast<int>(Arg(argc, argv, "obs-rocks", 120));
  const int rocks = static_cast<int>(Arg(argc, argv, "rocks", 120));
  const int threads = static_cast<int>(Arg(argc, argv, "threads", 1));
  const int scars = static_cast<int>(Arg(argc, argv, "scars", 2));
  // --max 0: the maxima left out of the misfit (MisfitOptions::include_max).
  observations::MisfitOptions misfit_options;
  misfit_options.include_max = Arg(argc, argv, "max", 1) != 0;
  // --runs G: G tracked runs of one field rock each (the field's rocks), each
  // its own group of rocks / G simulated rocks released from a point of its
  // own (posterior_twin.h's SplitIntoRuns; --run-spread), compared by their pooled
  // quantiles (the per-run residuals, whose number varies with the runs that
  // stopped, left out).
  const int runs = static_cast<int>(Arg(argc, argv, "runs", 0));
  // --run-spread r: the disc about each run's release point, m (0: the point).
  const double run_spread = bench::RealArg(argc, argv, "run-spread", 0.5);
  if (runs > 0) misfit_options.run_terms = observations::RunTerms::kPooled;
  // The measurement errors (0.1 m on heights, 1 m on stop points) times this:
  // at 0 the residuals' sigma is the Monte Carlo and sampling errors alone.
  const double error_scale = bench::RealArg(argc, argv, "error-scale", 1.0);
  if (K < 2 || C < 1 || T < 0 || points < 3 || points % 2 == 0 || obs_rocks < 10 || rocks < 10 ||
      scars < 0 || scars > 2) {
    std::fprintf(stderr,
                 "misfit_bias: --obs-seeds >= 2, --cal-seeds >= 1, --points odd >= 3, rocks >= "
                 "10, --scars 0..2\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  sites::Site site = calibrate::testing::TwinSite(rocks);
  if (runs > 0) calibrate::testing::SplitIntoRuns(runs, rocks, run_spread, &site);
  const calibrate::ParameterSpace space = calibrate::ParameterSpace::FromSite(site);
  // --truth a,b,c,d: another truth (the twin's values in its order).
  std::vector<double> truth = calibrate::testing::kTruth;
  if (const std::string given = bench::TextArg(argc, argv, "truth", ""); !given.empty()) {
    truth.clear();
    for (const char* at = given.c_str(); *at;) {
      char* end = nullptr;
      truth.push_back(std::strtod(at, &end));
      if (end == at) break;
      at = *end == ',' ? end + 1 : end;
    }
  }
  const std::size_t d = truth.size();
  bool inside = static_cast<int>(d) == space.size();
  for (std::size_t j = 0; inside && j < d; ++j)
    inside = truth[j] >= space.parameters()[j].lower && truth[j] <= space.parameters()[j].upper;
  if (!inside) {
    std::fprintf(stderr, "misfit_bias: --truth: %d values inside the twin's box\n", space.size());
    return 2;
  }

  std::vector<observations::Observations> obs;
  sites::Site field = calibrate::testing::TwinSite(runs > 0 ? runs : obs_rocks);
  if (runs > 0) calibrate::testing::SplitIntoRuns(runs, runs, run_spread, &field);
  field.scene.options.threads = threads;
  double observed_heights = 0, observed_stops = 0;
  for (int k = 0; k < K; ++k) {
    observations::Observations o = calibrate::testing::TwinObservations(
        field, truth, 5000 + static_cast<std::uint64_t>(k), runs > 0);
    o.tree_scars.resize(static_cast<std::size_t>(scars));
    o.error.height *= error_scale;
    o.error.runout *= error_scale;
    for (const auto& s : o.tree_scars) observed_heights += s.heights.size() / double(K);
    observed_stops += o.runout->distances.size() / double(K);
    obs.push_back(std::move(o));
  }

  // The grid of each axis: `points` values through the truth, `span` of the
  // range either side, inside the box.
  std::vector<std::vector<double>> grid(d);
  for (std::size_t j = 0; j < d; ++j) {
    const auto& p = space.parameters()[j];
    const double range = p.upper - p.lower, half = (points - 1) / 2;
    for (int i = 0; i < points; ++i) {
      const double v = truth[j] + (i - half) / half * span * range;
      if (v >= p.lower - 1e-12 && v <= p.upper + 1e-12) grid[j].push_back(v);
    }
  }

  // value[j][i][group][c][k]: the group's misfit; at_truth[id][c][k]: each residual.
  std::vector<std::vector<std::map<std::string, std::vector<std::vector<double>>>>> value(d);
  for (std::size_t j = 0; j < d; ++j) value[j].resize(grid[j].size());
  std::map<std::string, std::vector<std::vector<double>>> at_truth;
  std::vector<std::string> order;  // residuals in the misfit's order
  std::vector<observations::Residual> layout;
  // Each pair's residual vector: at the truth (pair c K + k) and along the axes.
  std::vector<Eigen::VectorXd> truth_vectors(static_cast<std::size_t>((C + T) * K));
  std::vector<std::vector<std::vector<Eigen::VectorXd>>> vectors(d);
  for (std::size_t j = 0; j < d; ++j)
    vectors[j].assign(grid[j].size(),
                      std::vector<Eigen::VectorXd>(static_cast<std::size_t>(C * K)));
  auto vector_of = [](const observations::Misfit& m) {
    Eigen::VectorXd v(static_cast<Eigen::Index>(m.residuals.size()));
    for (std::size_t n = 0; n < m.residuals.size(); ++n)
      v[static_cast<Eigen::Index>(n)] = m.residuals[n].value;
    return v;
  };
  const auto blank =
      std::vector<std::vector<double>>(static_cast<std::size_t>(C), std::vector<double>(K, 0.0));
  const auto blank_truth = std::vector<std::vector<double>>(static_cast<std::size_t>(C + T),
                                                            std::vector<double>(K, 0.0));
  int simulations = 0;
  for (int c = 0; c < C + T; ++c) {
    const core::Scene run =
        calibrate::RunScene(site, rocks, static_cast<std::uint64_t>(c + 1), threads);
    const calibrate::Objective objective(run, space, obs[0], misfit_options);
    auto score = [&](const std::vector<double>& theta, auto&& use) {
      core::Scene scene = objective.scene();
      space.Apply(theta, &scene);
      const core::Terrain terrain = core::BuildTerrain(scene);
      const core::SimulationResult sim = parallel::Simulate(scene, terrain);
      ++simulations;
      for (int k = 0; k < K; ++k)
        use(k, observations::ComputeMisfit(obs[static_cast<std::size_t>(k)], scene, sim,
                                           objective.misfit_options()));
    };
    // The truth: every residual, and the check against the production objective.
    score(truth, [&](int k, const observations::Misfit& m) {
      truth_vectors[static_cast<std::size_t>(c * K + k)] = vector_of(m);
      if (layout.empty()) layout = m.residuals;
      if (k == 0) {
        const observations::Misfit production = objective.Evaluate(truth);
        if (production.value != m.value) {
          std::fprintf(stderr, "misfit_bias: %.17g here against %.17g from Objective::Evaluate\n",
                       m.value, production.value);
          std::exit(1);
        }
      }
      for (const auto& r : m.residuals) {
        const std::string name = r.id.observation() + " " + r.id.quantity();
        if (!at_truth.count(name)) {
          at_truth[name] = blank_truth;
          order.push_back(name);
        }
        at_truth[name][static_cast<std::size_t>(c)][static_cast<std::size_t>(k)] = r.value;
      }
    });
    for (std::size_t j = 0; j < d && c < C; ++j)
      for (std::size_t i = 0; i < grid[j].size(); ++i) {
        std::vector<double> theta = truth;
        theta[j] = grid[j][i];
        score(theta, [&](int k, const observations::Misfit& m) {
          vectors[j][i][static_cast<std::size_t>(c * K + k)] = vector_of(m);
          auto& groups = value[j][i];
          for (const auto& r : m.residuals) {
            for (const std::string& g : {Group(r), std::string("all")}) {
              if (!groups.count(g)) groups[g] = blank;
              groups[g][static_cast<std::size_t>(c)][static_cast<std::size_t>(k)] +=
                  0.5 * r.value * r.value;
            }
          }
        });
      }
    if (c < C || (c + 1) % 20 == 0)
      std::fprintf(stderr, "calibration seed %d done (%d simulations, %.0f s)\n", c + 1,
                   simulations,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }

  std::printf("twin slope, truth");
  for (std::size_t j = 0; j < d; ++j)
    std::printf(" %s %.3g", space.parameters()[j].label().c_str(), truth[j]);
  std::printf(
      "\n%d observation seeds (%d rocks%s: %.1f heights, %.1f stop points on average), %d "
      "calibration seeds (%d rocks), %d simulations, %.0f s\n\n",
      K, runs > 0 ? runs : obs_rocks, runs > 0 ? " in as many runs" : "", observed_heights,
      observed_stops, C, rocks, simulations,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

  std::printf("At the truth (over %d x %d pairs): residual | mean | its s.e. | mean square\n",
              C + T, K);
  std::printf("|---|---|---|---|\n");
  double total_square = 0.0;
  for (const std::string& name : order) {
    const Moments m = Crossed(at_truth[name]);
    total_square += m.square;
    std::printf("| %s | %+.3f | %.3f | %.2f%s |\n", name.c_str(), m.mean, m.se, m.square,
                std::abs(m.mean) > 2.5 * m.se ? " (biased)" : "");
  }
  std::printf("sum of mean squares %.1f over %zu residuals (an honest likelihood: about %zu)\n\n",
              total_square, order.size(), order.size());

  std::printf(
      "Minimum of the mean misfit along each axis, (minimum - truth) / range in %%, "
      "and the mean misfit's rise there from its minimum to the truth:\n");
  std::vector<std::string> groups;
  for (const auto& [g, unused] : value[0][0]) groups.push_back(g);
  std::printf("| group |");
  for (std::size_t j = 0; j < d; ++j) std::printf(" %s |", space.parameters()[j].label().c_str());
  std::printf("\n|---|");
  for (std::size_t j = 0; j < d; ++j) std::printf("---|");
  std::printf("\n");
  for (const std::string& g : groups) {
    std::printf("| %s |", g.c_str());
    for (std::size_t j = 0; j < d; ++j) {
      const auto& p = space.parameters()[j];
      std::vector<double> mean, x;
      double at = 0.0;
      for (std::size_t i = 0; i < grid[j].size(); ++i) {
        const Moments m = Crossed(value[j][i].at(g));
        mean.push_back(m.mean);
        x.push_back(grid[j][i]);
        if (std::abs(grid[j][i] - truth[j]) < 1e-12) at = m.mean;
      }
      const double best = ArgMin(x, mean);
      std::printf(" %+.1f %% (%.2f) |", 100.0 * (best - truth[j]) / (p.upper - p.lower),
                  at - *std::min_element(mean.begin(), mean.end()));
    }
    std::printf("\n");
  }
  // Each pair's own minimum along each axis (the others at the truth), and
  // whether the truth lies within its 90 % likelihood-ratio interval
  // (misfit(truth) - minimum <= 1.353, half the 0.9 quantile of chi-square
  // with one degree of freedom): how the likelihood alone covers. Three
  // likelihoods of the same residuals: the misfit (independent), the
  // posterior's (each distribution's quantiles correlated,
  // calibrate::QuantileCorrelation), and the joint one of the residual
  // vector's second moments at the truth, measured over the pairs of the
  // truth-only seeds (or all when there are none): r^T S^-1 r / 2.
  const Eigen::MatrixXd w = calibrate::Whitening(calibrate::QuantileCorrelation(layout));
  const Eigen::Index n_res = static_cast<Eigen::Index>(layout.size());
  Eigen::MatrixXd second = Eigen::MatrixXd::Zero(n_res, n_res);
  const int from = T > 0 ? C : 0;
  for (int c = from; c < C + T; ++c)
    for (int k = 0; k < K; ++k) {
      const Eigen::VectorXd& v = truth_vectors[static_cast<std::size_t>(c * K + k)];
      second += v * v.transpose() / static_cast<double>((C + T - from) * K);
    }
  const Eigen::LLT<Eigen::MatrixXd> joint(second);
  const Eigen::MatrixXd joint_w = joint.matrixL().solve(Eigen::MatrixXd::Identity(n_res, n_res));
  {
    // How much the residuals overlap: the effective number of independent
    // residuals, (sum of eigenvalues)^2 / sum of squared eigenvalues of the
    // correlation matrix.
    Eigen::VectorXd sd = second.diagonal().cwiseSqrt();
    const Eigen::MatrixXd corr =
        sd.cwiseInverse().asDiagonal() * second * sd.cwiseInverse().asDiagonal();
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(corr).eigenvalues();
    std::printf(
        "\nThe residuals' correlation at the truth: %ld residuals, effective number %.1f, "
        "largest eigenvalue %.1f\n",
        static_cast<long>(n_res), ev.sum() * ev.sum() / ev.squaredNorm(), ev.maxCoeff());
  }
  struct Likelihood {
    const char* name;
    Eigen::MatrixXd whitening;
  };
  const std::vector<Likelihood> likelihoods = {
      {"independent (the misfit)", Eigen::MatrixXd::Identity(n_res, n_res)},
      {"quantiles correlated (the posterior's)", w},
      {"joint second moments at the truth", joint_w}};
  std::printf(
      "\nEach pair's own minimum along each axis (the other values at the truth): "
      "(mean - truth) / range, its standard deviation, and the share of 90 %% "
      "likelihood-ratio intervals holding the truth:\n| likelihood | parameter | mean "
      "offset | sd | covered |\n|---|---|---|---|---|\n");
  for (const bool smooth : {false, true})
    for (const Likelihood& l : likelihoods)
      for (std::size_t j = 0; j < d; ++j) {
        const auto& p = space.parameters()[j];
        const double range = p.upper - p.lower;
        double sum = 0.0, square = 0.0;
        int covered = 0;
        for (std::size_t pair = 0; pair < static_cast<std::size_t>(C * K); ++pair) {
          std::vector<double> y;
          double at = 0.0, low = 0.0;
          for (std::size_t i = 0; i < grid[j].size(); ++i) {
            y.push_back(0.5 * (l.whitening * vectors[j][i][pair]).squaredNorm());
            if (std::abs(grid[j][i] - truth[j]) < 1e-12) at = y.back();
          }
          double best = 0.0;
          if (smooth) {
            // A least-squares parabola through every point of the axis (a
            // smooth emulator's view): its minimum and its value at the truth.
            Eigen::MatrixXd a(static_cast<Eigen::Index>(y.size()), 3);
            Eigen::VectorXd b(static_cast<Eigen::Index>(y.size()));
            for (std::size_t i = 0; i < y.size(); ++i) {
              const double u = (grid[j][i] - truth[j]) / range;
              a.row(static_cast<Eigen::Index>(i)) << 1.0, u, u * u;
              b[static_cast<Eigen::Index>(i)] = y[i];
            }
            const Eigen::Vector3d q = a.colPivHouseholderQr().solve(b);
            const double u = q[2] > 0 ? std::clamp(-q[1] / (2 * q[2]), a(0, 1), a(a.rows() - 1, 1))
                                      : (q[1] > 0 ? a(0, 1) : a(a.rows() - 1, 1));
            best = u;
            at = q[0];
            low = q[0] + q[1] * u + q[2] * u * u;
          } else {
            best = (ArgMin(grid[j], y, &low) - truth[j]) / range;
          }
          sum += best;
          square += best * best;
          covered += at - low <= 1.353;
        }
        const double n = static_cast<double>(C) * K, mean = sum / n;
        std::printf("| %s%s | %s | %+.1f %% | %.1f %% | %d of %d (%.0f %%) |\n", l.name,
                    smooth ? ", parabola fitted" : "", p.label().c_str(), 100.0 * mean,
                    100.0 * std::sqrt(std::max(0.0, square / n - mean * mean)), covered, C * K,
                    100.0 * covered / n);
      }
  std::printf("\nMean misfit along each axis (all residuals):\n");
  for (std::size_t j = 0; j < d; ++j) {
    std::printf("%s:", space.parameters()[j].label().c_str());
    for (std::size_t i = 0; i < grid[j].size(); ++i)
      std::printf(" %.3g:%.1f", grid[j][i], Crossed(value[j][i].at("all")).mean);
    std::printf("\n");
  }
  return 0;
}
