// Standard errors, correlations and the smoothed estimate's local model
// (uncertainty.h).
#include "rockcal/calibrate/uncertainty.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace rockcal::calibrate {
namespace {

// Standard errors (physical units) and correlations from the covariance
// (J^T J)^-1 = V diag(1 / lambda) V^T in the unit box, scaled by the reduced
// chi-square of `residuals` residuals at `misfit` when the fit is worse than
// the stated uncertainties imply; returns that chi-square.
double FillFromInverseGram(const Eigen::MatrixXd& v, const Eigen::VectorXd& lambda, long residuals,
                           double misfit, const ParameterSpace& space, Uncertainty* u) {
  const int n = static_cast<int>(lambda.size());
  const int dof = std::max<int>(1, static_cast<int>(residuals) - n);
  const double chi2 = std::max(1.0, 2.0 * misfit / dof);
  const Eigen::MatrixXd cov = chi2 * v * lambda.cwiseInverse().asDiagonal() * v.transpose();
  for (int k = 0; k < n; ++k) {
    const auto& p = space.parameters()[k];
    u->std_error.push_back(std::sqrt(cov(k, k)) * (p.upper - p.lower));
  }
  u->correlation.assign(n, std::vector<double>(n, 0.0));
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) u->correlation[a][b] = cov(a, b) / std::sqrt(cov(a, a) * cov(b, b));
  return chi2;
}

// Standard errors from the Jacobian of the scaled residuals at the best
// point: cov = (J^T J)^-1 in the unit box, mapped to physical units.
Uncertainty JacobianUncertainty(const Eigen::MatrixXd& j_unit, double misfit,
                                const ParameterSpace& space) {
  Uncertainty u;
  const int n = static_cast<int>(j_unit.cols());
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(j_unit, Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  for (int k = 0; k < s.size(); ++k) u.singular_values.push_back(s[k]);
  const double tol = 1e-6 * (s.size() ? s[0] : 0.0);
  int rank = 0;
  for (int k = 0; k < s.size(); ++k) rank += s[k] > tol;
  u.computed = true;
  if (rank < n || s.size() == 0 || s[0] == 0.0) {
    u.rank_deficient = true;
    std::ostringstream msg;
    msg << "Jacobian rank " << rank << " of " << n
        << ": some parameter combinations do not change the misfit (not separately identifiable)";
    if (s.size() > 0) {
      const Eigen::VectorXd v = svd.matrixV().col(n - 1);
      msg << "; the least determined direction is";
      for (int k = 0; k < n; ++k)
        if (std::abs(v[k]) > 0.2)
          msg << " " << (v[k] > 0 ? "+" : "-") << space.parameters()[k].label();
    }
    u.message = msg.str();
    return u;
  }
  const double chi2 =
      FillFromInverseGram(svd.matrixV(), s.cwiseAbs2(), j_unit.rows(), misfit, space, &u);
  const double condition = s[0] / s[n - 1];
  std::ostringstream msg;
  msg << "linearised, from the Jacobian of the scaled residuals (condition number " << condition
      << ", reduced chi-square " << chi2
      << "); quantile residuals of one distribution are correlated, so these errors are a lower "
         "bound";
  u.message = msg.str();
  return u;
}

}  // namespace

Uncertainty JacobianUncertaintyAt(const ObjectiveFunction& objective, const std::vector<double>& at,
                                  double misfit) {
  const int n = objective.space().size();
  if (at.empty() || objective.residual_count() <= 0) return Uncertainty{};
  const std::vector<double> best_unit = objective.space().ToUnit(at);
  const int m = objective.residual_count();
  Eigen::MatrixXd j(m, n);
  // The 2n points are independent: simulated over the ranks of an MPI run.
  std::vector<std::vector<double>> points;
  std::vector<double> widths;
  for (int k = 0; k < n; ++k) {
    const double h = std::min(0.05, 0.5 * std::min(best_unit[k], 1 - best_unit[k]) + 1e-3);
    std::vector<double> up = best_unit, down = best_unit;
    up[k] = std::min(1.0, up[k] + h);
    down[k] = std::max(0.0, down[k] - h);
    widths.push_back(up[k] - down[k]);
    points.push_back(objective.space().ToPhysical(up));
    points.push_back(objective.space().ToPhysical(down));
  }
  const std::vector<observations::Misfit> misfits = objective.EvaluateAll(points);
  for (int k = 0; k < n; ++k) {
    const observations::Misfit& a = misfits[2 * static_cast<std::size_t>(k)];
    const observations::Misfit& b = misfits[2 * static_cast<std::size_t>(k) + 1];
    for (int r = 0; r < m; ++r)
      j(r, k) = (a.residuals[r].value - b.residuals[r].value) / widths[static_cast<std::size_t>(k)];
  }
  return JacobianUncertainty(j, misfit, objective.space());
}

