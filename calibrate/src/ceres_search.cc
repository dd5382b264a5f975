// Ceres' least squares as a search method (search.h).
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "search.h"

namespace rockcal::calibrate {
namespace {

// Ceres holds t + kCeresOffset, so its relative step becomes an absolute step in t.
constexpr double kCeresOffset = 100.0;

// Ceres residual functor over the offset unbounded parameters.
class CeresResiduals final {
 public:
  CeresResiduals(Evaluator* ev, int size) : ev_(ev), size_(size) {}
  bool operator()(double const* const* parameters, double* residuals) const {
    if (ev_->exhausted()) {
      // Out of budget inside an iteration: answer with the best residuals (not
      // an evaluation); the callback ends the solve at the iteration's end.
      const std::vector<double>& best = ev_->best_residuals();
      for (std::size_t k = 0; k < best.size(); ++k) residuals[k] = best[k];
      return !best.empty();
    }
    std::vector<double> unit(static_cast<std::size_t>(size_));
    for (int k = 0; k < size_; ++k)
      unit[k] = 1.0 / (1.0 + std::exp(-(parameters[0][k] - kCeresOffset)));
    const Evaluation& e = ev_->Evaluate(unit);
    for (std::size_t k = 0; k < e.residuals.size(); ++k) residuals[k] = e.residuals[k];
    return true;
  }

 private:
  Evaluator* ev_;
  int size_;
};

class BudgetCallback final : public ceres::IterationCallback {
 public:
  explicit BudgetCallback(const Evaluator* ev) : ev_(ev) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return ev_->exhausted() ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }

 private:
  const Evaluator* ev_;
};

// Runs Ceres from `unit` within the evaluator's budget; returns why it stopped.
Termination RunCeres(const std::vector<double>& unit, const MethodOptions& options, Evaluator* ev) {
  const int n = static_cast<int>(unit.size());
  // Unit box -> unbounded t = log(u / (1 - u)), kept away from the edges.
  std::vector<double> w(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double u = std::clamp(unit[k], 0.02, 0.98);
    w[k] = std::log(u / (1 - u)) + kCeresOffset;
  }
  ceres::NumericDiffOptions diff;
  diff.relative_step_size = options.ceres_step / kCeresOffset;
  auto* functor = new CeresResiduals(ev, n);
  auto* cost = new ceres::DynamicNumericDiffCostFunction<CeresResiduals, ceres::CENTRAL>(
      functor, ceres::TAKE_OWNERSHIP, diff);
  cost->AddParameterBlock(n);
  cost->SetNumResiduals(static_cast<int>(ev->residual_count()));
  ceres::Problem problem;
  ceres::LossFunction* loss = nullptr;
  if (options.ceres_loss == CeresLoss::kHuber) loss = new ceres::HuberLoss(1.0);
  if (options.ceres_loss == CeresLoss::kCauchy) loss = new ceres::CauchyLoss(1.0);
  problem.AddResidualBlock(cost, loss, w.data());
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = std::max(1, options.max_evals);
  so.minimizer_progress_to_stdout = false;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;  // parallelism is inside each simulation
  BudgetCallback callback(ev);
  so.callbacks.push_back(&callback);
  so.update_state_every_iteration = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (ev->exhausted()) return {TerminationType::kBudgetUsed, "budget used"};
  switch (summary.termination_type) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS:
      return {TerminationType::kConverged, summary.message};
    case ceres::NO_CONVERGENCE:
      return {TerminationType::kBudgetUsed, summary.message};
    case ceres::FAILURE:
    case ceres::USER_FAILURE:
      return {TerminationType::kFailed, summary.message};
  }
  return {TerminationType::kStopped, summary.message};
}

}  // namespace

Termination CeresSearch::Search(const std::vector<double>& unit, const MethodOptions& options,
                                const ParameterSpace&, Evaluator* ev) const {
  return RunCeres(unit, options, ev);
}

Uncertainty CeresSearch::UncertaintyOf(const MethodResult& result,
                                       const ObjectiveFunction& objective,
                                       const MethodOptions&) const {
  if (result.best.empty()) return Uncertainty{};
  return JacobianUncertaintyAt(objective, result.best, result.best_misfit);
}

}  // namespace rockcal::calibrate
