#include "rockcal/observations/misfit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "rockcal/core/format.h"
#include "rockcal/core/statistics.h"

namespace rockcal::observations {
namespace {

using core::FormatNumber;

constexpr double kAbsoluteSigmaFloor = 1e-9;

// Value at a fractional position k in [0, n - 1] of an ascending sample,
// interpolated linearly between neighbouring order statistics.
double AtPosition(const std::vector<double>& sorted, double k) {
  const std::size_t n = sorted.size();
  const double lo = std::floor(k);
  const std::size_t i = static_cast<std::size_t>(lo);
  if (i + 1 >= n) return sorted[n - 1];
  return sorted[i] + (k - lo) * (sorted[i + 1] - sorted[i]);
}

bool Finite(const core::Crossing& c) {
  return std::isfinite(c.height) && std::isfinite(c.speed) && std::isfinite(c.energy) &&
         c.point.allFinite();
}

// Number of rocks with a non-finite value in a record the misfit may read.
int CountNonFiniteRecords(const core::SimulationResult& result) {
  int count = 0;
  for (const core::RockRecord& rock : result.rocks) {
    bool ok = rock.start.allFinite() && rock.stop.allFinite();
    for (const core::Crossing& c : rock.crossings) ok = ok && (!c.crossed || Finite(c));
    for (const core::Crossing& c : rock.trees) ok = ok && (!c.crossed || Finite(c));
    if (!ok) ++count;
  }
  return count;
}

// Builds the residuals of one comparison into a Misfit.
class Comparer final {
 public:
  Comparer(const MisfitOptions& options, Misfit* misfit) : options_(options), misfit_(misfit) {}

  // Quantiles (options' levels, and the max) of the simulated against the
  // observed values; `error` is the one-sigma measurement error.
  void Distributions(const ResidualId& of, std::vector<double> simulated,
                     std::vector<double> observed, double error) const {
    Quantiles(of, std::move(simulated), std::move(observed), error, options_.levels,
              options_.include_max);
  }
  // The same at `levels` (and the max when `include_max`).
  void Quantiles(const ResidualId& of, std::vector<double> simulated, std::vector<double> observed,
                 double error, const std::vector<double>& levels, bool include_max) const;
  // A share: `k_sim` of `n_sim` simulated rocks against an observed share of
  // `n_obs` rocks; each side's binomial error with Jeffreys' estimate
  // (k + 1/2) / (n + 1), which stays > 0 when every rock stopped.
  void Share(const ResidualId& of, int k_sim, int n_sim, double observed, int n_obs) const;
  // A passing fraction: `crossed` of `released` simulated rocks.
  void Fraction(const ResidualId& of, int crossed, int released, double observed,
                double error) const;

  // The floor of a sigma of measurement error `error`.
  double SigmaFloor(double error) const { return Floor(error); }
  // Adds one residual of `of` and `statistic` as it is.
  void Residual(const ResidualId& of, Statistic statistic, double simulated, double observed,
                double sigma, double value) const {
    Add(of, statistic, 0.0, simulated, observed, sigma, value);
  }

 private:
  double Floor(double error) const {
    return std::max(options_.sigma_floor * error, kAbsoluteSigmaFloor);
  }
  void Add(const ResidualId& of, Statistic statistic, double level, double simulated,
           double observed, double sigma, double value) const {
    observations::Residual r;
    r.id = of.With(statistic, level);
    r.simulated = simulated;
    r.observed = observed;
    r.sigma = sigma;
    r.value = value;
    misfit_->residuals.push_back(r);
  }
  void Penalise(const std::string& why) const {
    misfit_->penalised = true;
    misfit_->message += (misfit_->message.empty() ? "" : " ") + why;
  }

