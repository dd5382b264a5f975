#include "rockcal/calibrate/posterior.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/random.h"
#include "rockcal/parallel/parallel.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kMinusInf = -std::numeric_limits<double>::infinity();
// Random streams (RandomStream(seed, stream)): one per chain from kChainStream on.
constexpr std::uint64_t kChainStream = 0x504f535400000000ull;   // "POST"
constexpr std::uint64_t kDesignSeedMix = 0x44455349474e0000ull;  // "DESIGN"

bool Inside(const Eigen::VectorXd& u) {
  for (Eigen::Index k = 0; k < u.size(); ++k)
    if (!(u(k) >= 0.0 && u(k) <= 1.0)) return false;
  return true;
}

}  // namespace

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

double Quantile(std::vector<double>* values, double p) {
  if (values->empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values->begin(), values->end());
  const double position = p * static_cast<double>(values->size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(values->size() - 1, below + 1);
  const double t = position - static_cast<double>(below);
  return (*values)[below] + t * ((*values)[above] - (*values)[below]);
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
  std::vector<std::vector<std::vector<double>>> traces(
      static_cast<std::size_t>(d), std::vector<std::vector<double>>(chains));
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
      if (Inside(y)) {
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

bool PosteriorOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (design_points < 0)
    s << "design_points = " << design_points << ": must be >= 0 (0: 6 (d + 1))";
  else if (rounds < 0)
    s << "rounds = " << rounds << ": must be >= 0";
  else if (round_points < 0)
    s << "round_points = " << round_points << ": must be >= 0 (0: 2 (d + 1))";
  else if (!(settled_variance >= 0.0))
    s << "settled_variance = " << settled_variance << ": must be >= 0";
  else if (!(warp > 0.0))
    s << "warp = " << warp << ": must be > 0";
  else if (!(undetermined_share > 0.0 && undetermined_share <= 1.0))
    s << "undetermined_share = " << undetermined_share << ": must be in (0, 1]";
  else
    return mcmc.IsValid(error) && emulator.IsValid(error);
  *error = s.str();
  return false;
}

int PosteriorOptions::DesignPoints(int parameters) const {
  return design_points > 0 ? design_points : 6 * (parameters + 1);
}
int PosteriorOptions::RoundPoints(int parameters) const {
  return round_points > 0 ? round_points : 2 * (parameters + 1);
}

namespace {

// The emulated points: unit-box coordinates and warped residuals.
struct Design {
  std::vector<std::vector<double>> unit;
  std::vector<std::vector<double>> warped;
  std::vector<double> misfit;

  bool Has(const std::vector<double>& u) const {
    for (const auto& p : unit) {
      double d2 = 0.0;
      for (std::size_t k = 0; k < u.size(); ++k) d2 += (p[k] - u[k]) * (p[k] - u[k]);
      if (d2 < 1e-20) return true;
    }
    return false;
  }
  const Eigen::MatrixXd* whitening = nullptr;  // null: none

  void Add(const std::vector<double>& u, const std::vector<double>& residuals, double m,
           double warp) {
    if (Has(u)) return;
    Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(residuals.data(),
                                                          static_cast<Eigen::Index>(residuals.size()));
    if (whitening) r = *whitening * r;
    std::vector<double> w;
    for (Eigen::Index k = 0; k < r.size(); ++k) w.push_back(warp * std::asinh(r(k) / warp));
    unit.push_back(u);
    warped.push_back(std::move(w));
    misfit.push_back(m);
  }
};

// The emulated residuals at u (unwarped mean, and variance by the delta
// method), folded into the log-likelihood: each residual r ~ N(mu, v) under
// the emulator, so E[exp(-r^2 / 2)] = exp(-mu^2 / (2 (1 + v))) / sqrt(1 + v).
struct EmulatedTarget {
  const Emulator* emulator;
  double warp;

  double LogDensity(const Eigen::VectorXd& u, double* mean_variance = nullptr) const {
    if (!Inside(u)) return kMinusInf;
    Eigen::VectorXd mean, variance;
    emulator->Predict(u, &mean, &variance);
    double value = 0.0, vsum = 0.0;
    for (Eigen::Index j = 0; j < mean.size(); ++j) {
      const double t = mean(j) / warp;
      const double mu = warp * std::sinh(t);
      const double slope = std::cosh(t);
      const double v = variance(j) * slope * slope;
      value += -0.5 * mu * mu / (1.0 + v) - 0.5 * std::log1p(v);
      vsum += v;
    }
    if (mean_variance) *mean_variance = vsum / static_cast<double>(mean.size());
    return value;
  }
};

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// The chains' starts: the design points of lowest misfit, distinct.
std::vector<Eigen::VectorXd> Starts(const Design& design, int chains) {
  std::vector<std::size_t> order(design.unit.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return design.misfit[a] < design.misfit[b]; });
  std::vector<Eigen::VectorXd> starts;
  for (std::size_t k = 0; k < order.size() && static_cast<int>(starts.size()) < chains; ++k) {
    const auto& u = design.unit[order[k]];
    starts.push_back(Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size())));
  }
  return starts;
}

