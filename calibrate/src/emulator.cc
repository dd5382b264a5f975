#include "rockcal/calibrate/emulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <sstream>
#include <stdexcept>

namespace rockcal::calibrate {

bool EmulatorOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (!(min_length > 0.0 && max_length > min_length))
    s << "length scale bounds [" << min_length << ", " << max_length
      << "]: need 0 < min_length < max_length";
  else if (!(min_nugget > 0.0 && max_nugget > min_nugget))
    s << "nugget bounds [" << min_nugget << ", " << max_nugget
      << "]: need 0 < min_nugget < max_nugget";
  else if (max_evals < 10)
    s << "max_evals = " << max_evals << ": must be >= 10";
  else
    return true;
  *error = s.str();
  return false;
}

double Matern52(double r) {
  const double a = std::sqrt(5.0) * r;
  return (1.0 + a + a * a / 3.0) * std::exp(-a);
}

namespace {

// The correlation matrix of the points (rows of x) at length scales `length`, plus the nugget.
Eigen::MatrixXd CorrelationMatrix(const Eigen::MatrixXd& x, const Eigen::VectorXd& length,
                                  double nugget) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd c(n, n);
  const Eigen::RowVectorXd inverse = length.cwiseInverse().transpose();
  for (Eigen::Index i = 0; i < n; ++i) {
    c(i, i) = 1.0 + nugget;
    for (Eigen::Index j = 0; j < i; ++j) {
      const double r = (x.row(i) - x.row(j)).cwiseProduct(inverse).norm();
      c(i, j) = c(j, i) = Matern52(r);
    }
  }
  return c;
}

// The regressors (1, u_1, ..., u_d) of each point.
Eigen::MatrixXd Regressors(const Eigen::MatrixXd& x) {
  Eigen::MatrixXd h(x.rows(), x.cols() + 1);
  h.col(0).setOnes();
  h.rightCols(x.cols()) = x;
  return h;
}

struct FitState {
  const Eigen::MatrixXd* x;
  const Eigen::MatrixXd* z;  // the outputs less their trend
  int dimensions;
};

// The concentrated log marginal likelihood at theta = (log length scales,
// log nugget); -inf where the correlation matrix is not positive definite.
double ConcentratedLogLikelihood(const std::vector<double>& theta, const FitState& s,
                                 Eigen::LLT<Eigen::MatrixXd>* llt_out = nullptr,
                                 Eigen::VectorXd* variances = nullptr) {
  const int d = s.dimensions;
  Eigen::VectorXd length(d);
  for (int k = 0; k < d; ++k) length(k) = std::exp(theta[static_cast<std::size_t>(k)]);
  const double nugget = std::exp(theta[static_cast<std::size_t>(d)]);
  Eigen::LLT<Eigen::MatrixXd> llt(CorrelationMatrix(*s.x, length, nugget));
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  const double n = static_cast<double>(s.x->rows());
  const Eigen::MatrixXd w = llt.matrixL().solve(*s.z);  // L^-1 z
  double log_det = 0.0;
  for (Eigen::Index i = 0; i < s.x->rows(); ++i) log_det += 2.0 * std::log(llt.matrixL()(i, i));
  const Eigen::Index r = s.z->cols();
  Eigen::VectorXd sigma2(r);
  double value = -0.5 * static_cast<double>(r) * log_det;
  for (Eigen::Index j = 0; j < r; ++j) {
    const double floor = 1e-12 * (1.0 + s.z->col(j).squaredNorm() / n);
    sigma2(j) = std::max(floor, w.col(j).squaredNorm() / n);
    value -= 0.5 * n * std::log(sigma2(j));
  }
  if (llt_out) *llt_out = llt;
  if (variances) *variances = sigma2;
  return std::isfinite(value) ? value : -std::numeric_limits<double>::infinity();
}

}  // namespace