  const MisfitOptions& options_;
  Misfit* misfit_;
};

void Comparer::Quantiles(const ResidualId& of, std::vector<double> simulated,
                         std::vector<double> observed, double error,
                         const std::vector<double>& levels, bool include_max) const {
  if (observed.empty()) {
    throw std::invalid_argument("ComputeMisfit: observation '" + of.observation() +
                                "' has no observed values");
  }
  std::sort(simulated.begin(), simulated.end());
  std::sort(observed.begin(), observed.end());
  const std::size_t quantities = levels.size() + (include_max ? 1 : 0);
  const bool sparse = simulated.size() < 2;
  // A distribution that cannot be compared adds exactly `penalty` to the misfit.
  const double penalty_value = std::sqrt(2.0 * options_.penalty / static_cast<double>(quantities));
  if (sparse) {
    Penalise(of.observation() + ": " + std::to_string(simulated.size()) + " simulated value" +
             (simulated.size() == 1 ? "" : "s") + " (fewer than 2); penalty " +
             FormatNumber(options_.penalty, "%.6g") + " added.");
  }
  const double min_sigma = Floor(error);
  auto compare = [&](Statistic statistic, double level, double sim, double obs, double sim_error,
                     double obs_error) {
    const double sigma = std::max(
        std::sqrt(error * error + sim_error * sim_error + obs_error * obs_error), min_sigma);
    const double value = sparse ? penalty_value : (sim - obs) / sigma;
    Add(of, statistic, level, sim, obs, sigma, value);
  };
  for (const double level : levels) {
    const double sim = simulated.empty() ? 0.0 : core::Quantile(simulated, level);
    compare(Statistic::kQuantile, level, sim, core::Quantile(observed, level),
            QuantileStandardError(simulated, level), QuantileStandardError(observed, level));
  }
  if (include_max) {
    // The observed maximum of m values against the simulated order statistic
    // that exceeds it with probability 1/2 under the model: the simulated
    // maximum of more rocks than observed would be biased high.
    const double k = simulated.empty() ? 0.0 : MaxOrderPosition(simulated.size(), observed.size());
    const double sim = simulated.empty() ? 0.0 : AtPosition(simulated, k);
    compare(Statistic::kMax, 0.0, sim, observed.back(), OrderStatisticError(simulated, k),
            MaxStandardError(observed));
  }
}

void Comparer::Share(const ResidualId& of, int k_sim, int n_sim, double observed, int n_obs) const {
  if (n_sim <= 0) {
    Penalise(of.observation() + ": no rocks released; penalty " +
             FormatNumber(options_.penalty, "%.6g") + " added.");
    Add(of, Statistic::kShare, 0.0, 0.0, observed, 1.0, std::sqrt(2.0 * options_.penalty));
    return;
  }
  auto variance = [](double k, int n) {
    const double p = (k + 0.5) / (n + 1.0);
    return p * (1.0 - p) / n;
  };
  const double f = static_cast<double>(k_sim) / n_sim;
  const double sigma = std::sqrt(variance(k_sim, n_sim) + variance(observed * n_obs, n_obs));
  Add(of, Statistic::kShare, 0.0, f, observed, sigma, (f - observed) / sigma);
}

void Comparer::Fraction(const ResidualId& of, int crossed, int released, double observed,
                        double error) const {
  if (released <= 0) {
    Penalise(of.observation() + ": no rocks released; penalty " +
             FormatNumber(options_.penalty, "%.6g") + " added.");
    Add(of, Statistic::kFraction, 0.0, 0.0, observed, std::max(error, Floor(error)),
        std::sqrt(2.0 * options_.penalty));
    return;
  }
  const double n = static_cast<double>(released);
  const double f = static_cast<double>(crossed) / n;
  const double sigma = std::max(std::sqrt(error * error + f * (1.0 - f) / n), Floor(error));
  Add(of, Statistic::kFraction, 0.0, f, observed, sigma, (f - observed) / sigma);
}

// The runout: where rocks stopped against the observed stops, pooled and per
// mass class, and the share of rocks that stopped. A rock that left the
// terrain or was still moving at the time limit is right-censored: it
// travelled at least to where it was last seen, so it enters the distances
// at D, at or beyond every stopped, observed and last-seen distance (the
// upper tail), never as a missing value, when every observed rock stopped.
// Losing rocks thus raises the upper quantiles and lowers the stopped share:
// it never lowers the misfit. When some observed rocks did not stop either
// (stopped_fraction < 1), the observed distances are those of the rocks that
// stopped, and the simulated ones are compared in kind: the stopped rocks'
// (the runout given stopping), with the share compared on its own.
// Per-run observations: run i's runout (from its own release) against the
// runouts of its group's rocks from the same release; a rock that did not
// stop is censored as above (at or beyond every distance). Two comparisons,
// as options.run_terms says:
// - pooled: the runs' runouts pooled into one distribution compared by
//   quantiles as above (each run adds its group's rocks, so the pooled
//   simulated sample is the mixture of the runs' predictions);
// - per run: one residual per run, (median_i - observed_i) / sigma_i with
//   sigma_i^2 = error^2 + s_i^2 (1 + pi / (2 n_i)): the observed stop is one
//   draw of the run's predictive distribution (spread s_i), the median of n_i
//   rocks has the Monte Carlo variance pi s_i^2 / (2 n_i). The spread s_i is
//   the run's own rocks' standard deviation (n_i - 1 degrees of freedom)
//   shrunk toward the spread pooled over all runs' rocks about their group
//   medians (1.4826 x their median absolute deviation, groups of 2 rocks or
//   more; options.run_spread_prior degrees of freedom):
//   s_i^2 = (nu0 s_pool^2 + (n_i - 1) s_own^2) / (nu0 + n_i - 1).
//   A run of one rock takes the pooled spread; a run split between rocks
//   that stuck and rocks that ran has a large own spread, so a moderate
//   residual; a run with no simulated rock adds a residual 0.
// The stopped share is compared in both cases. Each run's fit goes to
// misfit->runs.
void CompareRuns(const Runout& runout, double error, const core::SimulationResult& result,
                 const MisfitOptions& options, const Comparer& compare, Misfit* misfit) {
  std::vector<std::vector<const core::RockRecord*>> by_group;
  for (const core::RockRecord& rock : result.rocks) {
    const std::size_t g = static_cast<std::size_t>(rock.group);
    if (by_group.size() <= g) by_group.resize(g + 1);
    by_group[g].push_back(&rock);
  }
  double farthest = *std::max_element(runout.distances.begin(), runout.distances.end());
  for (std::size_t i = 0; i < runout.run_groups.size(); ++i) {
    const std::size_t g = static_cast<std::size_t>(runout.run_groups[i]);
    if (g >= by_group.size()) continue;
    for (const core::RockRecord* rock : by_group[g])
      farthest = std::max(farthest, (rock->stop.head<2>() - runout.run_origins[i]).norm());
  }
  std::vector<double> pooled;
  std::vector<std::vector<double>> samples;  // each run's runouts, ascending
  int stopped = 0, released = 0;
  for (std::size_t i = 0; i < runout.run_groups.size(); ++i) {
    const std::size_t g = static_cast<std::size_t>(runout.run_groups[i]);
    RunFit fit;
    fit.id = runout.run_ids[i];
    fit.group = runout.run_groups[i];
    fit.observed = runout.distances[i];
    std::vector<double> run;
    if (g < by_group.size()) {
      for (const core::RockRecord* rock : by_group[g]) {
        const double d = (rock->stop.head<2>() - runout.run_origins[i]).norm();
        const bool stop = rock->outcome == core::Outcome::kStopped;
        run.push_back(stop ? d : farthest);
        fit.stopped += stop ? 1 : 0;
        const double moved = (rock->stop.head<2>() - rock->start.head<2>()).norm();
        if (RunFit::StuckNearRelease(moved, fit.observed)) ++fit.stuck;
      }
    }
    fit.rocks = static_cast<int>(run.size());
    if (!run.empty()) {
      std::sort(run.begin(), run.end());
      fit.simulated = core::Quantile(run, 0.5);
    }
    stopped += fit.stopped;
    released += fit.rocks;
    pooled.insert(pooled.end(), run.begin(), run.end());
    samples.push_back(std::move(run));
    misfit->runs.push_back(fit);
  }
  if (options.run_terms != RunTerms::kPerRun)
    compare.Distributions(ResidualId::Of(ObservationKind::kRunoutDistance), std::move(pooled),
                          runout.distances, error);
  const int observed_rocks =
      runout.observed_rocks > 0 ? runout.observed_rocks : static_cast<int>(runout.distances.size());
  compare.Share(ResidualId::Of(ObservationKind::kRunoutStopped), stopped, released,
                runout.stopped_fraction, observed_rocks);
  if (options.run_terms == RunTerms::kPooled) return;

  std::vector<double> deviations;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].size() < 2) continue;
    for (const double d : samples[i]) deviations.push_back(std::abs(d - misfit->runs[i].simulated));
  }
  double pool = 0.0;
  if (!deviations.empty()) {
    std::sort(deviations.begin(), deviations.end());
    pool = 1.4826 * core::Quantile(deviations, 0.5);
  }
  constexpr double kPi = 3.14159265358979323846;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    RunFit& fit = misfit->runs[i];
    const std::vector<double>& run = samples[i];
    const double n = static_cast<double>(run.size());
    double own2 = 0.0;
    if (run.size() >= 2) {
      double mean = 0.0;
      for (const double d : run) mean += d;
      mean /= n;
      for (const double d : run) own2 += (d - mean) * (d - mean);
      own2 /= n - 1.0;
    }
    const double dof = options.run_spread_prior + std::max(n - 1.0, 0.0);
    const double spread2 =
        dof > 0.0 ? (options.run_spread_prior * pool * pool + std::max(n - 1.0, 0.0) * own2) / dof
                  : 0.0;
    fit.spread = std::sqrt(spread2);
    fit.sigma = run.empty() ? std::max(error, compare.SigmaFloor(error))
                            : std::max(std::sqrt(error * error + spread2 * (1.0 + kPi / (2.0 * n))),
                                       compare.SigmaFloor(error));
    const double value = run.empty() ? 0.0 : (fit.simulated - fit.observed) / fit.sigma;
    compare.Residual(ResidualId::Of(ObservationKind::kRun, static_cast<int>(i), fit.id),
                     Statistic::kRunout, fit.simulated, fit.observed, fit.sigma, value);
  }
}

