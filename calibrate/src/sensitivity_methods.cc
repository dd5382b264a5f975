// The sensitivity methods on any model (sensitivity.h): Morris' elementary
// effects and Sobol's indices with their bootstrap intervals, by name. The
// site study that runs them on a scene is sensitivity.cc.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/core/name_table.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using text::Num;

using core::kNaN;
// Random streams of the sampling, apart from the rocks' streams (rock index).
constexpr std::uint64_t kMorrisStream = (std::uint64_t{1} << 52) + 1;
constexpr std::uint64_t kSobolStream = (std::uint64_t{1} << 52) + 2;
constexpr std::uint64_t kSobolBootstrapStream = (std::uint64_t{1} << 52) + 3;

// Runs the model once and checks the length of its answer.
std::vector<double> Run(const SensitivityModel& model, const std::vector<double>& x, int outputs) {
  std::vector<double> y = model(x);
  if (static_cast<int>(y.size()) != outputs)
    throw std::invalid_argument("sensitivity model returned " + std::to_string(y.size()) +
                                " outputs, expected " + std::to_string(outputs));
  return y;
}

void CheckShape(const char* what, int parameters, int outputs) {
  if (parameters < 1)
    throw std::invalid_argument(std::string(what) + ": needs at least one parameter");
  if (outputs < 1) throw std::invalid_argument(std::string(what) + ": needs at least one output");
}

// Central `confidence` percentile interval of the finite values; NaNs when
// fewer than half are finite.
std::pair<double, double> Interval(std::vector<double> values, double confidence) {
  const std::size_t all = values.size();
  values.erase(
      std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
      values.end());
  if (values.empty() || 2 * values.size() < all) return {kNaN, kNaN};
  std::sort(values.begin(), values.end());
  const double tail = 0.5 * (1.0 - confidence);
  return {core::Quantile(values, tail), core::Quantile(values, 1.0 - tail)};
}

}  // namespace

// ---- Methods by name -------------------------------------------------------------

namespace {
constexpr core::Named<SensitivityMethod> kSensitivityMethods[] = {
    {SensitivityMethod::kMorris, "morris"}, {SensitivityMethod::kSobol, "sobol"}};
}  // namespace

const char* SensitivityMethodToString(SensitivityMethod method) {
  return core::NameOf(kSensitivityMethods, method);
}
std::string SensitivityMethodNames() { return core::NameList(kSensitivityMethods); }
bool StringToSensitivityMethod(const std::string& name, SensitivityMethod* method) {
  return core::IdOf(kSensitivityMethods, name, method);
}

// ---- Morris -------------------------------------------------------------------------

bool MorrisOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
    *error = "morris." + field + " = " + value + ": " + rule;
    return false;
  };
  if (trajectories < 2 || trajectories > 100000)
    return fail("trajectories", std::to_string(trajectories),
                "must be in [2, 100000] (sigma needs two effects)");
  if (levels < 2 || levels > 100 || levels % 2 != 0)
    return fail("levels", std::to_string(levels),
                "must be even and in [2, 100] (so that Delta = p / (2 (p - 1)) joins grid levels)");
  return true;
}