namespace {

// A linear model of the residual vector, r(u) = a + J (u - centre) in the
// unit box, fitted to the unpenalised evaluations of a trace near `centre`.
struct LocalResidualModel {
  Eigen::VectorXd a;              // m
  Eigen::MatrixXd j;              // m x n
  Eigen::MatrixXd offsets;        // one row u_i - centre per evaluation used
  std::vector<std::size_t> near;  // the evaluations used (trace indices)
  // What the evaluations' noise adds to J^T J on average: the sum over the
  // residuals of their scatter about the model, s_r^2, times the covariance
  // block (X^T X)^-1 of the slopes (n x n). J^T J minus it estimates the
  // noise-free J^T J without bias.
  Eigen::MatrixXd noise_gram;
};

// Fits the model to the evaluations within `radius` (max norm) of `centre`,
// the radius widened by half until 2(n + 1) are inside. *radius_used gets
// the final radius; nothing (with *why) when too few evaluations, or ones
// not spanning every parameter, make the model undetermined.
std::optional<LocalResidualModel> FitLocalResidualModel(const std::vector<Evaluation>& trace,
                                                        const ParameterSpace& space,
                                                        const std::vector<double>& centre,
                                                        double radius, int* points_used,
                                                        double* radius_used, std::string* why) {
  const int n = space.size();
  std::size_t m = 0;
  std::vector<std::vector<double>> units;
  for (const Evaluation& e : trace) {
    units.push_back(space.ToUnit(e.parameters));
    if (!e.penalised) m = std::max(m, e.residuals.size());
  }
  auto distance = [&](const std::vector<double>& u) {
    double d = 0.0;
    for (int k = 0; k < n; ++k) d = std::max(d, std::abs(u[k] - centre[k]));
    return d;
  };
  const std::size_t wanted = 2 * static_cast<std::size_t>(n + 1);
  std::vector<std::size_t> near;
  for (;; radius = std::min(1.0, 1.5 * radius)) {
    near.clear();
    for (std::size_t i = 0; i < trace.size(); ++i)
      if (!trace[i].penalised && trace[i].residuals.size() == m && distance(units[i]) <= radius)
        near.push_back(i);
    if (near.size() >= wanted || radius >= 1.0) break;
  }
  *radius_used = radius;
  *points_used = static_cast<int>(near.size());
  if (m == 0 || near.size() < wanted) {
    *why = std::to_string(near.size()) + " unpenalised evaluations, fewer than the " +
           std::to_string(wanted) + " a linear model of the residuals needs";
    return std::nullopt;
  }
  Eigen::MatrixXd x(static_cast<Eigen::Index>(near.size()), n + 1);
  Eigen::MatrixXd r(static_cast<Eigen::Index>(near.size()), static_cast<Eigen::Index>(m));
  for (std::size_t a = 0; a < near.size(); ++a) {
    const Eigen::Index row = static_cast<Eigen::Index>(a);
    x(row, 0) = 1.0;
    for (int k = 0; k < n; ++k) x(row, k + 1) = units[near[a]][k] - centre[k];
    for (std::size_t b = 0; b < m; ++b)
      r(row, static_cast<Eigen::Index>(b)) = trace[near[a]].residuals[b];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  if (qr.rank() < n + 1) {
    *why =
        "the evaluations nearby do not span every parameter (they lie on a "
        "lower-dimensional set), so the model is undetermined";
    return std::nullopt;
  }
  const Eigen::MatrixXd coef = qr.solve(r);  // (n + 1) x m
  LocalResidualModel model;
  model.a = coef.row(0).transpose();
  model.j = coef.bottomRows(n).transpose();  // m x n
  model.offsets = x.rightCols(n);
  const Eigen::Index points = static_cast<Eigen::Index>(near.size());
  const Eigen::MatrixXd xtx_inv =
      (x.transpose() * x).inverse().bottomRightCorner(n, n);  // slopes' covariance / s^2
  const double dof = static_cast<double>(points - (n + 1));
  double scatter = 0.0;  // sum of s_r^2
  if (dof > 0) scatter = (r - x * coef).colwise().squaredNorm().sum() / dof;
  model.noise_gram = scatter * xtx_inv;
  model.near = std::move(near);
  return model;
}

}  // namespace

Uncertainty LocalModelUncertainty(const std::vector<Evaluation>& trace, const ParameterSpace& space,
                                  const std::vector<double>& at, double misfit, double radius) {
  if (at.empty()) return Uncertainty{};
  int points = 0;
  double used = 0.0;
  std::string why;
  const std::optional<LocalResidualModel> model =
      FitLocalResidualModel(trace, space, space.ToUnit(at), radius, &points, &used, &why);
  if (!model) return Uncertainty{};
  // The fitted slopes carry the evaluations' Monte Carlo noise, which makes
  // J^T J larger than the misfit's true curvature and the errors too small:
  // take its average share off. A direction where nothing is left is one
  // the evaluations cannot tell from noise.
  const int n = space.size();
  const Eigen::MatrixXd gram = model->j.transpose() * model->j - model->noise_gram;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (gram + gram.transpose()));
  const Eigen::VectorXd lambda = eig.eigenvalues();  // ascending
  const Eigen::MatrixXd v = eig.eigenvectors();
  Uncertainty u;
  u.computed = true;
  u.from_search = true;
  for (int k = n - 1; k >= 0; --k) u.singular_values.push_back(std::sqrt(std::max(0.0, lambda[k])));
  std::ostringstream from;
  from << "a linear model of the residuals fitted to the " << points << " evaluations within "
       << used << " (unit box) of the calibrated values, its slopes' noise taken off, no extra "
       << "simulation";
  const double top = lambda[n - 1];
  if (!(top > 0.0) || !(lambda[0] > 1e-6 * top)) {
    u.rank_deficient = true;
    std::ostringstream msg;
    int lost = 0;
    while (lost < n && !(lambda[lost] > 1e-6 * std::max(top, 0.0))) ++lost;
    msg << "the misfit's curvature is lost in the Monte Carlo noise of the evaluations along "
        << lost << " of " << n << " directions, the least determined";
    Eigen::Index largest = 0;
    v.col(0).cwiseAbs().maxCoeff(&largest);
    const double sign = v(largest, 0) > 0 ? 1.0 : -1.0;  // its largest part counted +
    for (int k = 0; k < n; ++k)
      if (std::abs(v(k, 0)) > 0.3)
        msg << " " << (sign * v(k, 0) > 0 ? "+" : "-") << space.parameters()[k].label();
    msg << ": the values are not shown to be determined by the observations (more rocks or "
           "evaluations near them, calibrations at other seeds, or cross-validation tell more; "
           "from "
        << from.str() << ")";
    u.message = msg.str();
    return u;
  }
  const double chi2 = FillFromInverseGram(v, lambda, model->j.rows(), misfit, space, &u);
  std::ostringstream msg;
  msg << "linearised (condition number " << std::sqrt(top / lambda[0]) << ", reduced chi-square "
      << chi2 << "), from " << from.str()
      << "; quantile residuals of one distribution are correlated, so these errors are a lower "
         "bound";
  u.message = msg.str();
  return u;
}