void CompareRunout(const Runout& runout, double error, const core::SimulationResult& result,
                   const Comparer& compare) {
  struct Rock {
    double mass, distance;
  };
  std::vector<Rock> rocks;
  std::vector<double> lateral;
  double farthest = *std::max_element(runout.distances.begin(), runout.distances.end());
  int stopped = 0;
  for (const core::RockRecord& rock : result.rocks) {
    if (rock.outcome != core::Outcome::kStopped) continue;
    const Eigen::Vector2d p = rock.stop.head<2>();
    rocks.push_back({rock.mass, runout.Distance(p)});
    lateral.push_back(runout.Lateral(p));
    farthest = std::max(farthest, rocks.back().distance);
    ++stopped;
  }
  for (const core::RockRecord& rock : result.rocks)
    if (rock.outcome != core::Outcome::kStopped)
      farthest = std::max(farthest, runout.Distance(rock.stop.head<2>()));
  const bool all_stopped = runout.stopped_fraction >= 1.0;
  for (const core::RockRecord& rock : result.rocks)
    if (all_stopped && rock.outcome != core::Outcome::kStopped) rocks.push_back({rock.mass, farthest});
  std::vector<double> distance;
  for (const Rock& r : rocks) distance.push_back(r.distance);
  compare.Distributions(ResidualId::Of(ObservationKind::kRunoutDistance), std::move(distance),
                        runout.distances, error);
  if (runout.has_lateral())
    compare.Distributions(ResidualId::Of(ObservationKind::kRunoutLateral), std::move(lateral),
                          runout.lateral, error);
  const int observed_rocks =
      runout.observed_rocks > 0 ? runout.observed_rocks : static_cast<int>(runout.distances.size());
  compare.Share(ResidualId::Of(ObservationKind::kRunoutStopped), stopped,
                static_cast<int>(result.rocks.size()), runout.stopped_fraction, observed_rocks);
  if (runout.mass_classes < 2) return;
  const std::vector<double> bounds = runout.MassClassBounds();
  auto class_of = [&](double mass) {
    return static_cast<int>(std::upper_bound(bounds.begin(), bounds.end(), mass) - bounds.begin());
  };
  for (int c = 0; c < runout.mass_classes; ++c) {
    std::vector<double> sim, obs;
    for (const Rock& r : rocks)
      if (class_of(r.mass) == c) sim.push_back(r.distance);
    for (std::size_t k = 0; k < runout.masses.size(); ++k)
      if (class_of(runout.masses[k]) == c) obs.push_back(runout.distances[k]);
    if (obs.empty()) continue;  // ties at a bound can empty a class
    const std::string range =
        c == 0 ? "< " + FormatNumber(std::round(bounds[0]), "%.6g")
        : c + 1 == runout.mass_classes
            ? ">= " + FormatNumber(std::round(bounds[static_cast<std::size_t>(c - 1)]), "%.6g")
            : FormatNumber(std::round(bounds[static_cast<std::size_t>(c - 1)]), "%.6g") + "-" +
                  FormatNumber(std::round(bounds[static_cast<std::size_t>(c)]), "%.6g");
    compare.Quantiles(ResidualId::Of(ObservationKind::kRunoutMassClass, c, range), std::move(sim),
                      std::move(obs), error, {0.5}, false);
  }
}

}  // namespace