// Evaluates the unit-box points `units` through the log (replayed where
// logged as "posterior"), appending new evaluations as each finishes.
std::vector<Evaluation> EvaluatePoints(const ObjectiveFunction& objective,
                                       const std::vector<std::vector<double>>& units,
                                       EvaluationLog* log, const std::string& stage,
                                       const PosteriorProgress& progress, int* simulated,
                                       const Clock::time_point& start) {
  std::vector<Evaluation> out(units.size());
  std::vector<std::vector<double>> missing;
  std::vector<std::size_t> where;
  for (std::size_t k = 0; k < units.size(); ++k) {
    const std::vector<double> x = objective.space().ToPhysical(units[k]);
    const Evaluation* logged = log ? log->Find(Stage::Posterior(), x) : nullptr;
    if (logged && logged->residuals.size() == static_cast<std::size_t>(objective.residual_count())) {
      out[k] = *logged;
      out[k].replayed = true;
    } else {
      missing.push_back(x);
      where.push_back(k);
    }
  }
  int done = static_cast<int>(units.size() - missing.size());
  if (progress) progress(stage, done, static_cast<int>(units.size()));
  const int base = log ? log->size() : 0;
  objective.EvaluateAll(missing, [&](int i, const observations::Misfit& m) {
    Evaluation& e = out[where[static_cast<std::size_t>(i)]];
    e.stage = Stage::Posterior();
    e.index = base + i + 1;
    e.parameters = missing[static_cast<std::size_t>(i)];
    e.misfit = m.value;
    e.penalised = m.penalised;
    for (const auto& r : m.residuals) e.residuals.push_back(r.value);
    e.elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (log) log->Append(e);
    ++*simulated;
    ++done;
    if (progress) progress(stage, done, static_cast<int>(units.size()));
  });
  return out;
}

// Adds the unpenalised evaluations to the design.
int AddEvaluations(const ObjectiveFunction& objective, const std::vector<Evaluation>& evaluations,
                   double warp, Design* design) {
  int added = 0;
  for (const Evaluation& e : evaluations) {
    if (e.penalised || e.parameters.empty() ||
        e.residuals.size() != static_cast<std::size_t>(objective.residual_count()))
      continue;
    const std::size_t before = design->unit.size();
    design->Add(objective.space().ToUnit(e.parameters), e.residuals, e.misfit, warp);
    added += static_cast<int>(design->unit.size() - before);
  }
  return added;
}

// The refining round's new points: among the posterior samples, the one where
// the emulator is least sure, then again with the variance of the others
// damped near each point taken (as if it were known there).
std::vector<std::vector<double>> RefinePoints(const Emulator& emulator, const EmulatedTarget& target,
                                              const std::vector<Eigen::VectorXd>& samples, int count,
                                              double settled, const Design& design) {
  std::vector<double> score(samples.size());
  bool any = false;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    double v = 0.0;
    target.LogDensity(samples[k], &v);
    score[k] = v;
    if (v > settled) any = true;
  }
  std::vector<std::vector<double>> chosen;
  if (!any) return chosen;
  const Eigen::VectorXd& length = emulator.length_scales();
  while (static_cast<int>(chosen.size()) < count) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < samples.size(); ++k)
      if (score[k] > score[best]) best = k;
    if (!(score[best] > settled)) break;
    const Eigen::VectorXd p = samples[best];
    if (!design.Has(ToStd(p))) chosen.push_back(ToStd(p));
    for (std::size_t k = 0; k < samples.size(); ++k) {
      const double r = (samples[k] - p).cwiseQuotient(length).norm();
      const double c = Matern52(r);
      score[k] *= 1.0 - c * c;
    }
    score[best] = 0.0;
  }
  return chosen;
}