std::optional<std::vector<double>> FitSmoothedEstimate(const std::vector<Evaluation>& trace,
                                                       const ParameterSpace& space,
                                                       const std::vector<double>& around,
                                                       double radius, SmoothedEstimate* info) {
  const int n = space.size();
  const std::vector<double> centre = space.ToUnit(around);
  std::string why;
  const std::optional<LocalResidualModel> model =
      FitLocalResidualModel(trace, space, centre, radius, &info->points, &info->radius, &why);
  if (!model) {
    info->message = why;
    return std::nullopt;
  }
  radius = info->radius;
  const Eigen::VectorXd& a = model->a;
  const Eigen::MatrixXd& j = model->j;
  const std::vector<std::size_t>& near = model->near;
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(j);
  const Eigen::VectorXd d = -cod.solve(a);
  std::vector<double> unit(static_cast<std::size_t>(n));
  Eigen::VectorXd step(n);
  for (int k = 0; k < n; ++k) {
    unit[k] = std::clamp(centre[k] + std::clamp(d[k], -radius, radius), 0.0, 1.0);
    step[k] = unit[k] - centre[k];
  }
  info->predicted_misfit = 0.5 * (a + j * step).squaredNorm();
  // Robust: the median and the scaled median absolute deviation, so that a
  // few far evaluations where the model is poor do not widen the scatter.
  std::vector<double> delta;
  for (std::size_t p = 0; p < near.size(); ++p) {
    const Eigen::VectorXd di = model->offsets.row(static_cast<Eigen::Index>(p)).transpose();
    delta.push_back(trace[near[p]].misfit - 0.5 * (a + j * di).squaredNorm());
  }
  auto median = [](std::vector<double> v) {
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    const double upper = v[mid];
    if (v.size() % 2 == 1) return upper;
    return 0.5 *
           (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  };
  info->offset = median(delta);
  for (double& v : delta) v = std::abs(v - info->offset);
  info->scatter = 1.4826 * median(delta);
  std::ostringstream msg;
  msg << "linear model of the residuals fitted to the " << near.size() << " evaluations within "
      << radius << " (unit box)";
  if (cod.rank() < n) msg << "; the model's Jacobian has rank " << cod.rank() << " of " << n;
  info->message = msg.str();
  return unit;
}

}  // namespace rockcal::calibrate