const char* RunTermsName(RunTerms terms) {
  switch (terms) {
    case RunTerms::kPooled:
      return "pooled";
    case RunTerms::kPerRun:
      return "per_run";
    case RunTerms::kBoth:
      return "both";
  }
  return "?";
}

bool ParseRunTerms(const std::string& name, RunTerms* terms) {
  for (const RunTerms t : {RunTerms::kPooled, RunTerms::kPerRun, RunTerms::kBoth}) {
    if (name == RunTermsName(t)) {
      *terms = t;
      return true;
    }
  }
  return false;
}

std::string ResidualId::observation() const {
  std::string text;
  switch (kind) {
    case ObservationKind::kNone:
      break;
    case ObservationKind::kTreeScars:
    case ObservationKind::kPassing:
      text = name;
      break;
    case ObservationKind::kRunoutDistance:
      text = "runout distance";
      break;
    case ObservationKind::kRunoutMassClass:
      text = "runout distance, mass " + name + " kg";
      break;
    case ObservationKind::kRunoutLateral:
      text = "runout lateral";
      break;
    case ObservationKind::kRunoutStopped:
      text = "runout stopped";
      break;
    case ObservationKind::kRun:
      text = "run " + name;
      break;
    case ObservationKind::kPrior:
      return "prior";
  }
  return site.empty() ? text : site + ": " + text;
}