MorrisResult RunMorris(int k, int m, const SensitivityModel& model, const MorrisOptions& opt) {
  std::string error;
  if (!opt.IsValid(&error)) throw std::invalid_argument(error);
  CheckShape("RunMorris", k, m);
  const int p = opt.levels, half = p / 2;
  MorrisResult out;
  out.parameters = k;
  out.outputs = m;
  out.trajectories = opt.trajectories;
  out.levels = p;
  out.delta = static_cast<double>(half) / (p - 1);
  out.evaluations = opt.trajectories * (k + 1);
  // effects[o][i]: the finite elementary effects.
  std::vector<std::vector<std::vector<double>>> effects(
      static_cast<std::size_t>(m), std::vector<std::vector<double>>(static_cast<std::size_t>(k)));
  core::RandomStream rng(opt.seed, kMorrisStream);
  const std::size_t ku = static_cast<std::size_t>(k);
  int done = 0;
  for (int t = 0; t < opt.trajectories; ++t) {
    // Per parameter a direction and a start level from which a step of
    // `half` levels in that direction stays on the grid; a random order.
    std::vector<int> level(ku), dir(ku);
    for (std::size_t i = 0; i < ku; ++i) {
      dir[i] = rng.Uniform() < 0.5 ? 1 : -1;
      const int start = static_cast<int>(rng.Index(static_cast<std::size_t>(half)));
      level[i] = dir[i] > 0 ? start : half + start;
    }
    std::vector<std::size_t> order(ku);
    for (std::size_t i = 0; i < ku; ++i) order[i] = i;
    for (std::size_t i = ku; i > 1; --i) std::swap(order[i - 1], order[rng.Index(i)]);

    auto point = [&] {
      std::vector<double> x(ku);
      for (std::size_t i = 0; i < ku; ++i) x[i] = static_cast<double>(level[i]) / (p - 1);
      return x;
    };
    std::vector<double> y = Run(model, point(), m);
    if (opt.progress) opt.progress(++done, out.evaluations);
    for (std::size_t i : order) {
      level[i] += dir[i] * half;
      std::vector<double> y_next = Run(model, point(), m);
      if (opt.progress) opt.progress(++done, out.evaluations);
      for (std::size_t o = 0; o < static_cast<std::size_t>(m); ++o) {
        const double ee = (y_next[o] - y[o]) / (dir[i] * out.delta);
        if (std::isfinite(ee)) effects[o][i].push_back(ee);
      }
      y = std::move(y_next);
    }
  }
  out.index.assign(static_cast<std::size_t>(m), std::vector<MorrisIndex>(ku));
  for (std::size_t o = 0; o < static_cast<std::size_t>(m); ++o) {
    for (std::size_t i = 0; i < ku; ++i) {
      const std::vector<double>& e = effects[o][i];
      MorrisIndex& idx = out.index[o][i];
      idx.effects = static_cast<int>(e.size());
      if (e.empty()) {
        idx.mu = idx.mu_star = idx.sigma = kNaN;
        continue;
      }
      double sum = 0.0, sum_abs = 0.0;
      for (double v : e) sum += v, sum_abs += std::abs(v);
      const double n = static_cast<double>(e.size());
      idx.mu = sum / n;
      idx.mu_star = sum_abs / n;
      if (e.size() < 2) {
        idx.sigma = kNaN;
      } else {
        idx.sigma = core::SampleStandardDeviation(e);
      }
    }
  }
  return out;
}

// ---- Sobol ----------------------------------------------------------------------------

bool SobolOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
    *error = "sobol." + field + " = " + value + ": " + rule;
    return false;
  };
  if (samples < 4 || samples > 10000000)
    return fail("samples", std::to_string(samples), "must be in [4, 10000000]");
  if (bootstrap < 20 || bootstrap > 100000)
    return fail("bootstrap", std::to_string(bootstrap), "must be in [20, 100000]");
  if (!(confidence > 0.5 && confidence < 1))
    return fail("confidence", Num(confidence), "must be in (0.5, 1)");
  return true;
}

namespace {

// The indices of one output from the rows `pick` (indices into the N rows,
// repeats allowed): fa[n], fb[n], fab[i][n]. S_i = mean((f(B) - f0) (f(A_B^i)
// - f(A))) / V (Saltelli et al. 2010, table 2, with f(B) centred on the mean
// f0 of f(A) and f(B)); ST_i = mean((f(A) - f(A_B^i))^2) / (2 V) (Jansen
// 1999); V the variance of the 2N values of f(A) and f(B).
void SobolEstimate(const std::vector<double>& fa, const std::vector<double>& fb,
                   const std::vector<std::vector<double>>& fab,
                   const std::vector<std::size_t>& pick, std::vector<double>* first,
                   std::vector<double>* total) {
  const std::size_t k = fab.size();
  first->assign(k, kNaN);
  total->assign(k, kNaN);
  const double n = static_cast<double>(pick.size());
  if (pick.size() < 2) return;
  double mean = 0.0;
  for (std::size_t r : pick) mean += fa[r] + fb[r];
  mean /= 2.0 * n;
  double var = 0.0;
  for (std::size_t r : pick)
    var += (fa[r] - mean) * (fa[r] - mean) + (fb[r] - mean) * (fb[r] - mean);
  var /= 2.0 * n - 1.0;
  if (!(var > 0.0)) return;
  for (std::size_t i = 0; i < k; ++i) {
    double v1 = 0.0, vt = 0.0;
    for (std::size_t r : pick) {
      // f(B) centred: the same expectation (the differences average to 0),
      // far less spread when the output's mean is large against its spread.
      v1 += (fb[r] - mean) * (fab[i][r] - fa[r]);
      vt += (fa[r] - fab[i][r]) * (fa[r] - fab[i][r]);
    }
    (*first)[i] = v1 / n / var;
    (*total)[i] = vt / (2.0 * n) / var;
  }
}

}  // namespace

