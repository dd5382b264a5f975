// The correlation of a misfit's residuals, for the posterior's likelihood
// (docs/posterior.md, "Correlated residuals"). The misfit sums squared
// residuals as if each were an independent draw; but the quantiles of one
// distribution share their values, and the statistics of different
// distributions (the heights at two partitions, the stop points, the share
// stopped) are statistics of the same rocks. The posterior takes their
// correlation R into its likelihood by whitening: with R = L L^T, the
// components of L^-1 r are independent where r has correlation R, and
// |L^-1 r|^2 = r^T R^-1 r.
#ifndef ROCKCAL_CALIBRATE_RESIDUAL_CORRELATION_H_
#define ROCKCAL_CALIBRATE_RESIDUAL_CORRELATION_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"

namespace rockcal::calibrate {

// The asymptotic correlation of the quantile residuals of each observation,
// sqrt(p (1 - q) / (q (1 - p))) between its levels p <= q (the covariance of
// sample quantiles: David & Nagaraja 2003, Order Statistics, sec. 10.3), for
// residuals named as `layout` (their values unused); the identity between
// residuals of different observations and for every residual that is not a
// quantile (maxima, shares, fractions, runs, impacts, priors).
Eigen::MatrixXd QuantileCorrelation(const std::vector<observations::Residual>& layout);

// A correlation matrix from `replicates` (one row per replicate, one column
// per residual), shrunk towards `target` (a correlation matrix of as many
// columns) by the weight that minimises the expected squared error of the
// estimate (Schaefer & Strimmer 2005, A shrinkage approach to large-scale
// covariance matrix estimation, Statistical Applications in Genetics and
// Molecular Biology 4:32, their estimator of lambda with a general target):
// lambda = sum Var(r_ij) / sum (r_ij - t_ij)^2 over i != j, in [0, 1]. A
// column that does not vary takes the target's row and column. Sets *lambda
// when given. Fewer than 3 replicates: the target.
Eigen::MatrixXd ShrunkCorrelation(const Eigen::MatrixXd& replicates, const Eigen::MatrixXd& target,
                                  double* lambda = nullptr);

// The correlation of the residuals of `result` against `observations`
// (ComputeMisfit with `options`): their values in `replicates` bootstrap
// resamples of its rocks (each rock group resampled with replacement to its
// own count, from a random stream of `seed`; measured impacts' replays are
// kept as they are), shrunk towards QuantileCorrelation of its residuals
// (ShrunkCorrelation). Replicates whose misfit is penalised or of another
// length are left out. Empty when `result` itself gives a penalised misfit.
// The rocks' resampling stands for both Monte Carlo errors: the simulated
// statistics' and (observations of the same rocks) the observed ones'.
Eigen::MatrixXd BootstrapResidualCorrelation(const observations::Observations& observations,
                                             const core::Scene& scene,
                                             const core::SimulationResult& result,
                                             const observations::MisfitOptions& options,
                                             int replicates, std::uint64_t seed,
                                             double* lambda = nullptr);

// L^-1 for R = L L^T (Cholesky); the identity of R's size when R is not
// positive definite.
Eigen::MatrixXd Whitening(const Eigen::MatrixXd& correlation);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_RESIDUAL_CORRELATION_H_
