#include "rockcal/calibrate/mcmc.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "rockcal/core/error.h"
#include "rockcal/core/random.h"

namespace rockcal::calibrate {
namespace {

// Random streams (RandomStream(seed, stream)): one per chain from kChainStream on.
constexpr std::uint64_t kChainStream = 0x504f535400000000ull;  // "POST"

}  // namespace

bool InUnitBox(const Eigen::VectorXd& u) {
  for (Eigen::Index k = 0; k < u.size(); ++k)
    if (!(u(k) >= 0.0 && u(k) <= 1.0)) return false;
  return true;
}

bool McmcOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (chains < 2)
    s << "chains = " << chains << ": must be >= 2";
  else if (burn_in < 100)
    s << "burn_in = " << burn_in << ": must be >= 100";
  else if (steps < 100)
    s << "steps = " << steps << ": must be >= 100";
  else if (thin < 1 || thin > steps)
    s << "thin = " << thin << ": must be in [1, steps]";
  else
    return true;
  *error = s.str();
  return false;
}

namespace {

// Each chain halved, for SplitRhat and EffectiveSampleSize: 2m sequences of
// n values (chains shorter than 2 min_half left out); empty when fewer than
// two sequences remain or their lengths differ.
std::vector<std::vector<double>> SplitChains(const std::vector<std::vector<double>>& chains,
                                             std::size_t min_half) {
  std::vector<std::vector<double>> halves;
  for (const std::vector<double>& c : chains) {
    const std::size_t n = c.size() / 2;
    if (n < min_half) continue;
    halves.emplace_back(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(n));
    halves.emplace_back(c.end() - static_cast<std::ptrdiff_t>(n), c.end());
  }
  if (halves.size() < 2) return {};
  for (const auto& h : halves)
    if (h.size() != halves.front().size()) return {};
  return halves;
}

}  // namespace

