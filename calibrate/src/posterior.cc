#include "rockcal/calibrate/posterior.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/residual_correlation.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kMinusInf = -std::numeric_limits<double>::infinity();
constexpr std::uint64_t kDesignSeedMix = 0x44455349474e0000ull;  // "DESIGN"
constexpr std::uint64_t kCorrelationSeedMix = 0x434f5252454c0000ull;  // "CORREL"

// The number of independent residuals whose information `correlation`'s
// carry: (tr R)^2 / tr(R^2) (n when independent, 1 when all move as one).
double EffectiveCount(const Eigen::MatrixXd& correlation) {
  const double trace = correlation.trace();
  const double square = correlation.cwiseProduct(correlation).sum();
  return square > 0.0 ? trace * trace / square : 0.0;
}

}  // namespace

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
  else if (bootstrap_replicates < 0)
    s << "bootstrap_replicates = " << bootstrap_replicates << ": must be >= 0 (0: the quantiles' correlation alone)";
  else if (predictive_draws < 0)
    s << "predictive_draws = " << predictive_draws << ": must be >= 0 (0: no predictive bands)";
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

// The emulated points: unit-box coordinates, physical values, residuals,
// the sigmas' log term (observations::Misfit::log_scale) and the negative
// log-likelihoods (the misfit, plus the log term when the likelihood
// carries it); the residuals are whitened and warped when emulated
// (Outputs), the log term emulated as it is.
struct Design {
  bool log_term = false;  // PosteriorOptions::sigma_log_term
  // The residuals the likelihood takes (LikelihoodResiduals; empty: all).
  std::vector<bool> keep;
  std::vector<std::vector<double>> unit;
  std::vector<std::vector<double>> physical;
  std::vector<std::vector<double>> residuals;
  std::vector<double> log_scale;
  std::vector<double> misfit;

  bool Has(const std::vector<double>& u) const {
    for (const auto& p : unit) {
      double d2 = 0.0;
      for (std::size_t k = 0; k < u.size(); ++k) d2 += (p[k] - u[k]) * (p[k] - u[k]);
      if (d2 < 1e-20) return true;
    }
    return false;
  }
  void Add(const std::vector<double>& u, const std::vector<double>& x, const std::vector<double>& r,
           double scale, double m) {
    if (Has(u)) return;
    unit.push_back(u);
    physical.push_back(x);
    if (keep.empty()) {
      residuals.push_back(r);
    } else {
      // The kept residuals, and the misfit of those alone.
      std::vector<double> kept;
      m = 0.0;
      for (std::size_t j = 0; j < r.size(); ++j) {
        if (!keep[j]) continue;
        kept.push_back(r[j]);
        m += 0.5 * r[j] * r[j];
      }
      residuals.push_back(std::move(kept));
    }
    log_scale.push_back(scale);
    misfit.push_back(log_term ? m + scale : m);
  }
  // Whether the log term is emulated: the likelihood carries it and it
  // varies over the design (a constant output, which moves nothing in the
  // likelihood, would still move the emulator's fit).
  bool EmulatesLogTerm() const {
    if (!log_term || log_scale.empty()) return false;
    const auto [lo, hi] = std::minmax_element(log_scale.begin(), log_scale.end());
    return *hi - *lo > 1e-9 * std::max(1.0, std::abs(*hi));
  }
  // The emulated outputs of each point: its residuals whitened (W r; W
  // empty: as they are) and warped, r' = c asinh(r / c), then its log term
  // when EmulatesLogTerm().
  std::vector<std::vector<double>> Outputs(const Eigen::MatrixXd& whitening, double warp) const {
    std::vector<std::vector<double>> out;
    const bool with_log_term = EmulatesLogTerm();
    for (std::size_t i = 0; i < residuals.size(); ++i) {
      Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(
          residuals[i].data(), static_cast<Eigen::Index>(residuals[i].size()));
      if (whitening.size() > 0) r = whitening * r;
      std::vector<double> w;
      for (Eigen::Index k = 0; k < r.size(); ++k) w.push_back(warp * std::asinh(r(k) / warp));
      if (with_log_term) w.push_back(log_scale[i]);
      out.push_back(std::move(w));
    }
    return out;
  }
  // The point of lowest negative log-likelihood (physical values); the design
  // is not empty.
  const std::vector<double>& Best() const {
    return physical[static_cast<std::size_t>(
        std::min_element(misfit.begin(), misfit.end()) - misfit.begin())];
  }
};

