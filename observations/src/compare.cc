#include "compare.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "rockcal/core/format.h"
#include "statistics.h"

namespace rockcal::observations {
namespace {

using core::FormatNumber;

constexpr double kAbsoluteSigmaFloor = 1e-9;

}  // namespace

double Comparer::Floor(double error) const {
  return std::max(options_.sigma_floor * error, kAbsoluteSigmaFloor);
}

void Comparer::Add(const ResidualId& of, Statistic statistic, double level, double simulated,
                   double observed, double sigma, double value, double fixed_sigma) const {
  observations::Residual r;
  r.id = of.With(statistic, level);
  r.simulated = simulated;
  r.observed = observed;
  r.sigma = sigma;
  r.value = value;
  r.fixed_sigma = fixed_sigma;
  misfit_->residuals.push_back(r);
}

void Comparer::Penalise(const std::string& why) const {
  misfit_->penalised = true;
  misfit_->message += (misfit_->message.empty() ? "" : " ") + why;
}

void Comparer::Quantiles(const ResidualId& of, std::vector<double> simulated,
                         std::vector<double> observed, double error,
                         const std::vector<double>& levels, bool include_max) const {
  Quantiles(of, Sample{std::move(simulated), {}}, Sample{std::move(observed), {}}, error, levels,
            include_max);
}

namespace {

// Sorts a sample's values ascending, its clusters alongside.
void SortSample(Comparer::Sample* s) {
  if (s->clusters.size() != s->values.size()) {
    s->clusters.clear();
    std::sort(s->values.begin(), s->values.end());
    return;
  }
  std::vector<std::size_t> order(s->values.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return s->values[a] < s->values[b]; });
  Comparer::Sample sorted;
  for (const std::size_t i : order) {
    sorted.values.push_back(s->values[i]);
    sorted.clusters.push_back(s->clusters[i]);
  }
  *s = std::move(sorted);
}

// The level-p quantile's error of a sorted sample, its design effect taken.
double ClusteredError(const Comparer::Sample& s, double quantile, double level) {
  const double e = QuantileStandardError(s.values, level);
  if (s.clusters.empty()) return e;
  return e * std::sqrt(QuantileDesignEffect(s.values, s.clusters, quantile, level));
}

}  // namespace

void Comparer::Quantiles(const ResidualId& of, Sample simulated_sample, Sample observed_sample,
                         double error, const std::vector<double>& levels, bool include_max) const {
  SortSample(&simulated_sample);
  SortSample(&observed_sample);
  const std::vector<double>& simulated = simulated_sample.values;
  const std::vector<double>& observed = observed_sample.values;
  if (observed.empty()) {
    throw std::invalid_argument("ComputeMisfit: observation '" + of.observation() +
                                "' has no observed values");
  }
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
    const double fixed = std::max(std::sqrt(error * error + obs_error * obs_error), min_sigma);
    const double value = sparse ? penalty_value : (sim - obs) / sigma;
    Add(of, statistic, level, sim, obs, sigma, value, sparse ? 0.0 : fixed);
  };
  for (const double level : levels) {
    // Type-8 quantiles: unbiased between samples of different sizes.
    const double sim = simulated.empty() ? 0.0 : ComparedQuantile(simulated, level);
    const double obs = ComparedQuantile(observed, level);
    compare(Statistic::kQuantile, level, sim, obs, ClusteredError(simulated_sample, sim, level),
            ClusteredError(observed_sample, obs, level));
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
    Add(of, Statistic::kShare, 0.0, 0.0, observed, 1.0, std::sqrt(2.0 * options_.penalty), 0.0);
    return;
  }
  auto variance = [](double k, int n) {
    const double p = (k + 0.5) / (n + 1.0);
    return p * (1.0 - p) / n;
  };
  const double f = static_cast<double>(k_sim) / n_sim;
  const double sigma = std::sqrt(variance(k_sim, n_sim) + variance(observed * n_obs, n_obs));
  const double fixed = std::sqrt(variance(observed * n_obs, n_obs));
  Add(of, Statistic::kShare, 0.0, f, observed, sigma, (f - observed) / sigma, fixed);
}

void Comparer::Fraction(const ResidualId& of, int crossed, int released, double observed,
                        double error) const {
  if (released <= 0) {
    Penalise(of.observation() + ": no rocks released; penalty " +
             FormatNumber(options_.penalty, "%.6g") + " added.");
    Add(of, Statistic::kFraction, 0.0, 0.0, observed, std::max(error, Floor(error)),
        std::sqrt(2.0 * options_.penalty), 0.0);
    return;
  }
  const double n = static_cast<double>(released);
  const double f = static_cast<double>(crossed) / n;
  const double fixed = std::max(error, Floor(error));
  const double sigma = std::max(std::sqrt(error * error + f * (1.0 - f) / n), fixed);
  Add(of, Statistic::kFraction, 0.0, f, observed, sigma, (f - observed) / sigma, fixed);
}

void MisfitTerms::CheckPartition(const std::string& label, int partition) const {
  const std::size_t n_partitions = scene.partitions.size();
  if (partition < 0 || static_cast<std::size_t>(partition) >= n_partitions) {
    throw std::invalid_argument("ComputeMisfit: observation '" + label + "' refers to partition " +
                                std::to_string(partition) + " but the scene has " +
                                std::to_string(n_partitions));
  }
  for (const core::RockRecord& rock : result.rocks) {
    if (rock.crossings.size() <= static_cast<std::size_t>(partition)) {
      throw std::invalid_argument("ComputeMisfit: rock " + std::to_string(rock.rock) + " records " +
                                  std::to_string(rock.crossings.size()) +
                                  " partition crossings but observation '" + label +
                                  "' needs partition " + std::to_string(partition) +
                                  " (simulate with RequiredRecording(observations, ...))");
    }
  }
}

void MisfitTerms::CheckProbe(const std::string& label, int probe) const {
  for (const core::RockRecord& rock : result.rocks) {
    if (probe < 0 || rock.trees.size() <= static_cast<std::size_t>(probe)) {
      throw std::invalid_argument("ComputeMisfit: rock " + std::to_string(rock.rock) + " records " +
                                  std::to_string(rock.trees.size()) + " trees but observation '" +
                                  label + "' needs tree probe " + std::to_string(probe) +
                                  " (simulate with RequiredRecording(observations, ...))");
    }
  }
}

}  // namespace rockcal::observations