double SplitRhat(const std::vector<std::vector<double>>& chains) {
  const std::vector<std::vector<double>> halves = SplitChains(chains, 2);
  if (halves.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t n = halves.front().size();
  const double m = static_cast<double>(halves.size());
  std::vector<double> means;
  double within = 0.0;
  for (const auto& h : halves) {
    double mean = 0.0;
    for (double v : h) mean += v;
    mean /= static_cast<double>(n);
    double var = 0.0;
    for (double v : h) var += (v - mean) * (v - mean);
    within += var / static_cast<double>(n - 1) / m;
    means.push_back(mean);
  }
  double grand = 0.0;
  for (double v : means) grand += v / m;
  double between = 0.0;
  for (double v : means) between += (v - grand) * (v - grand);
  between *= static_cast<double>(n) / (m - 1.0);
  if (!(within > 0.0)) return between > 0.0 ? std::numeric_limits<double>::infinity() : 1.0;
  const double pooled = (static_cast<double>(n) - 1.0) / static_cast<double>(n) * within +
                        between / static_cast<double>(n);
  return std::sqrt(pooled / within);
}

double EffectiveSampleSize(const std::vector<std::vector<double>>& chains) {
  // Split chains, as SplitRhat; the autocorrelation at lag t from the
  // within-chain autocovariance and the pooled variance (Gelman et al. 2013,
  // Bayesian Data Analysis, 3rd ed., eq. 11.7), summed in pairs of lags
  // while a pair's sum stays positive (Geyer's initial positive sequence).
  std::vector<std::vector<double>> halves = SplitChains(chains, 4);
  if (halves.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t n = halves.front().size();
  const double m = static_cast<double>(halves.size());
  const double nn = static_cast<double>(n);
  std::vector<double> means;
  double within = 0.0;
  for (auto& h : halves) {
    double mean = 0.0;
    for (double v : h) mean += v / nn;
    double var = 0.0;
    for (double& v : h) {
      v -= mean;  // centred from here on
      var += v * v;
    }
    within += var / (nn - 1.0) / m;
    means.push_back(mean);
  }
  double grand = 0.0;
  for (double v : means) grand += v / m;
  double between = 0.0;
  for (double v : means) between += (v - grand) * (v - grand);
  between *= nn / (m - 1.0);
  const double pooled = (nn - 1.0) / nn * within + between / nn;
  if (!(pooled > 0.0)) return m * nn;  // constant chains: every draw counts
  const auto rho = [&](std::size_t t) {
    if (t == 0) return 1.0;
    double acov = 0.0;
    for (const auto& h : halves) {
      double s = 0.0;
      for (std::size_t i = 0; i + t < n; ++i) s += h[i] * h[i + t];
      acov += s / nn / m;
    }
    return 1.0 - (within - acov) / pooled;
  };
  double sum = 0.0;
  for (std::size_t t = 0; t + 1 < n; t += 2) {
    const double pair = rho(t) + rho(t + 1);
    if (!(pair > 0.0)) break;
    sum += pair;
  }
  const double tau = std::max(2.0 * sum - 1.0, 1.0 / std::log10(std::max(m * nn, 10.0)));
  return m * nn / tau;
}

McmcResult AdaptiveMetropolis(const std::function<double(const Eigen::VectorXd&)>& log_target,
                              const std::vector<Eigen::VectorXd>& starts,
                              const McmcOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("posterior sampler options", error);
  if (starts.empty()) throw std::invalid_argument("AdaptiveMetropolis: no starting point");
  const Eigen::Index d = starts.front().size();
  const std::size_t chains = static_cast<std::size_t>(options.chains);
  McmcResult out;
  std::vector<std::vector<std::vector<double>>> traces(static_cast<std::size_t>(d),
                                                       std::vector<std::vector<double>>(chains));
  std::vector<std::vector<Eigen::VectorXd>> kept(chains);
  long accepted = 0, proposed = 0;
  // The chains advance in lock step, each on its own random stream, so that
  // the proposal's covariance can pool them: (2.38^2 / d) times the
  // covariance of every chain's states since a quarter of the burn-in
  // (Haario et al. 2001, pooled over chains: a chain that started in a
  // narrow corner learns the posterior's extent from the others), and a
  // global scale per chain tuned towards an acceptance of 0.234 (Andrieu &
  // Thoms 2008, A tutorial on adaptive MCMC, Statistics and Computing
  // 18:343-373, algorithm 4). Both frozen after the burn-in.
  std::vector<core::RandomStream> rng;
  std::vector<Eigen::VectorXd> x(chains);
  std::vector<double> lp(chains);
  const double log_scale0 = std::log(2.38 * 2.38 / static_cast<double>(d));
  std::vector<double> log_scale(chains, log_scale0);
  for (std::size_t c = 0; c < chains; ++c) {
    rng.emplace_back(options.seed, kChainStream + static_cast<std::uint64_t>(c));
    x[c] = starts[c % starts.size()];
    for (Eigen::Index k = 0; k < d; ++k) x[c](k) = std::clamp(x[c](k), 0.0, 1.0);
    lp[c] = log_target(x[c]);
  }
  // At first 0.1 of the box along each axis (scale applied below).
  Eigen::MatrixXd chol = Eigen::MatrixXd::Identity(d, d) * (0.1 / std::exp(0.5 * log_scale0));
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(d);
  Eigen::MatrixXd m2 = Eigen::MatrixXd::Zero(d, d);
  long count = 0;
  const int pool_from = options.burn_in / 4;
  const int total = options.burn_in + options.steps;
  for (int step = 0; step < total; ++step) {
    const bool burn = step < options.burn_in;
    for (std::size_t c = 0; c < chains; ++c) {
      Eigen::VectorXd z(d);
      for (Eigen::Index k = 0; k < d; ++k) z(k) = rng[c].Normal();
      const Eigen::VectorXd y = x[c] + std::exp(0.5 * log_scale[c]) * (chol * z);
      const double log_u = std::log(std::max(rng[c].Uniform(), 1e-300));
      if (!burn) ++proposed;
      bool accept = false;
      if (InUnitBox(y)) {
        const double ly = log_target(y);
        if (std::isfinite(ly) && (ly >= lp[c] || log_u < ly - lp[c] || !std::isfinite(lp[c]))) {
          x[c] = y;
          lp[c] = ly;
          accept = true;
          if (!burn) ++accepted;
        }
      }
      if (burn) {
        // Robbins-Monro on the log scale, the gain falling as 1 / sqrt(step).
        log_scale[c] += ((accept ? 1.0 : 0.0) - 0.234) / std::sqrt(1.0 + step);
        log_scale[c] = std::clamp(log_scale[c], std::log(1e-4), std::log(100.0));
        if (step >= pool_from) {
          ++count;
          const Eigen::VectorXd delta = x[c] - mean;
          mean += delta / static_cast<double>(count);
          m2 += delta * (x[c] - mean).transpose();
        }
        continue;
      }
      for (Eigen::Index k = 0; k < d; ++k)
        traces[static_cast<std::size_t>(k)][c].push_back(x[c](k));
      if ((step - options.burn_in) % options.thin == 0) kept[c].push_back(x[c]);
    }
    if (burn && count >= 200 && (step + 1) % 50 == 0) {
      const Eigen::MatrixXd cov =
          m2 / static_cast<double>(count - 1) + 1e-8 * Eigen::MatrixXd::Identity(d, d);
      Eigen::LLT<Eigen::MatrixXd> llt(cov);
      if (llt.info() == Eigen::Success) chol = llt.matrixL();
    }
  }
  for (auto& c : kept)
    for (auto& s : c) out.samples.push_back(std::move(s));
  for (Eigen::Index k = 0; k < d; ++k) {
    out.rhat.push_back(SplitRhat(traces[static_cast<std::size_t>(k)]));
    out.ess.push_back(EffectiveSampleSize(traces[static_cast<std::size_t>(k)]));
  }
  out.acceptance = proposed ? static_cast<double>(accepted) / static_cast<double>(proposed) : 0.0;
  return out;
}

}  // namespace rockcal::calibrate