SobolResult RunSobol(int k, int m, const SensitivityModel& model, const SobolOptions& opt) {
  std::string error;
  if (!opt.IsValid(&error)) throw std::invalid_argument(error);
  CheckShape("RunSobol", k, m);
  const std::size_t ku = static_cast<std::size_t>(k), mu = static_cast<std::size_t>(m);
  const std::size_t nu = static_cast<std::size_t>(opt.samples);
  SobolResult out;
  out.parameters = k;
  out.outputs = m;
  out.samples = opt.samples;
  out.bootstrap = opt.bootstrap;
  out.confidence = opt.confidence;
  out.evaluations = opt.samples * (k + 2);

  core::RandomStream rng(opt.seed, kSobolStream);
  std::vector<std::vector<double>> a(nu, std::vector<double>(ku)), b = a;
  for (std::size_t r = 0; r < nu; ++r) {
    for (double& v : a[r]) v = rng.Uniform();
    for (double& v : b[r]) v = rng.Uniform();
  }
  // Values per output: fa[o][r], fb[o][r], fab[o][i][r].
  std::vector<std::vector<double>> fa(mu, std::vector<double>(nu)), fb = fa;
  std::vector<std::vector<std::vector<double>>> fab(mu,
                                                    std::vector<std::vector<double>>(ku, fa[0]));
  int done = 0;
  auto progress = [&] {
    if (opt.progress) opt.progress(++done, out.evaluations);
  };
  for (std::size_t r = 0; r < nu; ++r) {
    const std::vector<double> ya = Run(model, a[r], m);
    progress();
    const std::vector<double> yb = Run(model, b[r], m);
    progress();
    for (std::size_t o = 0; o < mu; ++o) fa[o][r] = ya[o], fb[o][r] = yb[o];
    for (std::size_t i = 0; i < ku; ++i) {
      std::vector<double> x = a[r];
      x[i] = b[r][i];
      const std::vector<double> y = Run(model, x, m);
      progress();
      for (std::size_t o = 0; o < mu; ++o) fab[o][i][r] = y[o];
    }
  }

  core::RandomStream boot(opt.seed, kSobolBootstrapStream);
  out.variance.assign(mu, kNaN);
  out.rows.assign(mu, 0);
  out.index.assign(mu, std::vector<SobolIndex>(ku));
  std::vector<double> first, total;
  for (std::size_t o = 0; o < mu; ++o) {
    std::vector<std::size_t> rows;
    for (std::size_t r = 0; r < nu; ++r) {
      bool finite = std::isfinite(fa[o][r]) && std::isfinite(fb[o][r]);
      for (std::size_t i = 0; i < ku; ++i) finite = finite && std::isfinite(fab[o][i][r]);
      if (finite) rows.push_back(r);
    }
    out.rows[o] = static_cast<int>(rows.size());
    if (rows.size() >= 2) {
      double mean = 0.0, var = 0.0;
      for (std::size_t r : rows) mean += fa[o][r] + fb[o][r];
      mean /= 2.0 * static_cast<double>(rows.size());
      for (std::size_t r : rows)
        var += (fa[o][r] - mean) * (fa[o][r] - mean) + (fb[o][r] - mean) * (fb[o][r] - mean);
      out.variance[o] = var / (2.0 * static_cast<double>(rows.size()) - 1.0);
    }
    SobolEstimate(fa[o], fb[o], fab[o], rows, &first, &total);
    for (std::size_t i = 0; i < ku; ++i) {
      out.index[o][i].first = first[i];
      out.index[o][i].total = total[i];
    }
    // Bootstrap: resample the usable rows with replacement.
    std::vector<std::vector<double>> first_b(ku), total_b(ku);
    std::vector<std::size_t> pick(rows.size());
    for (int rep = 0; rep < opt.bootstrap; ++rep) {
      for (auto& r : pick) r = rows[boot.Index(rows.size())];
      SobolEstimate(fa[o], fb[o], fab[o], pick, &first, &total);
      for (std::size_t i = 0; i < ku; ++i) {
        first_b[i].push_back(first[i]);
        total_b[i].push_back(total[i]);
      }
    }
    for (std::size_t i = 0; i < ku; ++i) {
      SobolIndex& idx = out.index[o][i];
      std::tie(idx.first_low, idx.first_high) = Interval(first_b[i], opt.confidence);
      std::tie(idx.total_low, idx.total_high) = Interval(total_b[i], opt.confidence);
      if (rows.empty()) idx.first_low = idx.first_high = idx.total_low = idx.total_high = kNaN;
    }
  }
  return out;
}

}  // namespace rockcal::calibrate