// The summaries of result->samples from `chains` (SummariseSamples, with
// their unthinned R-hat and ESS) and the message on R-hat and the emulator.
void Summarise(const McmcResult& chains, const PosteriorOptions& options, PosteriorResult* result) {
  result->chains = options.mcmc.chains;
  SummariseSamples(options.undetermined_share, &chains, result);
  std::ostringstream message;
  if (!(result->max_rhat < 1.1))
    message << "R-hat " << result->max_rhat
            << " above 1.1: the chains disagree (a multimodal or poorly emulated posterior); "
               "give more design points or rounds. ";
  if (result->emulator_variance > 0.25)
    message << "the emulator is unsure where the posterior is (variance "
            << result->emulator_variance
            << " sigma^2 per residual): the intervals are wider than the data alone give; "
               "give more rounds or points. ";
  result->message = message.str();
  while (!result->message.empty() && result->message.back() == ' ') result->message.pop_back();
}

}  // namespace

ParameterPosterior SummariseValues(std::vector<double> values, int chains, double prior_width,
                                   double undetermined_share) {
  ParameterPosterior p;
  const std::size_t n = values.size();
  for (double x : values) p.mean += x / static_cast<double>(n);
  for (double x : values) p.sd += (x - p.mean) * (x - p.mean);
  p.sd = std::sqrt(p.sd / std::max<double>(1.0, static_cast<double>(n) - 1.0));
  p.rhat = p.ess = std::numeric_limits<double>::quiet_NaN();
  if (chains >= 2 && n % static_cast<std::size_t>(chains) == 0) {
    const std::size_t length = n / static_cast<std::size_t>(chains);
    std::vector<std::vector<double>> split;
    for (std::size_t c = 0; c < static_cast<std::size_t>(chains); ++c)
      split.emplace_back(values.begin() + static_cast<std::ptrdiff_t>(c * length),
                         values.begin() + static_cast<std::ptrdiff_t>((c + 1) * length));
    p.rhat = SplitRhat(split);
    p.ess = EffectiveSampleSize(split);
  }
  p.p05 = Quantile(&values, 0.05);
  p.median = Quantile(&values, 0.5);
  p.p95 = Quantile(&values, 0.95);
  p.width_share = (p.p95 - p.p05) / prior_width;
  p.undetermined = p.width_share > undetermined_share;
  return p;
}

void SummariseSamples(double undetermined_share, const McmcResult* traces,
                      PosteriorResult* result) {
  const std::size_t d = result->space.parameters().size();
  const std::size_t n = result->samples.size();
  result->parameters.clear();
  result->max_rhat = 0.0;
  std::vector<double> means(d, 0.0), sds(d, 0.0);
  for (std::size_t k = 0; k < d; ++k) {
    std::vector<double> v;
    for (const auto& s : result->samples) v.push_back(s[k]);
    const Parameter& par = result->space.parameters()[k];
    ParameterPosterior p = SummariseValues(std::move(v), traces ? 0 : result->chains,
                                           0.9 * (par.upper - par.lower), undetermined_share);
    if (traces) {
      p.rhat = traces->rhat[k];
      p.ess = traces->ess[k];
    }
    result->max_rhat = std::max(result->max_rhat, p.rhat);
    result->min_ess = k == 0 ? p.ess : std::min(result->min_ess, p.ess);
    means[k] = p.mean;
    sds[k] = p.sd;
    result->parameters.push_back(p);
  }
  result->correlation.assign(d, std::vector<double>(d, 0.0));
  for (std::size_t a = 0; a < d; ++a)
    for (std::size_t b = 0; b < d; ++b) {
      double c = 0.0;
      for (const auto& s : result->samples) c += (s[a] - means[a]) * (s[b] - means[b]);
      c /= std::max<double>(1.0, static_cast<double>(n) - 1.0);
      result->correlation[a][b] = sds[a] > 0 && sds[b] > 0 ? c / (sds[a] * sds[b]) : (a == b);
    }
}

PosteriorResult MapPosterior(
    const PosteriorResult& from, ParameterSpace space,
    const std::function<std::vector<double>(const std::vector<double>&)>& map,
    double undetermined_share) {
  PosteriorResult out;
  out.space = std::move(space);
  out.chains = from.chains;
  for (const std::vector<double>& s : from.samples) out.samples.push_back(map(s));
  SummariseSamples(undetermined_share, nullptr, &out);
  return out;
}

