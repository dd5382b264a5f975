// How well the data determine the calibrated values: standard errors and
// correlations from a Jacobian or from the search's own evaluations, and the
// smoothed estimate's local model of the residuals.
#ifndef ROCKCAL_CALIBRATE_UNCERTAINTY_H_
#define ROCKCAL_CALIBRATE_UNCERTAINTY_H_

#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/evaluation.h"
#include "rockcal/calibrate/objective.h"

namespace rockcal::calibrate {

// Standard errors and correlations of the calibrated parameters from the
// Jacobian of the scaled residuals (Ceres).
struct Uncertainty {
  bool computed = false;
  bool rank_deficient = false;
  std::string message;
  std::vector<double> std_error;                 // physical units
  std::vector<std::vector<double>> correlation;  // n x n
  std::vector<double> singular_values;           // of the Jacobian in the unit box
  // From the search's own evaluations (LocalModelUncertainty), not from a
  // Jacobian by central differences at the calibrated values.
  bool from_search = false;
};

// The smoothed estimate of a method run (MethodOptions::estimate).
struct SmoothedEstimate {
  bool used = false;              // false: the calibrated values are the lowest evaluation
  std::string message;            // how it was made, or why it was not
  int points = 0;                 // evaluations the linear model was fitted to
  double radius = 0.0;            // their neighbourhood's half-width in the unit box
  double predicted_misfit = 0.0;  // the model's misfit at the estimate
  // How the fitted evaluations' misfits m_i stand to the model's, 0.5 |a + J
  // d_i|^2: the median of m_i - model_i (the noise's own share, > 0) and its
  // scatter, 1.4826 times the median absolute deviation (a standard
  // deviation that a few far, poorly modelled evaluations do not inflate).
  // The estimate is used only where its evaluated
  // misfit is at most 3 of them above model + offset (the model holds there)
  // and at most 1 above the lowest evaluation (it is not visibly worse than
  // the lowest).
  double offset = 0.0, scatter = 0.0;
  double evaluated_misfit = 0.0;  // the misfit evaluated at the estimate
};

// Standard errors and correlations at `at` (physical values, misfit
// `misfit` there): the Jacobian of the scaled residuals by central
// differences in the unit box (2n evaluations, spread over the ranks under
// mpirun, a step of 5 % of each range or less near a bound), then the
// Gauss-Newton covariance (J^T J)^-1, scaled by the reduced chi-square when
// that is above 1, mapped to physical units. What the ceres method reports
// at its calibrated values.
Uncertainty JacobianUncertaintyAt(const ObjectiveFunction& objective, const std::vector<double>& at,
                                  double misfit);

// One stage of the smoothed estimate of MethodOptions::estimate: a linear
// model of the residual vector, r(u) = a + J (u - u_around) in the unit box,
// fitted by least squares to the unpenalised evaluations of `trace` within
// `radius` (max norm) of `around` (physical values), the radius widened by
// half until 2(n + 1) of them are inside; then the Gauss-Newton minimiser of
// |a + J d|^2 (least norm where J is rank deficient), each component of d
// clamped to the radius and the box. Returns the estimate in the unit box,
// or nothing when the evaluations cannot determine the model (too few, or
// not spanning every parameter); *info receives the points, the radius, the
// model's misfit at the estimate and a message.
std::optional<std::vector<double>> FitSmoothedEstimate(const std::vector<Evaluation>& trace,
                                                       const ParameterSpace& space,
                                                       const std::vector<double>& around,
                                                       double radius, SmoothedEstimate* info);

// Standard errors at `at` (physical values; `misfit` there) from the same
// local linear model of the residuals as FitSmoothedEstimate's, fitted to
// the evaluations of `trace` around `at`: what the search's own evaluations
// say of how well the data determine each value, at no extra simulation.
// Not computed (Uncertainty::computed false) when the model cannot be fitted.
Uncertainty LocalModelUncertainty(const std::vector<Evaluation>& trace, const ParameterSpace& space,
                                  const std::vector<double>& at, double misfit, double radius);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_UNCERTAINTY_H_