std::string ResidualId::quantity() const {
  switch (statistic) {
    case Statistic::kNone:
      return "";
    case Statistic::kQuantile:
      return LevelName(level);
    case Statistic::kMax:
      return "max";
    case Statistic::kShare:
      return "share";
    case Statistic::kFraction:
      return "fraction";
    case Statistic::kRunout:
      return "runout";
    case Statistic::kOffset:
      return site + ":" + name + "_offset";
  }
  return "";
}

ResidualId ResidualId::Of(ObservationKind kind, int index, std::string name) {
  ResidualId id;
  id.kind = kind;
  id.index = index;
  id.name = std::move(name);
  return id;
}

ResidualId ResidualId::With(Statistic what, double at) const {
  ResidualId id = *this;
  id.statistic = what;
  id.level = at;
  return id;
}

ResidualId ResidualId::observation_id() const { return With(Statistic::kNone); }

bool ResidualId::operator==(const ResidualId& o) const {
  return kind == o.kind && index == o.index && name == o.name && statistic == o.statistic &&
         level == o.level && site == o.site;
}

bool ResidualId::operator<(const ResidualId& o) const {
  return std::tie(site, kind, index, name, statistic, level) <
         std::tie(o.site, o.kind, o.index, o.name, o.statistic, o.level);
}

