// What every kind's misfit terms share: the comparison of a simulated with
// an observed distribution by quantiles and the maximum, of a share and of
// a passing fraction (observations/README.md, "The misfit"), and the checks
// that a result recorded what an observation reads. Private to
// observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_COMPARE_H_
#define ROCKCAL_OBSERVATIONS_SRC_COMPARE_H_

#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::observations {

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
  // Values drawn in clusters: `clusters[i]` names the draw value i came
  // from (a tracked run, a simulated rock); empty, each value its own.
  struct Sample {
    std::vector<double> values;
    std::vector<int> clusters;
  };
  // Quantiles of clustered samples: each side's quantile error times the
  // square root of its design effect (QuantileDesignEffect), since values
  // of one cluster are not independent draws.
  void Quantiles(const ResidualId& of, Sample simulated, Sample observed, double error,
                 const std::vector<double>& levels, bool include_max) const;
  // A share: `k_sim` of `n_sim` simulated rocks against an observed share of
  // `n_obs` rocks; each side's binomial error with Jeffreys' estimate
  // (k + 1/2) / (n + 1), which stays > 0 when every rock stopped.
  void Share(const ResidualId& of, int k_sim, int n_sim, double observed, int n_obs) const;
  // A passing fraction: `crossed` of `released` simulated rocks.
  void Fraction(const ResidualId& of, int crossed, int released, double observed,
                double error) const;

  // The floor of a sigma of measurement error `error`.
  double SigmaFloor(double error) const { return Floor(error); }
  // Adds one residual of `of` and `statistic` as it is; `fixed_sigma` is
  // the part of `sigma` the simulation does not change (Residual::fixed_sigma;
  // 0: all of it).
  void Residual(const ResidualId& of, Statistic statistic, double simulated, double observed,
                double sigma, double value, double fixed_sigma) const {
    Add(of, statistic, 0.0, simulated, observed, sigma, value, fixed_sigma);
  }

 private:
  double Floor(double error) const;
  void Add(const ResidualId& of, Statistic statistic, double level, double simulated,
           double observed, double sigma, double value, double fixed_sigma) const;
  void Penalise(const std::string& why) const;

  const MisfitOptions& options_;
  Misfit* misfit_;
};

// What a kind's misfit terms (kinds::Kind::misfit) read and write.
struct MisfitTerms {
  const core::Scene& scene;
  const core::SimulationResult& result;
  const MisfitOptions& options;
  const Comparer& compare;
  Misfit* misfit;

  // Throw std::invalid_argument when the scene has no partition `partition`
  // or a rock did not record its crossings, or a rock did not record tree
  // probe `probe` (simulate with RequiredRecording); `label` names the
  // observation.
  void CheckPartition(const std::string& label, int partition) const;
  void CheckProbe(const std::string& label, int probe) const;
};

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_SRC_COMPARE_H_