// The emulated residuals at u (unwarped mean, and variance by the delta
// method), folded into the log-likelihood: each residual r ~ N(mu, v) under
// the emulator, so E[exp(-r^2 / 2)] = exp(-mu^2 / (2 (1 + v))) / sqrt(1 + v);
// with `log_term`, minus the emulated log term of the sigmas (the last
// output, at its mean).
struct EmulatedTarget {
  const Emulator* emulator;
  double warp;
  bool log_term;

  double LogDensity(const Eigen::VectorXd& u, double* mean_variance = nullptr) const {
    if (!InUnitBox(u)) return kMinusInf;
    Eigen::VectorXd mean, variance;
    emulator->Predict(u, &mean, &variance);
    const Eigen::Index residuals = log_term ? mean.size() - 1 : mean.size();
    double value = log_term ? -mean(residuals) : 0.0, vsum = 0.0;
    for (Eigen::Index j = 0; j < residuals; ++j) {
      const double t = mean(j) / warp;
      const double mu = warp * std::sinh(t);
      const double slope = std::cosh(t);
      const double v = variance(j) * slope * slope;
      value += -0.5 * mu * mu / (1.0 + v) - 0.5 * std::log1p(v);
      vsum += v;
    }
    if (mean_variance) *mean_variance = vsum / static_cast<double>(residuals);
    return value;
  }
};

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// The chains' starts: the design points of lowest negative log-likelihood
// (Design::misfit), distinct.
std::vector<Eigen::VectorXd> Starts(const Design& design, int chains) {
  std::vector<std::size_t> order(design.unit.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return design.misfit[a] < design.misfit[b];
  });
  std::vector<Eigen::VectorXd> starts;
  for (std::size_t k = 0; k < order.size() && static_cast<int>(starts.size()) < chains; ++k) {
    const auto& u = design.unit[order[k]];
    starts.push_back(
        Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size())));
  }
  return starts;
}

