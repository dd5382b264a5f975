// A Gaussian-process emulator of a vector-valued function of the unit box:
// the residual vector of a calibration's misfit, from the evaluations made
// so far, so that the posterior (posterior.h) can be sampled without a
// simulation per step. See docs/posterior.md.
//
// Model (Kennedy & O'Hagan 2001; Santner, Williams & Notz 2003, ch. 2-3):
// each output y_j(u) = h(u)^T b_j + z_j(u), with a linear trend h(u) = (1,
// u_1, ..., u_d) fitted by least squares, and z_j a zero-mean Gaussian
// process of variance s_j^2 and correlation c(u, u') + tau [u = u'], the
// same for every output: a Matern 5/2 kernel with one length scale per
// coordinate (automatic relevance), and a nugget tau for the simulator's
// Monte Carlo noise (with common random numbers a fixed realisation of it:
// the misfit is a rugged, not a smooth, function of the parameters). The
// variances s_j^2 are profiled out; the length scales and the nugget
// maximise the concentrated marginal likelihood (NLopt BOBYQA from a few
// fixed starts, so the fit is deterministic).
#ifndef ROCKCAL_CALIBRATE_EMULATOR_H_
#define ROCKCAL_CALIBRATE_EMULATOR_H_

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace rockcal::calibrate {

// Options of the emulator fit. Defaults in brackets.
struct EmulatorOptions {
  // Bounds of every length scale, in the unit box [0.03, 20].
  double min_length = 0.03, max_length = 20.0;
  // Bounds of the nugget as a share of the process variance [1e-8, 1].
  double min_nugget = 1e-8, max_nugget = 1.0;
  // Marginal-likelihood evaluations per start of the optimiser [300], >= 10.
  int max_evals = 300;

  bool IsValid(std::string* error) const;
};

class Emulator final {
 public:
  // Fits the emulator to points `x` (each of the same dimension d >= 1, in
  // the unit box) and values `y` (one vector of R >= 1 outputs per point).
  // Needs at least d + 3 distinct points. Throws std::invalid_argument for
  // inconsistent sizes, too few points or invalid options.
  static Emulator Fit(const std::vector<std::vector<double>>& x,
                      const std::vector<std::vector<double>>& y, const EmulatorOptions& options = {});

  // The emulator's mean of every output at `u` (unit box), and the variance
  // of the smooth process there (without the nugget: the simulator's own
  // noise is in the misfit's sigmas already).
  void Predict(const Eigen::VectorXd& u, Eigen::VectorXd* mean, Eigen::VectorXd* variance) const;
  // The posterior correlation-scale variance 1 - k^T C^-1 k at `u` (>= 0):
  // each output's variance is it times that output's process variance.
  double ReducedVariance(const Eigen::VectorXd& u) const;

  int dimensions() const { return static_cast<int>(length_.size()); }
  int outputs() const { return static_cast<int>(process_variance_.size()); }
  int points() const { return static_cast<int>(x_.rows()); }
  const Eigen::VectorXd& length_scales() const { return length_; }
  double nugget() const { return nugget_; }  // as a share of the process variance
  const Eigen::VectorXd& process_variances() const { return process_variance_; }
  double log_likelihood() const { return log_likelihood_; }  // concentrated, at the fit

 private:
  Eigen::MatrixXd x_;        // N x d
  Eigen::MatrixXd trend_;    // (d + 1) x R
  Eigen::MatrixXd alpha_;    // N x R: C^-1 (y - H b)
  Eigen::LLT<Eigen::MatrixXd> llt_;  // of C
  Eigen::VectorXd length_;
  Eigen::VectorXd process_variance_;
  double nugget_ = 0.0;
  double log_likelihood_ = 0.0;

  Eigen::VectorXd Correlations(const Eigen::VectorXd& u) const;
};

// The Matern 5/2 correlation at scaled distance r >= 0.
double Matern52(double r);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_EMULATOR_H_