std::vector<double> MisfitOptions::DefaultLevels() {
  return {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
}

bool MisfitOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (levels.empty() && !include_max) {
    return fail(
        "levels is empty and include_max is false (expected at least one quantity to "
        "compare)");
  }
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (!(levels[i] >= 0.0 && levels[i] <= 1.0)) {
      return fail("levels[" + std::to_string(i) + "] = " + FormatNumber(levels[i], "%.6g") +
                  " (expected a level in [0, 1])");
    }
  }
  if (!(std::isfinite(penalty) && penalty > 0.0)) {
    return fail("penalty = " + FormatNumber(penalty, "%.6g") + " (expected a finite number > 0)");
  }
  if (!(std::isfinite(run_spread_prior) && run_spread_prior >= 0.0)) {
    return fail("run_spread_prior = " + FormatNumber(run_spread_prior, "%.6g") +
                " (expected a finite number >= 0)");
  }
  if (!(sigma_floor > 0.0 && sigma_floor <= 1.0)) {
    return fail("sigma_floor = " + FormatNumber(sigma_floor, "%.6g") +
                " (expected a number in (0, 1])");
  }
  return true;
}

std::string Misfit::Report() const {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-28s %-9s %12s %12s %12s %10s\n", "observation", "quantity",
                "simulated", "observed", "sigma", "residual");
  out << line;
  for (const Residual& r : residuals) {
    std::snprintf(line, sizeof(line), "%-28s %-9s %12.5g %12.5g %12.5g %10.4g\n",
                  r.id.observation().c_str(), r.id.quantity().c_str(), r.simulated, r.observed,
                  r.sigma, r.value);
    out << line;
  }
  out << "misfit " << value << (penalised ? " (penalised)" : "") << "\n";
  if (!message.empty()) out << message << "\n";
  return out.str();
}

double Misfit::MeanRunError() const {
  if (runs.empty()) return 0.0;
  double sum = 0.0;
  for (const RunFit& r : runs) sum += std::abs(r.simulated - r.observed);
  return sum / static_cast<double>(runs.size());
}

int Misfit::StuckRocks() const {
  int n = 0;
  for (const RunFit& r : runs) n += r.stuck;
  return n;
}

namespace {

// P(|Z| >= x) for a standard normal Z.
double TwoSidedTail(double x) { return std::erfc(std::abs(x) / std::sqrt(2.0)); }

// P(K >= k) for K ~ Binomial(n, p), 0 < p < 1.
double BinomialTail(int n, int k, double p) {
  if (k <= 0) return 1.0;
  if (k > n) return 0.0;
  double sum = 0.0;
  for (int j = k; j <= n; ++j)
    sum += std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) +
                    j * std::log(p) + (n - j) * std::log1p(-p));
  return std::min(1.0, sum);
}

std::string Chance(double p) {
  return p < 1e-4 ? "< 0.01 %" : FormatNumber(100.0 * p, "%.2g") + " %";
}

}  // namespace

std::string FitVerdict::Sentence() const {
  if (penalised) return "poor: the misfit was penalised (see its message)";
  if (outside.empty() && !poor && !fair)
    return "good: every compared quantity (" + std::to_string(compared) + ") within 2 sigma";
  std::string s = std::string(poor ? "poor" : fair ? "fair" : "good") + ": " +
                  std::to_string(outside.size()) + " of " + std::to_string(compared) +
                  " compared quantities outside 2 sigma";
  const std::string chances = "at least as many with probability " + Chance(count_chance) +
                              ", a largest as far with probability " + Chance(largest_chance);
  s += poor || fair ? " (a correct model gives " + chances + ")"
                    : ", as a correct model gives (" + chances + ")";
  for (std::size_t k = 0; k < outside.size() && k < 3; ++k)
    s += (k ? "; " : ", the worst ") + outside[k];
  return s;
}

