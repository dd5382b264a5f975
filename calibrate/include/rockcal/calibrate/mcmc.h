// The sampler of the posterior (posterior.h): adaptive Metropolis on the
// unit box, with split R-hat and the effective sample size of its chains.
// See docs/posterior.md.
#ifndef ROCKCAL_CALIBRATE_MCMC_H_
#define ROCKCAL_CALIBRATE_MCMC_H_

#include <Eigen/Dense>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rockcal::calibrate {

// ---- The sampler -----------------------------------------------------------------

// Whether every coordinate of u lies in [0, 1] (the uniform prior's support;
// false for NaN).
bool InUnitBox(const Eigen::VectorXd& u);

// Options of AdaptiveMetropolis. Defaults in brackets.
struct McmcOptions {
  int chains = 4;      // independent chains, >= 2 (R-hat needs two) [4]
  int burn_in = 3000;  // steps per chain discarded, over which the proposal adapts, >= 100 [3000]
  int steps = 12000;   // steps per chain kept, >= 100 [12000]
  int thin = 12;       // every thin-th kept step is a sample, >= 1 [12]
  std::uint64_t seed = 1;

  bool IsValid(std::string* error) const;
};

struct McmcResult {
  // The samples of every chain, chain after chain (chains * steps / thin of them).
  std::vector<Eigen::VectorXd> samples;
  std::vector<double> rhat;  // split R-hat per coordinate (Gelman et al. 2013)
  std::vector<double> ess;   // effective sample size per coordinate (EffectiveSampleSize)
  double acceptance = 0.0;   // after burn-in, over the chains
};

// Samples the density exp(log_target(u)) on the unit box [0, 1]^d by
// adaptive Metropolis (Haario, Saksman & Tamminen 2001): Gaussian proposals
// whose covariance is (2.38^2 / d) times the chain's own during burn-in,
// then frozen; a proposal outside the box is rejected (uniform prior).
// Chain k starts at starts[k % starts.size()] and draws from its own random
// stream of `seed`: the result depends on the seed only, never on threads.
McmcResult AdaptiveMetropolis(const std::function<double(const Eigen::VectorXd&)>& log_target,
                              const std::vector<Eigen::VectorXd>& starts,
                              const McmcOptions& options);

// Split R-hat of one scalar over chains of equal length (each chain halved).
double SplitRhat(const std::vector<std::vector<double>>& chains);
// The effective sample size of one scalar over chains of equal length (each
// chain halved as for SplitRhat): the draws' count over the integrated
// autocorrelation time, the autocorrelations from the within-chain
// autocovariances and the pooled variance, summed while consecutive pairs
// stay positive (Gelman et al. 2013, Bayesian Data Analysis, 3rd ed.,
// sec. 11.5). NaN for chains of fewer than 8 values.
double EffectiveSampleSize(const std::vector<std::vector<double>>& chains);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_MCMC_H_