PosteriorResult SamplePosterior(const ObjectiveFunction& objective,
                                const std::vector<Evaluation>& reused,
                                const PosteriorOptions& options, EvaluationLog* log,
                                const PosteriorProgress& progress,
                                const std::vector<observations::Residual>& layout) {
  const auto start = Clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw InputError("posterior options", error);
  const ParameterSpace& space = objective.space();
  const int d = space.size();
  PosteriorResult result;
  result.space = space;
  Design design;
  Eigen::MatrixXd whitening;
  if (options.correlated_quantiles &&
      layout.size() == static_cast<std::size_t>(objective.residual_count())) {
    whitening = QuantileWhitening(layout);
    design.whitening = &whitening;
  }
  result.reused = AddEvaluations(objective, reused, options.warp, &design);

  // The space-filling design, topping the reused evaluations up.
  const int wanted = options.DesignPoints(d) - static_cast<int>(design.unit.size());
  if (wanted > 0) {
    const auto points = SpaceFillingDesign(DesignKind::kLatinHypercube, wanted, d,
                                           options.mcmc.seed ^ kDesignSeedMix);
    const std::vector<Evaluation> e =
        EvaluatePoints(objective, points, log, "design", progress, &result.simulated, start);
    result.evaluated += static_cast<int>(points.size());
    AddEvaluations(objective, e, options.warp, &design);
  }
  if (static_cast<int>(design.unit.size()) < d + 3)
    throw std::runtime_error("posterior: " + std::to_string(design.unit.size()) +
                             " unpenalised evaluations to emulate " + std::to_string(d) +
                             " parameters; need at least " + std::to_string(d + 3) +
                             " (give more design points)");

  McmcOptions round_mcmc = options.mcmc;
  round_mcmc.steps = std::max(100, options.mcmc.steps / 2);
  round_mcmc.thin = std::min(round_mcmc.thin, round_mcmc.steps);
  for (int round = 0; round < options.rounds; ++round) {
    if (progress) progress("emulator, round " + std::to_string(round + 1), 0, 1);
    const Emulator emulator = Emulator::Fit(design.unit, design.warped, options.emulator);
    const EmulatedTarget target{&emulator, options.warp};
    round_mcmc.seed = options.mcmc.seed + 7919ull * static_cast<std::uint64_t>(round + 1);
    const McmcResult chains = AdaptiveMetropolis(
        [&](const Eigen::VectorXd& u) { return target.LogDensity(u); },
        Starts(design, round_mcmc.chains), round_mcmc);
    const auto points = RefinePoints(emulator, target, chains.samples, options.RoundPoints(d),
                                     options.settled_variance, design);
    if (points.empty()) break;
    ++result.rounds;
    const std::vector<Evaluation> e =
        EvaluatePoints(objective, points, log, "round " + std::to_string(round + 1), progress,
                       &result.simulated, start);
    result.evaluated += static_cast<int>(points.size());
    AddEvaluations(objective, e, options.warp, &design);
  }

  if (progress) progress("sampling", 0, 1);
  const Emulator emulator = Emulator::Fit(design.unit, design.warped, options.emulator);
  const EmulatedTarget target{&emulator, options.warp};
  const McmcResult chains = AdaptiveMetropolis(
      [&](const Eigen::VectorXd& u) { return target.LogDensity(u); },
      Starts(design, options.mcmc.chains), options.mcmc);
  result.emulated = emulator.points();
  result.length_scales = ToStd(emulator.length_scales());
  result.nugget = emulator.nugget();
  result.acceptance = chains.acceptance;
  std::vector<double> variances;
  for (const Eigen::VectorXd& u : chains.samples) {
    double v = 0.0;
    target.LogDensity(u, &v);
    variances.push_back(v);
    result.samples.push_back(space.ToPhysical(ToStd(u)));
  }
  result.emulator_variance = Quantile(&variances, 0.5);

  Summarise(chains, options, &result);
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

Eigen::MatrixXd QuantileWhitening(const std::vector<observations::Residual>& layout) {
  const Eigen::Index n = static_cast<Eigen::Index>(layout.size());
  Eigen::MatrixXd w = Eigen::MatrixXd::Identity(n, n);
  // The quantile residuals of each observation: (index, level).
  std::map<observations::ResidualId, std::vector<std::pair<Eigen::Index, double>>> groups;
  for (Eigen::Index k = 0; k < n; ++k) {
    const observations::ResidualId& id = layout[static_cast<std::size_t>(k)].id;
    if (id.statistic != observations::Statistic::kQuantile || !(id.level > 0.0 && id.level < 1.0))
      continue;
    groups[id.observation_id()].push_back({k, id.level});
  }
  for (const auto& [name, members] : groups) {
    const Eigen::Index m = static_cast<Eigen::Index>(members.size());
    if (m < 2) continue;
    Eigen::MatrixXd corr(m, m);
    for (Eigen::Index i = 0; i < m; ++i)
      for (Eigen::Index j = 0; j < m; ++j) {
        double p = members[static_cast<std::size_t>(i)].second, q = members[static_cast<std::size_t>(j)].second;
        if (p > q) std::swap(p, q);
        corr(i, j) = std::sqrt(p * (1.0 - q) / (q * (1.0 - p)));
      }
    Eigen::LLT<Eigen::MatrixXd> llt(corr);
    if (llt.info() != Eigen::Success) continue;
    const Eigen::MatrixXd block =
        llt.matrixL().solve(Eigen::MatrixXd::Identity(m, m));  // L^-1: |L^-1 r|^2 = r^T C^-1 r
    for (Eigen::Index i = 0; i < m; ++i)
      for (Eigen::Index j = 0; j < m; ++j)
        w(members[static_cast<std::size_t>(i)].first, members[static_cast<std::size_t>(j)].first) =
            block(i, j);
  }
  return w;
}

PredictiveDraw SiteDraw(const sites::Site& site, const observations::Observations& obs,
                        const observations::MisfitOptions& misfit, const ParameterSpace& space,
                        int rocks, int threads) {
  return [&site, &obs, misfit, space, rocks, threads](const std::vector<double>& physical,
                                                      std::uint64_t seed) {
    core::Scene scene = RunScene(site, rocks, seed, threads);
    space.Apply(physical, &scene);
    RecordingNeeds needs;
    needs.observations = &obs;
    needs.partitions = true;
    needs.energy_check = scene.options.record.energy_check;
    scene.options.record = RecordingFor(scene, needs);
    PredictiveOutcome out;
    try {
      const core::SimulationResult sim = parallel::Simulate(scene);
      out.misfit = observations::ComputeMisfit(obs, scene, sim, misfit);
      out.statistics =
          DrawStatistics(scene, core::ComputeStats(scene, sim), static_cast<int>(sim.rocks.size()));
    } catch (const std::exception& e) {
      out = PredictiveOutcome{};
      out.misfit.penalised = true;
      out.misfit.message = std::string("simulation failed: ") + e.what();
    }
    return out;
  };
}

namespace {

// A predictive draw's outcome as bytes for parallel::Map, and back.
std::string EncodeOutcome(const PredictiveOutcome& outcome) {
  parallel::Writer w;
  w.String(EncodeMisfit(outcome.misfit));
  w.Int(static_cast<long long>(outcome.statistics.size()));
  for (const DrawValue& v : outcome.statistics) {
    w.String(v.where);
    w.String(v.quantity);
    w.String(v.unit);
    w.Double(v.value);
  }
  return w.bytes();
}

PredictiveOutcome DecodeOutcome(const std::string& bytes) {
  parallel::Reader r(bytes);
  PredictiveOutcome out;
  out.misfit = DecodeMisfit(r.String());
  out.statistics.resize(static_cast<std::size_t>(r.Int()));
  for (DrawValue& v : out.statistics) {
    v.where = r.String();
    v.quantity = r.String();
    v.unit = r.String();
    v.value = r.Double();
  }
  return out;
}

}  // namespace

void PredictiveBands(const PredictiveDraw& draw, std::uint64_t seed, int rocks, int draws,
                     PosteriorResult* result, const PosteriorProgress& progress) {
  result->bands.clear();
  result->statistic_bands.clear();
  if (draws <= 0 || result->samples.empty()) return;
  const std::size_t n = result->samples.size();
  std::vector<std::vector<double>> chosen;
  for (int k = 0; k < draws; ++k)
    chosen.push_back(result->samples[(static_cast<std::size_t>(k) * n + n / 2) / static_cast<std::size_t>(draws) % n]);
  int done = 0;
  if (progress) progress("predictive bands", 0, draws);
  const std::vector<std::string> bytes = parallel::Map(
      draws,
      [&](int k) {
        return EncodeOutcome(
            draw(chosen[static_cast<std::size_t>(k)], seed + 1000 + static_cast<std::uint64_t>(k)));
      },
      [&](int, const std::string&) {
        if (progress) progress("predictive bands", ++done, draws);
      });
  std::vector<observations::Misfit> misfits;
  std::vector<std::vector<DrawValue>> statistics;
  for (const std::string& b : bytes) {
    PredictiveOutcome o = DecodeOutcome(b);
    misfits.push_back(std::move(o.misfit));
    if (!o.statistics.empty()) statistics.push_back(std::move(o.statistics));
  }
  result->statistic_bands = BandsOverDraws(statistics);
  // The residuals by their identity, in the first draw's order.
  std::vector<observations::ResidualId> keys;
  std::map<observations::ResidualId, std::vector<double>> values;
  std::map<observations::ResidualId, double> observed;
  for (const observations::Misfit& m : misfits)
    for (const observations::Residual& r : m.residuals) {
      if (!std::isfinite(r.simulated)) continue;
      const observations::ResidualId& key = r.id;
      if (!values.count(key)) keys.push_back(key);
      values[key].push_back(r.simulated);
      observed[key] = r.observed;
    }
  for (const auto& key : keys) {
    std::vector<double> v = values[key];
    PredictiveBand b;
    b.id = key;
    b.observed = observed[key];
    b.p05 = Quantile(&v, 0.05);
    b.median = Quantile(&v, 0.5);
    b.p95 = Quantile(&v, 0.95);
    result->bands.push_back(b);
  }
  result->band_draws = draws;
  result->band_rocks = rocks;
}

std::string PosteriorCsv(const PosteriorResult& result) {
  std::ostringstream out;
  for (std::size_t k = 0; k < result.space.parameters().size(); ++k)
    out << (k ? "," : "") << text::CsvField(result.space.parameters()[k].label());
  out << "\n";
  for (const auto& s : result.samples) {
    for (std::size_t k = 0; k < s.size(); ++k) out << (k ? "," : "") << text::Num(s[k], "%.8g");
    out << "\n";
  }
  return out.str();
}

nlohmann::json PosteriorJson(const PosteriorResult& result) {
  using text::JsonNum;
  nlohmann::json parameters = nlohmann::json::array();
  for (std::size_t k = 0; k < result.parameters.size(); ++k) {
    const ParameterPosterior& p = result.parameters[k];
    const Parameter& par = result.space.parameters()[k];
    parameters.push_back({{"label", par.label()},
                          {"median", JsonNum(p.median)},
                          {"p05", JsonNum(p.p05)},
                          {"p95", JsonNum(p.p95)},
                          {"mean", JsonNum(p.mean)},
                          {"sd", JsonNum(p.sd)},
                          {"width_share", JsonNum(p.width_share)},
                          {"undetermined", p.undetermined},
                          {"rhat", JsonNum(p.rhat)},
                          {"ess", JsonNum(p.ess)}});
  }
  nlohmann::json correlation = nlohmann::json::array();
  for (const auto& row : result.correlation) {
    nlohmann::json r = nlohmann::json::array();
    for (double c : row) r.push_back(JsonNum(c));
    correlation.push_back(r);
  }
  nlohmann::json bands = nlohmann::json::array();
  for (const PredictiveBand& b : result.bands)
    bands.push_back({{"observation", b.id.observation()},
                     {"quantity", b.id.quantity()},
                     {"observed", JsonNum(b.observed)},
                     {"p05", JsonNum(b.p05)},
                     {"median", JsonNum(b.median)},
                     {"p95", JsonNum(b.p95)},
                     {"inside", b.inside()}});
  nlohmann::json length = nlohmann::json::array();
  for (double l : result.length_scales) length.push_back(JsonNum(l));
  nlohmann::json predictive = {
      {"draws", result.band_draws}, {"rocks", result.band_rocks}, {"bands", bands}};
  if (!result.statistic_bands.empty())
    predictive["statistics"] = DrawBandsJson(result.statistic_bands);
  return {{"parameters", parameters},
          {"correlation", correlation},
          {"samples", result.samples.size()},
          {"max_rhat", JsonNum(result.max_rhat)},
          {"min_ess", JsonNum(result.min_ess)},
          {"acceptance", JsonNum(result.acceptance)},
          {"reused_evaluations", result.reused},
          {"posterior_evaluations", result.evaluated},
          {"simulated", result.simulated},
          {"emulated_points", result.emulated},
          {"refining_rounds", result.rounds},
          {"emulator_variance", JsonNum(result.emulator_variance)},
          {"length_scales", length},
          {"nugget", JsonNum(result.nugget)},
          {"wall_seconds", JsonNum(result.wall_seconds)},
          {"predictive", predictive},
          {"message", result.message}};
}

}  // namespace rockcal::calibrate