FitVerdict AssessFit(const Misfit& misfit) {
  FitVerdict v;
  v.compared = static_cast<int>(misfit.residuals.size());
  v.penalised = misfit.penalised;
  std::vector<const Residual*> far;
  double largest = 0.0;
  for (const Residual& r : misfit.residuals) {
    if (std::abs(r.value) > 2.0) far.push_back(&r);
    largest = std::max(largest, std::abs(r.value));
  }
  std::sort(far.begin(), far.end(), [](const Residual* a, const Residual* b) {
    return std::abs(a->value) > std::abs(b->value);
  });
  for (const Residual* r : far) {
    char line[160];
    std::snprintf(line, sizeof line, ": simulated %.3g against %.3g observed (%+.1f sigma)",
                  r->simulated, r->observed, r->value);
    v.outside.push_back(r->id.observation() + " " + r->id.quantity() + line);
  }
  if (v.compared > 0) {
    v.count_chance =
        BinomialTail(v.compared, static_cast<int>(far.size()), TwoSidedTail(2.0));
    // 1 - (1 - q)^N without cancellation for a small q.
    v.largest_chance = -std::expm1(v.compared * std::log1p(-TwoSidedTail(largest)));
  }
  const double chance = std::min(v.count_chance, v.largest_chance);
  v.poor = misfit.penalised || chance < FitVerdict::kPoorChance;
  v.fair = !v.poor && chance < FitVerdict::kFairChance;
  return v;
}

double QuantileStandardError(const std::vector<double>& sorted, double level) {
  const std::size_t n = sorted.size();
  if (n < 2) return 0.0;
  const double last = static_cast<double>(n - 1);
  const double centre = last * level;
  const double half = std::sqrt(static_cast<double>(n) * level * (1.0 - level));
  const double lo = std::clamp(centre - half, 0.0, last);
  const double hi = std::clamp(centre + half, 0.0, last);
  return 0.5 * (AtPosition(sorted, hi) - AtPosition(sorted, lo));
}

double MaxStandardError(const std::vector<double>& sorted) {
  const std::size_t n = sorted.size();
  if (n < 2) return 0.0;
  const std::size_t j = std::clamp<std::size_t>(n / 10, 1, n - 1);
  const double threshold = sorted[n - 1 - j];
  double excess = 0.0;
  for (std::size_t i = n - j; i < n; ++i) excess += sorted[i] - threshold;
  return std::max(sorted[n - 1] - sorted[n - 2], excess / static_cast<double>(j));
}

double MaxOrderPosition(std::size_t simulated, std::size_t observed) {
  const double n = static_cast<double>(simulated), m = static_cast<double>(observed);
  // P_k for k = 1, 2, ...: the chance that the k-th largest simulated value
  // exceeds the observed maximum; it falls with k, to 0 at k = n + 1.
  double before = 1.0, p = n / (n + m);
  double k = 1.0;
  while (p > 0.5) {
    before = p;
    p *= (n - k) / (n + m - k);
    k += 1.0;
  }
  if (k == 1.0) return n - 1.0;
  // P_{k-1} = before > 1/2 >= P_k = p.
  return n - (k - 1.0 + (before - 0.5) / (before - p));
}

double OrderStatisticError(const std::vector<double>& sorted, double position) {
  const std::size_t n = sorted.size();
  if (n < 2) return 0.0;
  const double last = static_cast<double>(n - 1);
  const double p = std::clamp(position / last, 0.0, 1.0);
  const double h = std::max(1.0, std::sqrt(static_cast<double>(n) * p * (1.0 - p)));
  const double lo = std::clamp(position - h, 0.0, last);
  const double hi = std::clamp(position + h, 0.0, last);
  return hi > lo ? h * (AtPosition(sorted, hi) - AtPosition(sorted, lo)) / (hi - lo) : 0.0;
}

std::string LevelName(double level) {
  const double percent = 100.0 * level;
  const double rounded = std::round(percent);
  if (std::abs(percent - rounded) < 1e-9) {
    return "p" + std::to_string(static_cast<long>(rounded));
  }
  return "p" + FormatNumber(percent, "%.6g");
}

