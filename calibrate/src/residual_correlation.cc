#include "rockcal/calibrate/residual_correlation.h"

#include <cmath>
#include <map>
#include <utility>

#include <Eigen/Cholesky>

#include "rockcal/core/random.h"

namespace rockcal::calibrate {
namespace {

constexpr std::uint64_t kBootstrapStream = 0x424f4f5453545250ull;  // "BOOTSTRP"

}  // namespace

Eigen::MatrixXd QuantileCorrelation(const std::vector<observations::Residual>& layout) {
  const Eigen::Index n = static_cast<Eigen::Index>(layout.size());
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(n, n);
  // The quantile residuals of each observation: (index, level).
  std::map<observations::ResidualId, std::vector<std::pair<Eigen::Index, double>>> groups;
  for (Eigen::Index k = 0; k < n; ++k) {
    const observations::ResidualId& id = layout[static_cast<std::size_t>(k)].id;
    if (id.statistic != observations::Statistic::kQuantile || !(id.level > 0.0 && id.level < 1.0))
      continue;
    groups[id.observation_id()].push_back({k, id.level});
  }
  for (const auto& [name, members] : groups)
    for (const auto& [i, p0] : members)
      for (const auto& [j, q0] : members) {
        const double p = std::min(p0, q0), q = std::max(p0, q0);
        c(i, j) = std::sqrt(p * (1.0 - q) / (q * (1.0 - p)));
      }
  return c;
}

Eigen::MatrixXd ShrunkCorrelation(const Eigen::MatrixXd& replicates, const Eigen::MatrixXd& target,
                                  double* lambda) {
  const Eigen::Index n = replicates.rows(), p = replicates.cols();
  if (lambda) *lambda = 1.0;
  if (n < 3) return target;
  // Standardised columns; those that do not vary are marked.
  Eigen::MatrixXd x = replicates.rowwise() - replicates.colwise().mean();
  std::vector<bool> varies(static_cast<std::size_t>(p), false);
  for (Eigen::Index j = 0; j < p; ++j) {
    // Constant up to rounding (the mean of equal values need not equal
    // them): the spread against the values' own size.
    const double range = replicates.col(j).maxCoeff() - replicates.col(j).minCoeff();
    const double size = replicates.col(j).cwiseAbs().maxCoeff();
    const double sd = std::sqrt(x.col(j).squaredNorm() / static_cast<double>(n - 1));
    if (range > 1e-12 * size && std::isfinite(sd) && sd > 0.0) {
      x.col(j) /= sd;
      varies[static_cast<std::size_t>(j)] = true;
    } else {
      x.col(j).setZero();
    }
  }
  // r_ij = n / (n - 1) mean_k w_kij with w_kij = x_ki x_kj, and its
  // variance n / (n - 1)^3 sum_k (w_kij - mean w_ij)^2.
  const double nd = static_cast<double>(n);
  const Eigen::MatrixXd r = x.transpose() * x / (nd - 1.0);
  double var_sum = 0.0, dist_sum = 0.0;
  for (Eigen::Index i = 0; i < p; ++i) {
    if (!varies[static_cast<std::size_t>(i)]) continue;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (j == i || !varies[static_cast<std::size_t>(j)]) continue;
      const Eigen::ArrayXd w = x.col(i).array() * x.col(j).array();
      const double mean = w.mean();
      var_sum += nd / ((nd - 1.0) * (nd - 1.0) * (nd - 1.0)) * (w - mean).square().sum();
      const double d = r(i, j) - target(i, j);
      dist_sum += d * d;
    }
  }
  const double l = dist_sum > 0.0 ? std::min(1.0, std::max(0.0, var_sum / dist_sum)) : 1.0;
  if (lambda) *lambda = l;
  Eigen::MatrixXd out = target;
  for (Eigen::Index i = 0; i < p; ++i)
    for (Eigen::Index j = 0; j < p; ++j)
      if (i != j && varies[static_cast<std::size_t>(i)] && varies[static_cast<std::size_t>(j)])
        out(i, j) = l * target(i, j) + (1.0 - l) * r(i, j);
  return out;
}

Eigen::MatrixXd BootstrapResidualCorrelation(const observations::Observations& observations,
                                             const core::Scene& scene,
                                             const core::SimulationResult& result,
                                             const observations::MisfitOptions& options,
                                             int replicates, std::uint64_t seed, double* lambda) {
  const observations::Misfit base = observations::ComputeMisfit(observations, scene, result, options);
  if (base.penalised || base.residuals.empty()) return {};
  const Eigen::Index p = static_cast<Eigen::Index>(base.residuals.size());
  // The rocks of each group, resampled within it.
  std::map<int, std::vector<std::size_t>> groups;
  for (std::size_t k = 0; k < result.rocks.size(); ++k) groups[result.rocks[k].group].push_back(k);
  core::RandomStream random(seed, kBootstrapStream);
  std::vector<Eigen::VectorXd> rows;
  core::SimulationResult resample;
  resample.impacts = result.impacts;
  resample.cells_recorded = result.cells_recorded;
  resample.strikes_recorded = result.strikes_recorded;
  for (int b = 0; b < replicates; ++b) {
    resample.rocks.clear();
    for (const auto& [group, members] : groups)
      for (std::size_t k = 0; k < members.size(); ++k)
        resample.rocks.push_back(result.rocks[members[random.Index(members.size())]]);
    const observations::Misfit m = observations::ComputeMisfit(observations, scene, resample, options);
    if (m.penalised || static_cast<Eigen::Index>(m.residuals.size()) != p) continue;
    Eigen::VectorXd row(p);
    // The simulated value over the unresampled residual's sigma: the
    // statistic's own variation, not its error estimate's.
    for (Eigen::Index j = 0; j < p; ++j) {
      const observations::Residual& r0 = base.residuals[static_cast<std::size_t>(j)];
      row(j) = m.residuals[static_cast<std::size_t>(j)].simulated / r0.sigma;
    }
    if (row.allFinite()) rows.push_back(std::move(row));
  }
  Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), p);
  for (std::size_t b = 0; b < rows.size(); ++b) x.row(static_cast<Eigen::Index>(b)) = rows[b];
  return ShrunkCorrelation(x, QuantileCorrelation(base.residuals), lambda);
}

Eigen::MatrixXd Whitening(const Eigen::MatrixXd& correlation) {
  const Eigen::Index n = correlation.rows();
  Eigen::LLT<Eigen::MatrixXd> llt(correlation);
  if (llt.info() != Eigen::Success) return Eigen::MatrixXd::Identity(n, n);
  return llt.matrixL().solve(Eigen::MatrixXd::Identity(n, n));
}

}  // namespace rockcal::calibrate