// Evaluates the unit-box points `units` through the log (replayed where
// logged as "posterior", with the sigmas' log term when `log_term` needs
// it), appending new evaluations as each finishes.
std::vector<Evaluation> EvaluatePoints(const ObjectiveFunction& objective,
                                       const std::vector<std::vector<double>>& units,
                                       EvaluationLog* log, const std::string& stage,
                                       const PosteriorProgress& progress, int* simulated,
                                       const Clock::time_point& start, bool log_term) {
  std::vector<Evaluation> out(units.size());
  std::vector<std::vector<double>> missing;
  std::vector<std::size_t> where;
  for (std::size_t k = 0; k < units.size(); ++k) {
    const std::vector<double> x = objective.space().ToPhysical(units[k]);
    const Evaluation* logged = log ? log->Find(Stage::Posterior(), x) : nullptr;
    if (logged && (!log_term || std::isfinite(logged->log_scale)) &&
        logged->residuals.size() == static_cast<std::size_t>(objective.residual_count())) {
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
  const std::vector<observations::Misfit> misfits =
      objective.EvaluateAll(missing, [&](int i, const observations::Misfit& m) {
        Evaluation& e = out[where[static_cast<std::size_t>(i)]];
        e = EvaluationOf(Stage::Posterior(), missing[static_cast<std::size_t>(i)], m);
        e.index = base + i + 1;
        e.elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        if (log) log->Append(e);
        ++*simulated;
        ++done;
        if (progress) progress(stage, done, static_cast<int>(units.size()));
      });
  // Under mpirun the callback runs on rank 0 only: every rank takes the
  // misfits EvaluateAll returns to all, so that all emulate the same design
  // (else their posteriors parted and a refining round waited forever).
  for (std::size_t i = 0; i < missing.size() && i < misfits.size(); ++i) {
    Evaluation& e = out[where[i]];
    if (!e.parameters.empty()) continue;
    e = EvaluationOf(Stage::Posterior(), missing[i], misfits[i]);
    e.index = base + static_cast<int>(i) + 1;
  }
  return out;
}

// Adds the unpenalised evaluations to the design.
int AddEvaluations(const ObjectiveFunction& objective, const std::vector<Evaluation>& evaluations,
                   Design* design) {
  int added = 0;
  for (const Evaluation& e : evaluations) {
    if (e.penalised || e.parameters.empty() || (design->log_term && !std::isfinite(e.log_scale)) ||
        e.residuals.size() != static_cast<std::size_t>(objective.residual_count()))
      continue;
    const std::size_t before = design->unit.size();
    design->Add(objective.space().ToUnit(e.parameters), e.parameters, e.residuals, e.log_scale,
                e.misfit);
    added += static_cast<int>(design->unit.size() - before);
  }
  return added;
}

// The refining round's new points: among the posterior samples, the one where
// the emulator is least sure, then again with the variance of the others
// damped near each point taken (as if it were known there).
std::vector<std::vector<double>> RefinePoints(const Emulator& emulator,
                                              const EmulatedTarget& target,
                                              const std::vector<Eigen::VectorXd>& samples,
                                              int count, double settled, const Design& design) {
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
  p.p05 = core::QuantileOf(&values, 0.05);
  p.median = core::QuantileOf(&values, 0.5);
  p.p95 = core::QuantileOf(&values, 0.95);
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

std::vector<bool> LikelihoodResiduals(const std::vector<observations::Residual>& layout,
                                      bool sigma_log_term) {
  std::vector<bool> keep(layout.size(), true);
  if (sigma_log_term) return keep;
  std::set<std::string> pooled;  // sites whose runs' stops are compared pooled
  for (const observations::Residual& r : layout)
    if (r.id.kind == observations::ObservationKind::kRunoutDistance) pooled.insert(r.id.site);
  for (std::size_t j = 0; j < layout.size(); ++j)
    if (layout[j].id.kind == observations::ObservationKind::kRun && pooled.count(layout[j].id.site))
      keep[j] = false;
  return keep;
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
  design.log_term = options.sigma_log_term;
  if (layout.size() == static_cast<std::size_t>(objective.residual_count())) {
    design.keep = LikelihoodResiduals(layout, options.sigma_log_term);
    result.left_out = static_cast<int>(std::count(design.keep.begin(), design.keep.end(), false));
    if (result.left_out == 0) design.keep.clear();
  }
  result.sigma_log_term = options.sigma_log_term;
  result.reused = AddEvaluations(objective, reused, &design);

  // The space-filling design, topping the reused evaluations up.
  const int wanted = options.DesignPoints(d) - static_cast<int>(design.unit.size());
  if (wanted > 0) {
    const auto points = SpaceFillingDesign(DesignKind::kLatinHypercube, wanted, d,
                                           options.mcmc.seed ^ kDesignSeedMix);
    const std::vector<Evaluation> e =
        EvaluatePoints(objective, points, log, "design", progress, &result.simulated, start,
                       options.sigma_log_term);
    result.evaluated += static_cast<int>(points.size());
    AddEvaluations(objective, e, &design);
  }
  if (static_cast<int>(design.unit.size()) < d + 3)
    throw std::runtime_error("posterior: " + std::to_string(design.unit.size()) +
                             " unpenalised evaluations to emulate " + std::to_string(d) +
                             " parameters; need at least " + std::to_string(d + 3) +
                             " (give more design points)");

  // The residuals' correlation, taken at the design's best point.
  Eigen::MatrixXd correlation;
  if (options.correlated_quantiles && options.bootstrap_replicates > 0) {
    if (progress) progress("residual correlation", 0, 1);
    correlation = objective.ResidualCorrelation(design.Best(), options.bootstrap_replicates,
                                                options.mcmc.seed ^ kCorrelationSeedMix);
    if (correlation.rows() == objective.residual_count()) result.correlation_source = "bootstrap";
    else correlation.resize(0, 0);
  }
  if (correlation.size() == 0 && options.correlated_quantiles &&
      layout.size() == static_cast<std::size_t>(objective.residual_count())) {
    correlation = QuantileCorrelation(layout);
    result.correlation_source = "quantiles";
  }
  if (!design.keep.empty() && correlation.size() > 0) {
    // The left-out residuals' rows and columns go: the kept residuals'
    // correlation is their block of the whole one.
    std::vector<Eigen::Index> kept;
    for (std::size_t j = 0; j < design.keep.size(); ++j)
      if (design.keep[j]) kept.push_back(static_cast<Eigen::Index>(j));
    correlation = Eigen::MatrixXd(correlation(kept, kept));
  }
  Eigen::MatrixXd whitening;
  if (correlation.size() > 0) {
    whitening = Whitening(correlation);
    result.effective_residuals = EffectiveCount(correlation);
  } else {
    result.correlation_source = "independent";
    result.effective_residuals = objective.residual_count() - result.left_out;
  }

  McmcOptions round_mcmc = options.mcmc;
  round_mcmc.steps = std::max(100, options.mcmc.steps / 2);
  round_mcmc.thin = std::min(round_mcmc.thin, round_mcmc.steps);
  for (int round = 0; round < options.rounds; ++round) {
    if (progress) progress("emulator, round " + std::to_string(round + 1), 0, 1);
    const Emulator emulator =
        Emulator::Fit(design.unit, design.Outputs(whitening, options.warp), options.emulator);
    const EmulatedTarget target{&emulator, options.warp, design.EmulatesLogTerm()};
    round_mcmc.seed = options.mcmc.seed + 7919ull * static_cast<std::uint64_t>(round + 1);
    const McmcResult chains =
        AdaptiveMetropolis([&](const Eigen::VectorXd& u) { return target.LogDensity(u); },
                           Starts(design, round_mcmc.chains), round_mcmc);
    const auto points = RefinePoints(emulator, target, chains.samples, options.RoundPoints(d),
                                     options.settled_variance, design);
    if (points.empty()) break;
    ++result.rounds;
    const std::vector<Evaluation> e =
        EvaluatePoints(objective, points, log, "round " + std::to_string(round + 1), progress,
                       &result.simulated, start, options.sigma_log_term);
    result.evaluated += static_cast<int>(points.size());
    AddEvaluations(objective, e, &design);
  }

  if (progress) progress("sampling", 0, 1);
  const Emulator emulator =
      Emulator::Fit(design.unit, design.Outputs(whitening, options.warp), options.emulator);
  const EmulatedTarget target{&emulator, options.warp, design.EmulatesLogTerm()};
  const McmcResult chains =
      AdaptiveMetropolis([&](const Eigen::VectorXd& u) { return target.LogDensity(u); },
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
  result.emulator_variance = core::QuantileOf(&variances, 0.5);

  Summarise(chains, options, &result);
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

std::string PointReleaseWarning(const core::Scene& scene) {
  int points = 0;
  std::string first;
  for (const core::RockGroup& g : scene.groups)
    if (g.release.zone.empty() && points++ == 0) first = g.id;
  if (points == 0) return "";
  return std::to_string(points) + " of " + std::to_string(scene.groups.size()) +
         " rock groups start at an exact point" +
         (first.empty() ? "" : " (the first: '" + first + "')") +
         ": their rocks meet the same ground first, so the compared statistics can jump with the "
         "values, which the emulator smooths over (intervals too narrow); give each release "
         "point its position error (\"position_spread\"; docs/posterior.md, \"Tracked runs\")";
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
                     {"new_p05", JsonNum(b.new_p05)},
                     {"new_p95", JsonNum(b.new_p95)},
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
          {"residual_correlation", result.correlation_source},
          {"sigma_log_term", result.sigma_log_term},
          {"effective_residuals", JsonNum(result.effective_residuals)},
          {"left_out_residuals", result.left_out},
          {"wall_seconds", JsonNum(result.wall_seconds)},
          {"predictive", predictive},
          {"message", result.message}};
}

}  // namespace rockcal::calibrate