Misfit ComputeMisfit(const Observations& observations, const core::Scene& scene,
                     const core::SimulationResult& result, const MisfitOptions& options) {
  std::string invalid;
  if (!options.IsValid(&invalid)) throw std::invalid_argument("MisfitOptions: " + invalid);

  Misfit misfit;
  const int non_finite = std::max(result.figures.non_finite, CountNonFiniteRecords(result));
  if (non_finite > 0) {
    misfit.value = options.penalty;
    misfit.penalised = true;
    misfit.message = "the simulation produced " + std::to_string(non_finite) +
                     " rock(s) with a non-finite state; misfit set to the penalty " +
                     FormatNumber(options.penalty, "%.6g") + ".";
    return misfit;
  }

  const std::size_t n_partitions = scene.partitions.size();
  auto check_partition = [&](const std::string& label, int partition) {
    if (partition < 0 || static_cast<std::size_t>(partition) >= n_partitions) {
      throw std::invalid_argument("ComputeMisfit: observation '" + label +
                                  "' refers to partition " + std::to_string(partition) +
                                  " but the scene has " + std::to_string(n_partitions));
    }
    for (const core::RockRecord& rock : result.rocks) {
      if (rock.crossings.size() <= static_cast<std::size_t>(partition)) {
        throw std::invalid_argument("ComputeMisfit: rock " + std::to_string(rock.rock) +
                                    " records " + std::to_string(rock.crossings.size()) +
                                    " partition crossings but observation '" + label +
                                    "' needs partition " + std::to_string(partition) +
                                    " (simulate with RequiredRecording(observations, ...))");
      }
    }
  };
  auto check_probe = [&](const std::string& label, int probe) {
    for (const core::RockRecord& rock : result.rocks) {
      if (probe < 0 || rock.trees.size() <= static_cast<std::size_t>(probe)) {
        throw std::invalid_argument("ComputeMisfit: rock " + std::to_string(rock.rock) +
                                    " records " + std::to_string(rock.trees.size()) +
                                    " trees but observation '" + label + "' needs tree probe " +
                                    std::to_string(probe) +
                                    " (simulate with RequiredRecording(observations, ...))");
      }
    }
  };

  const Comparer compare(options, &misfit);
  for (std::size_t i = 0; i < observations.tree_scars.size(); ++i) {
    const ScarSet& set = observations.tree_scars[i];
    std::vector<double> simulated;
    if (set.at_partition()) {
      check_partition(set.label, set.partition);
      const std::size_t p = static_cast<std::size_t>(set.partition);
      for (const core::RockRecord& rock : result.rocks) {
        if (rock.crossings[p].crossed) simulated.push_back(rock.crossings[p].height);
      }
    } else {
      for (const Tree& tree : set.trees) {
        check_probe(set.label, tree.probe);
        const std::size_t k = static_cast<std::size_t>(tree.probe);
        for (const core::RockRecord& rock : result.rocks) {
          if (rock.trees[k].crossed) simulated.push_back(rock.trees[k].height);
        }
      }
    }
    compare.Distributions(
        ResidualId::Of(ObservationKind::kTreeScars, static_cast<int>(i), set.label),
        std::move(simulated), set.ObservedHeights(), observations.error.height);
  }

  if (observations.runout && observations.runout->has_runs())
    CompareRuns(*observations.runout, observations.error.runout, result, options, compare,
                &misfit);
  else if (observations.runout)
    CompareRunout(*observations.runout, observations.error.runout, result, compare);

  const int released = static_cast<int>(result.rocks.size());
  for (std::size_t i = 0; i < observations.passing.size(); ++i) {
    const Passing& passing = observations.passing[i];
    check_partition(passing.label, passing.partition);
    const std::size_t p = static_cast<std::size_t>(passing.partition);
    int crossed = 0;
    for (const core::RockRecord& rock : result.rocks) crossed += rock.crossings[p].crossed ? 1 : 0;
    compare.Fraction(ResidualId::Of(ObservationKind::kPassing, static_cast<int>(i), passing.label),
                     crossed, released, passing.fraction, observations.error.passing);
  }

  double sum = 0.0;
  for (const Residual& r : misfit.residuals) sum += r.value * r.value;
  misfit.value = 0.5 * sum;
  return misfit;
}

}  // namespace rockcal::observations