Emulator Emulator::Fit(const std::vector<std::vector<double>>& x,
                       const std::vector<std::vector<double>>& y, const EmulatorOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("emulator options: " + error);
  if (x.empty() || x.size() != y.size())
    throw std::invalid_argument("emulator: " + std::to_string(x.size()) + " points and " +
                                std::to_string(y.size()) + " value vectors");
  const int d = static_cast<int>(x.front().size());
  const int r = static_cast<int>(y.front().size());
  const int n = static_cast<int>(x.size());
  if (d < 1 || r < 1) throw std::invalid_argument("emulator: no dimensions or no outputs");
  if (n < d + 3)
    throw std::invalid_argument("emulator: " + std::to_string(n) + " points for " +
                                std::to_string(d) + " dimensions; need at least " +
                                std::to_string(d + 3));
  Emulator e;
  e.x_.resize(n, d);
  Eigen::MatrixXd values(n, r);
  for (int i = 0; i < n; ++i) {
    if (static_cast<int>(x[static_cast<std::size_t>(i)].size()) != d ||
        static_cast<int>(y[static_cast<std::size_t>(i)].size()) != r)
      throw std::invalid_argument("emulator: point " + std::to_string(i) +
                                  " has another dimension or output count");
    for (int k = 0; k < d; ++k) e.x_(i, k) = x[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
    for (int j = 0; j < r; ++j) values(i, j) = y[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  }
  // The linear trend by least squares (complete orthogonal decomposition:
  // defined even where the points do not span a direction).
  const Eigen::MatrixXd h = Regressors(e.x_);
  e.trend_ = h.completeOrthogonalDecomposition().solve(values);
  const Eigen::MatrixXd z = values - h * e.trend_;

  const FitState state{&e.x_, &z, d};
  std::vector<double> lower(static_cast<std::size_t>(d + 1)), upper(lower.size());
  for (int k = 0; k < d; ++k) {
    lower[static_cast<std::size_t>(k)] = std::log(options.min_length);
    upper[static_cast<std::size_t>(k)] = std::log(options.max_length);
  }
  lower[static_cast<std::size_t>(d)] = std::log(options.min_nugget);
  upper[static_cast<std::size_t>(d)] = std::log(options.max_nugget);
  // Fixed starts: short, middling and long length scales, each with a
  // small and a large nugget; the best of the local optima.
  std::vector<double> best;
  double best_value = -std::numeric_limits<double>::infinity();
  for (double length : {0.2, 0.6, 2.0})
    for (double nugget : {1e-3, 0.1}) {
      std::vector<double> theta(static_cast<std::size_t>(d + 1), std::log(length));
      theta[static_cast<std::size_t>(d)] = std::log(nugget);
      nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(d + 1));
      opt.set_lower_bounds(lower);
      opt.set_upper_bounds(upper);
      opt.set_maxeval(options.max_evals);
      opt.set_xtol_abs(1e-3);
      opt.set_ftol_abs(1e-6);
      opt.set_initial_step(0.5);
      opt.set_max_objective(
          [](const std::vector<double>& t, std::vector<double>&, void* data) {
            const double v = ConcentratedLogLikelihood(t, *static_cast<const FitState*>(data));
            return std::isfinite(v) ? v : -1e300;
          },
          const_cast<FitState*>(&state));
      double value = -std::numeric_limits<double>::infinity();
      try {
        opt.optimize(theta, value);
      } catch (const std::exception&) {
        value = ConcentratedLogLikelihood(theta, state);  // round-off: keep where it stopped
      }
      if (value > best_value) {
        best_value = value;
        best = theta;
      }
    }
  if (best.empty()) throw std::invalid_argument("emulator: no positive definite correlation");
  e.length_.resize(d);
  for (int k = 0; k < d; ++k) e.length_(k) = std::exp(best[static_cast<std::size_t>(k)]);
  e.nugget_ = std::exp(best[static_cast<std::size_t>(d)]);
  e.log_likelihood_ = ConcentratedLogLikelihood(best, state, &e.llt_, &e.process_variance_);
  if (!std::isfinite(e.log_likelihood_))
    throw std::invalid_argument("emulator: no positive definite correlation at the fit");
  e.alpha_ = e.llt_.solve(z);
  return e;
}

Eigen::VectorXd Emulator::Correlations(const Eigen::VectorXd& u) const {
  const Eigen::Index n = x_.rows();
  Eigen::VectorXd k(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double r2 = 0.0;
    for (Eigen::Index c = 0; c < x_.cols(); ++c) {
      const double t = (x_(i, c) - u(c)) / length_(c);
      r2 += t * t;
    }
    k(i) = Matern52(std::sqrt(r2));
  }
  return k;
}

double Emulator::ReducedVariance(const Eigen::VectorXd& u) const {
  const Eigen::VectorXd k = Correlations(u);
  const Eigen::VectorXd w = llt_.matrixL().solve(k);
  return std::max(0.0, 1.0 - w.squaredNorm());
}

void Emulator::Predict(const Eigen::VectorXd& u, Eigen::VectorXd* mean,
                       Eigen::VectorXd* variance) const {
  const Eigen::VectorXd k = Correlations(u);
  Eigen::VectorXd h(u.size() + 1);
  h(0) = 1.0;
  h.tail(u.size()) = u;
  *mean = trend_.transpose() * h + alpha_.transpose() * k;
  if (variance) {
    const Eigen::VectorXd w = llt_.matrixL().solve(k);
    *variance = process_variance_ * std::max(0.0, 1.0 - w.squaredNorm());
  }
}

}  // namespace rockcal::calibrate
