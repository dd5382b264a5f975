#include "rockcal/calibrate/calibration.h"

#include <ceres/ceres.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <nlopt.hpp>
#include <optional>
#include <sstream>
#include <tuple>

#include "rockcal/core/error.h"
#include "rockcal/core/name_table.h"
#include "rockcal/parallel/parallel.h"
#include "rockcal/sites/input_file.h"

namespace rockcal::calibrate {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Ceres holds t + kCeresOffset, so its relative step becomes an absolute step in t.
constexpr double kCeresOffset = 100.0;

// The methods' one table: name, and how RunMethod runs each.
struct MethodInfo {
  Method id;
  const char* name;
  bool ceres;
  nlopt::algorithm algorithm;
  bool global;
};

const MethodInfo kMethods[] = {
    {Method::kBobyqa, "nlopt:bobyqa", false, nlopt::LN_BOBYQA, false},
    {Method::kSbplx, "nlopt:sbplx", false, nlopt::LN_SBPLX, false},
    {Method::kNelderMead, "nlopt:neldermead", false, nlopt::LN_NELDERMEAD, false},
    {Method::kCobyla, "nlopt:cobyla", false, nlopt::LN_COBYLA, false},
    {Method::kDirectL, "nlopt:direct_l", false, nlopt::GN_DIRECT_L, true},
    {Method::kCrs2, "nlopt:crs2", false, nlopt::GN_CRS2_LM, true},
    {Method::kIsres, "nlopt:isres", false, nlopt::GN_ISRES, true},
    {Method::kMlsl, "nlopt:mlsl", false, nlopt::G_MLSL_LDS, true},
    {Method::kCeres, "ceres", true, nlopt::LN_BOBYQA, false},
};

nlohmann::json ToJson(const Evaluation& e) {
  return {{"method", e.stage.name()}, {"evaluation", e.index},    {"parameters", e.parameters},
          {"misfit", e.misfit},       {"residuals", e.residuals}, {"penalised", e.penalised},
          {"seconds", e.seconds},     {"elapsed", e.elapsed}};
}

// A whole-number field of a log record, from 0 to T's maximum. A fraction, a
// negative number or one beyond T (1e300) is not a record rockcal wrote, and
// converting it would be undefined behaviour.
template <typename T>
T WholeField(const nlohmann::json& record, const char* key, const std::string& where) {
  const nlohmann::json& v = record.at(key);
  if (v.is_number_unsigned()) {
    const std::uint64_t u = v.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())) return static_cast<T>(u);
  }
  throw InputError(where, std::string("not an evaluation record: \"") + key + "\" is " +
                              (v.is_number() ? v.dump() : std::string("a ") + v.type_name()) +
                              "; expected a whole number from 0 to " +
                              std::to_string(std::numeric_limits<T>::max()));
}

// Everything a method asks of the objective: budget, log replay, trace, best.
class Evaluator final {
 public:
  Evaluator(Stage stage, const ObjectiveFunction& objective, const MethodOptions& options,
            EvaluationLog* log, const CalibrationProgress& progress)
      : stage_(stage), objective_(objective), options_(options), log_(log), progress_(progress) {}

  // The search's budget: the options' less the evaluations kept back for
  // the smoothed estimate.
  // The time budget is rank 0's clock, so that every rank of a distributed
  // run stops at the same evaluation.
  bool exhausted() const {
    if (static_cast<int>(trace_.size()) >= limit()) return true;
    return options_.max_seconds > 0 && parallel::RootDecides(Elapsed() >= options_.max_seconds);
  }
  int remaining() const { return limit() - static_cast<int>(trace_.size()); }
  void Reserve(int evaluations) { reserved_ = evaluations; }

  const Evaluation& Evaluate(const std::vector<double>& unit) {
    const std::vector<double> x = objective_.space().ToPhysical(unit);
    Evaluation e;
    const Evaluation* logged = log_ ? log_->Find(stage_, x) : nullptr;
    if (logged) {
      // Every evaluation has residual_count() residuals; a record with
      // another count (a log edited by hand) would overrun the methods'
      // residual arrays.
      if (logged->residuals.size() != static_cast<std::size_t>(objective_.residual_count()))
        throw InputError(log_->path(), "cannot resume: the logged " + stage_.name() +
                                           " evaluation " + std::to_string(logged->index) +
                                           " has " + std::to_string(logged->residuals.size()) +
                                           " residuals where this "
                                           "calibration has " +
                                           std::to_string(objective_.residual_count()) +
                                           "; start afresh with --force instead of --resume");
      e = *logged;
      e.replayed = true;
      // New work continues the clock of the run this one resumes.
      replayed_offset_ = e.elapsed;
      resumed_ = Clock::now();
    } else {
      const auto t0 = Clock::now();
      const observations::Misfit m = objective_.Evaluate(x);
      e.stage = stage_;
      e.parameters = x;
      e.misfit = m.value;
      e.penalised = m.penalised;
      for (const auto& r : m.residuals) e.residuals.push_back(r.value);
      e.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      ++simulated_;
    }
    e.index = static_cast<int>(trace_.size()) + 1;
    if (!logged) {
      e.elapsed = Elapsed();
      if (log_) log_->Append(e);
    }
    trace_.push_back(e);
    if (e.misfit < best_misfit_) {
      best_misfit_ = e.misfit;
      best_ = x;
      best_residuals_ = e.residuals;
    }
    if (progress_) progress_(trace_.back(), best_misfit_);
    return trace_.back();
  }

  // Wall seconds of this method: those of the run it resumes, then this one's.
  double Elapsed() const {
    return replayed_offset_ + std::chrono::duration<double>(Clock::now() - resumed_).count();
  }

  MethodResult Finish(Termination termination) {
    MethodResult r;
    r.stage = stage_;
    r.termination = std::move(termination);
    r.best = r.lowest = best_;
    r.best_misfit = r.lowest_misfit = best_misfit_;
    r.evaluations = static_cast<int>(trace_.size());
    r.simulated = simulated_;
    r.wall_seconds = trace_.empty() ? 0.0 : trace_.back().elapsed;
    r.trace = std::move(trace_);
    return r;
  }

  const std::vector<double>& best() const { return best_; }
  double best_misfit() const { return best_misfit_; }
  const std::vector<double>& best_residuals() const { return best_residuals_; }
  const std::vector<Evaluation>& trace() const { return trace_; }
  int residual_count() const { return objective_.residual_count(); }

 private:
  int limit() const { return options_.max_evals - reserved_; }

  Stage stage_;
  const ObjectiveFunction& objective_;
  const MethodOptions& options_;
  EvaluationLog* log_;
  const CalibrationProgress& progress_;
  Clock::time_point resumed_ = Clock::now();
  double replayed_offset_ = 0.0;
  std::vector<Evaluation> trace_;
  std::vector<double> best_, best_residuals_;
  double best_misfit_ = kInf;
  int simulated_ = 0;
  int reserved_ = 0;
};


Termination NloptTermination(nlopt::result r) {
  using T = TerminationType;
  switch (r) {
    case nlopt::SUCCESS:
      return {T::kConverged, "success"};
    case nlopt::STOPVAL_REACHED:
      return {T::kConverged, "target misfit reached"};
    case nlopt::FTOL_REACHED:
      return {T::kConverged, "misfit converged (ftol)"};
    case nlopt::XTOL_REACHED:
      return {T::kConverged, "parameters converged (xtol)"};
    case nlopt::MAXEVAL_REACHED:
      return {T::kBudgetUsed, "evaluation budget used"};
    case nlopt::MAXTIME_REACHED:
      return {T::kBudgetUsed, "time budget used"};
    default:
      return {T::kStopped, "stopped (" + std::to_string(static_cast<int>(r)) + ")"};
  }
}

// Runs one NLopt algorithm from `unit` with at most `evals` evaluations.
Termination RunNlopt(nlopt::algorithm algorithm, std::vector<double> unit, int evals,
                     const MethodOptions& options, Evaluator* ev) {
  const unsigned n = static_cast<unsigned>(unit.size());
  nlopt::opt opt(algorithm, n);
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(evals);
  opt.set_xtol_rel(1e-4);
  opt.set_ftol_abs(1e-9);
  if (algorithm == nlopt::G_MLSL_LDS) {
    nlopt::opt local(nlopt::LN_BOBYQA, n);
    local.set_xtol_rel(1e-3);
    local.set_maxeval(std::max(10, evals / 5));
    opt.set_local_optimizer(local);
  }
  if (algorithm == nlopt::LN_BOBYQA || algorithm == nlopt::LN_SBPLX ||
      algorithm == nlopt::LN_NELDERMEAD || algorithm == nlopt::LN_COBYLA) {
    std::vector<double> step(n, options.initial_step);
    // Keep the first simplex inside the box.
    for (unsigned k = 0; k < n; ++k)
      if (unit[k] + step[k] > 1.0) step[k] = -step[k];
    opt.set_initial_step(step);
  }
  nlopt::srand(options.seed);
  // NLopt turns an exception of the objective into its own bare "nlopt
  // failure": the evaluator's errors (a log that cannot be written, a log
  // that does not fit) are kept here and thrown again once NLopt has stopped.
  struct Data {
    Evaluator* ev;
    std::exception_ptr error;
  } data{ev, nullptr};
  opt.set_min_objective(
      [](const std::vector<double>& x, std::vector<double>& grad, void* p) -> double {
        (void)grad;  // derivative-free methods only
        Data* d = static_cast<Data*>(p);
        if (d->ev->exhausted()) throw nlopt::forced_stop();
        try {
          return d->ev->Evaluate(x).misfit;
        } catch (...) {
          d->error = std::current_exception();
          throw nlopt::forced_stop();
        }
      },
      &data);
  double f = 0.0;
  Termination termination;
  try {
    termination = NloptTermination(opt.optimize(unit, f));
  } catch (const nlopt::forced_stop&) {
    termination = ev->exhausted() ? Termination{TerminationType::kBudgetUsed, "budget used"}
                                  : Termination{TerminationType::kStopped, "stopped"};
  } catch (const nlopt::roundoff_limited&) {
    termination = {TerminationType::kStopped, "round-off limited"};
  } catch (const std::exception& e) {
    termination = {TerminationType::kFailed, std::string("nlopt: ") + e.what()};
  }
  if (data.error) std::rethrow_exception(data.error);
  return termination;
}

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
    for (int k = 0; k < size_; ++k) unit[k] = 1.0 / (1.0 + std::exp(-(parameters[0][k] - kCeresOffset)));
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

// Runs Ceres from `unit` within the evaluator's budget; returns why it stopped.
Termination RunCeres(std::vector<double> unit, const MethodOptions& options, Evaluator* ev) {
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

// Uncertainty at the calibrated values (JacobianUncertaintyAt).
Uncertainty CeresUncertainty(const MethodResult& result, const ObjectiveFunction& objective) {
  if (result.best.empty()) return Uncertainty{};
  return JacobianUncertaintyAt(objective, result.best, result.best_misfit);
}

// The evaluations the smoothed estimate keeps back from the search: a
// stencil of 2n + 1 points and the estimate itself.
int SmoothingEvaluations(int n) { return 2 * n + 2; }
// The smallest budget that also leaves the search 2(n + 1) evaluations.
int SmoothingBudget(int n) { return 2 * (n + 1) + SmoothingEvaluations(n); }
// The smallest budget for the first stage alone: 2(n + 1) evaluations of
// the search for its model (a local search's first 2n + 1 are a stencil
// about its start: BOBYQA's initial model) and one for its estimate.
int FirstStageBudget(int n) { return 2 * (n + 1) + 1; }

// How much of the smoothed estimate a budget has room for.
enum class Smoothing { kNone, kFirstStage, kBoth };
Smoothing SmoothingFor(const MethodOptions& options, int n) {
  if (options.estimate != Estimate::kSmoothed) return Smoothing::kNone;
  if (options.max_evals >= SmoothingBudget(n)) return Smoothing::kBoth;
  return options.max_evals >= FirstStageBudget(n) ? Smoothing::kFirstStage : Smoothing::kNone;
}

// Whether an estimate holds: the misfit evaluated there agrees with its
// model (at most 3 standard deviations of the fitted evaluations' scatter
// above the model's misfit plus the noise's share), and is at most one
// standard deviation above the lowest evaluation. The second test is
// deliberately strict: the lowest evaluation is biased low (it is the
// minimum of many noisy values), so a sound estimate often evaluates above
// it, but with few rocks the scatter is as large as the misfit itself, and
// the calibrated values should then not be visibly worse than the lowest.
bool Holds(const SmoothedEstimate& s, double lowest) {
  const double slack = 1e-9 * (1.0 + std::abs(lowest));
  return s.evaluated_misfit <= s.predicted_misfit + s.offset + 3.0 * s.scatter + slack &&
         s.evaluated_misfit <= lowest + s.scatter + slack;
}

std::string Agreement(const SmoothedEstimate& s, double lowest) {
  std::ostringstream out;
  out << "misfit " << s.evaluated_misfit << " evaluated there against " << s.predicted_misfit + s.offset
      << " from the model, lowest " << lowest << ", scatter " << s.scatter;
  return out.str();
}

// The method's result: the smoothed estimate `info`, with `message`, and
// where it is used its values `estimate` and their misfit; the lowest
// evaluation otherwise.
MethodResult Concluded(Evaluator* ev, Termination termination, SmoothedEstimate info,
                       std::string message, const std::vector<double>& estimate, double misfit) {
  info.message = std::move(message);
  MethodResult result = ev->Finish(std::move(termination));
  if (info.used) {
    result.best = estimate;
    result.best_misfit = misfit;
  }
  result.smoothed = std::move(info);
  return result;
}

// The result of a method run. With `smoothing`, in two stages:
//  1. a first estimate fitted to the search's evaluations near the lowest (or
//     the lowest itself when they cannot determine it);
//  2. a stencil around it, its centre and half the smoothing radius either
//     way along each parameter (so the evaluations span every parameter at
//     a step the noise cannot swamp), then the estimate refitted around the
//     first one to the stencil and every evaluation nearby, and evaluated.
// Each stage's estimate is evaluated and kept only where it Holds: where the
// misfit there agrees with its model and is not visibly above the lowest. A
// misfit far from linear residuals (few rocks, a curved valley) fails that;
// the first stage's stencil is then centred on the lowest evaluation, and
// after the second the lowest evaluation stands. A budget with room for the
// first stage only (Smoothing::kFirstStage) ends after it. Without
// `smoothing`, the lowest evaluation.
MethodResult Conclude(Evaluator* ev, Termination termination, Smoothing smoothing,
                      const MethodOptions& options, const ObjectiveFunction& objective) {
  const ParameterSpace& space = objective.space();
  const int n = space.size();
  if (smoothing == Smoothing::kNone || ev->best().empty()) {
    MethodResult result = ev->Finish(std::move(termination));
    if (options.estimate == Estimate::kSmoothed)
      result.smoothed.message = "not used: a budget of " + std::to_string(options.max_evals) +
                                " evaluations is too small for it (it needs " +
                                std::to_string(FirstStageBudget(n)) + ")";
    return result;
  }
  ev->Reserve(0);
  SmoothedEstimate first;
  const std::optional<std::vector<double>> first_unit =
      FitSmoothedEstimate(ev->trace(), space, ev->best(), options.smoothing_radius, &first);
  std::vector<double> centre = first_unit ? *first_unit : space.ToUnit(ev->best());
  const double h = 0.5 * options.smoothing_radius;
  bool first_holds = first_unit.has_value();
  double first_lowest = ev->best_misfit();
  if (first_unit) {
    first.evaluated_misfit = ev->Evaluate(centre).misfit;
    first_holds = Holds(first, first_lowest);
    if (!first_holds) centre = space.ToUnit(ev->best());
  }
  if (smoothing == Smoothing::kFirstStage) {
    std::ostringstream msg;
    if (!first_unit)
      msg << "the lowest evaluation (" << first.message << ")";
    else
      msg << "a " << first.message << " (" << Agreement(first, first_lowest) << ")"
          << (first_holds ? "" : ", which did not hold, so the lowest evaluation");
    msg << "; no stencil: a budget of " << options.max_evals << " evaluations leaves no room for it"
        << " (it needs " << SmoothingBudget(n) << ")";
    first.used = first_holds;
    return Concluded(ev, std::move(termination), first, msg.str(), space.ToPhysical(centre),
                     first.evaluated_misfit);
  }
  const std::vector<double> first_centre = centre;
  for (int k = 0; k < n; ++k)
    for (const double sign : {1.0, -1.0}) {
      std::vector<double> u = centre;
      u[k] = std::clamp(u[k] + sign * h, 0.0, 1.0);
      ev->Evaluate(u);
    }
  SmoothedEstimate info;
  const std::optional<std::vector<double>> unit = FitSmoothedEstimate(
      ev->trace(), space, space.ToPhysical(centre), options.smoothing_radius, &info);
  std::ostringstream msg;
  if (!first_unit)
    msg << "first the lowest evaluation (" << first.message << ")";
  else if (!first_holds)
    msg << "first a " << first.message << ", which did not hold ("
        << Agreement(first, first_lowest) << "), so the lowest evaluation";
  else
    msg << "first a " << first.message << " (" << Agreement(first, first_lowest) << ")";
  msg << "; then a stencil of " << 2 * n + 1 << " evaluations (" << h
      << " either way along each parameter) and a ";
  std::vector<double> estimate;
  double misfit = 0.0;
  if (unit) {
    estimate = space.ToPhysical(*unit);
    const double lowest = ev->best_misfit();
    info.evaluated_misfit = misfit = ev->Evaluate(*unit).misfit;
    info.used = Holds(info, lowest);
    msg << info.message << " (" << Agreement(info, lowest) << ")";
  } else {
    msg << "model that could not be fitted: " << info.message;
  }
  // A second stage that did not hold leaves the first standing, if it still
  // holds against the lowest evaluation, which the stencil may have lowered.
  const bool first_stands = first_holds && Holds(first, ev->best_misfit());
  if (!info.used) {
    msg << (unit ? "; its minimiser did not hold, so the calibrated values are "
                 : "; the calibrated values are ")
        << (first_stands  ? "the first estimate's"
            : first_holds ? "the lowest evaluation (the stencil went lower than the first estimate "
                            "by more than its scatter)"
                          : "the lowest evaluation");
  }
  if (!info.used && first_stands) {
    info = first;
    info.used = true;
    estimate = space.ToPhysical(first_centre);
    misfit = first.evaluated_misfit;
  }
  return Concluded(ev, std::move(termination), info, msg.str(), estimate, misfit);
}

}  // namespace

Uncertainty JacobianUncertaintyAt(const ObjectiveFunction& objective,
                                  const std::vector<double>& at, double misfit) {
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
    return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  };
  info->offset = median(delta);
  for (double& v : delta) v = std::abs(v - info->offset);
  info->scatter = 1.4826 * median(delta);
  std::ostringstream msg;
  msg << "linear model of the residuals fitted to the " << near.size()
      << " evaluations within " << radius << " (unit box)";
  if (cod.rank() < n) msg << "; the model's Jacobian has rank " << cod.rank() << " of " << n;
  info->message = msg.str();
  return unit;
}

bool MethodOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (max_evals < 2) {
    s << "max_evals = " << max_evals << ": must be >= 2";
  } else if (!(max_seconds >= 0)) {
    s << "max_seconds = " << max_seconds << ": must be >= 0 (0: no limit)";
  } else if (!(polish_fraction >= 0 && polish_fraction <= 0.9)) {
    s << "polish_fraction = " << polish_fraction << ": must be in [0, 0.9]";
  } else if (!(initial_step > 0 && initial_step <= 1)) {
    s << "initial_step = " << initial_step << ": must be in (0, 1]";
  } else if (!(ceres_step > 0 && ceres_step <= 2)) {
    s << "ceres_step = " << ceres_step << ": must be in (0, 2]";
  } else if (!*CeresLossToString(ceres_loss)) {
    s << "ceres_loss = " << static_cast<int>(ceres_loss) << ": must be one of " << CeresLossNames();
  } else if (!*EstimateToString(estimate)) {
    s << "estimate = " << static_cast<int>(estimate) << ": must be one of " << EstimateNames();
  } else if (!(smoothing_radius > 0 && smoothing_radius <= 1)) {
    s << "smoothing_radius = " << smoothing_radius << ": must be in (0, 1]";
  } else {
    return true;
  }
  *error = s.str();
  return false;
}

namespace {

constexpr core::Named<CeresLoss> kCeresLosses[] = {
    {CeresLoss::kNone, "none"}, {CeresLoss::kHuber, "huber"}, {CeresLoss::kCauchy, "cauchy"}};
constexpr core::Named<Estimate> kEstimates[] = {{Estimate::kLowest, "lowest"},
                                                {Estimate::kSmoothed, "smoothed"}};

}  // namespace

const char* CeresLossToString(CeresLoss loss) { return core::NameOf(kCeresLosses, loss); }
bool StringToCeresLoss(const std::string& name, CeresLoss* loss) {
  return core::IdOf(kCeresLosses, name, loss);
}
std::string CeresLossNames() { return core::NameList(kCeresLosses); }
const char* EstimateToString(Estimate estimate) { return core::NameOf(kEstimates, estimate); }
bool StringToEstimate(const std::string& name, Estimate* estimate) {
  return core::IdOf(kEstimates, name, estimate);
}
std::string EstimateNames() { return core::NameList(kEstimates); }

const char* MethodToString(Method method) { return core::NameOf(kMethods, method); }
bool StringToMethod(const std::string& name, Method* method) {
  return core::IdOf(kMethods, name, method);
}
std::string MethodNames() { return core::NameList(kMethods); }
const std::vector<Method>& AllMethods() {
  static const std::vector<Method> methods = core::IdList(kMethods);
  return methods;
}

namespace {
constexpr const char* kPosteriorStage = "posterior";
}  // namespace

Stage Stage::Posterior() {
  Stage s;
  s.posterior = true;
  return s;
}

std::string Stage::name() const {
  if (posterior) return kPosteriorStage;
  // No comma: the name is a field of trace.csv and comparison.csv.
  return std::string(MethodToString(method)) +
         (rocks > 0 ? " (" + std::to_string(rocks) + " rocks)" : "");
}

bool Stage::FromName(const std::string& name, Stage* stage) {
  if (name == kPosteriorStage) {
    *stage = Posterior();
    return true;
  }
  Stage s;
  const std::size_t space = name.find(' ');
  if (!StringToMethod(name.substr(0, space), &s.method)) return false;
  if (space != std::string::npos) {
    // A refining stage's " (N rocks)": N read, and the name taken only when
    // name() writes it back the same.
    const long rocks = std::strtol(name.c_str() + std::min(name.size(), space + 2), nullptr, 10);
    if (rocks < 1 || rocks > std::numeric_limits<int>::max()) return false;
    s.rocks = static_cast<int>(rocks);
    if (s.name() != name) return false;
  }
  *stage = s;
  return true;
}

bool Stage::operator==(const Stage& o) const {
  return posterior == o.posterior && (posterior || (method == o.method && rocks == o.rocks));
}

bool Stage::operator<(const Stage& o) const {
  if (posterior != o.posterior) return posterior < o.posterior;
  if (posterior) return false;
  return std::tie(method, rocks) < std::tie(o.method, o.rocks);
}

const char* TerminationName(TerminationType type) {
  switch (type) {
    case TerminationType::kConverged:
      return "converged";
    case TerminationType::kBudgetUsed:
      return "budget used";
    case TerminationType::kStopped:
      return "stopped";
    case TerminationType::kFailed:
      return "failed";
  }
  return "?";
}

std::vector<std::string> Fingerprint::Differences(const Fingerprint& logged) const {
  std::vector<std::string> out;
  auto find = [](const Fingerprint& f, const std::string& what) -> const std::string* {
    for (const auto& [name, value] : f.parts)
      if (name == what) return &value;
    return nullptr;
  };
  for (const auto& [name, value] : parts) {
    const std::string* old = find(logged, name);
    if (!old || *old != value) out.push_back(name);
  }
  for (const auto& [name, value] : logged.parts)
    if (!find(*this, name)) out.push_back(name);
  return out;
}

std::string HashFile(const std::string& path) {
  sites::CheckInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot read the file to fingerprint it");
  std::uint64_t h = 14695981039346656037ull;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize k = 0; k < in.gcount(); ++k) {
      h ^= static_cast<unsigned char>(buffer[k]);
      h *= 1099511628211ull;
    }
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

namespace {

// A resumed log's header: the fingerprint of the inputs it was made with,
// which must be `fingerprint` but for the parts named in `unknown`. Returns
// the logged fingerprint.
Fingerprint CheckLogHeader(const std::string& line, const std::string& where,
                           const Fingerprint& fingerprint,
                           const std::vector<std::string>& unknown) {
  nlohmann::json h = nlohmann::json::parse(line, nullptr, false);
  if (h.is_discarded() || !h.is_object() || !h.contains("fingerprint") ||
      !h["fingerprint"].is_object())
    throw InputError(where,
                     "no fingerprint header (a log written by an older rockcal, or not an "
                     "evaluation log): cannot tell whether its evaluations still hold; start "
                     "afresh with --force instead of --resume");
  Fingerprint logged;
  for (const auto& [name, value] : h["fingerprint"].items())
    logged.Add(name, value.is_string() ? value.get<std::string>() : value.dump());
  std::vector<std::string> changed = fingerprint.Differences(logged);
  changed.erase(std::remove_if(changed.begin(), changed.end(),
                               [&](const std::string& c) {
                                 return std::find(unknown.begin(), unknown.end(), c) !=
                                        unknown.end();
                               }),
                changed.end());
  if (!changed.empty()) {
    std::string list;
    for (const std::string& c : changed) list += (list.empty() ? "" : ", ") + c;
    throw InputError(where, "cannot resume: what determines the evaluations changed since "
                            "this log was written: " + list +
                            "; restore it, or start afresh with --force instead of --resume");
  }
  return logged;
}

// One record of a resumed log, of the calibration at `seed`, `rocks` and
// parameter `names`. Throws nlohmann::json's exceptions on a line that is
// not a record.
Evaluation ReadLogRecord(const std::string& line, const std::string& where, std::uint64_t seed,
                         int rocks, const std::vector<std::string>& names) {
  const nlohmann::json j = nlohmann::json::parse(line);
  if (WholeField<std::uint64_t>(j, "seed", where) != seed ||
      WholeField<int>(j, "rocks", where) != rocks ||
      j.at("names").get<std::vector<std::string>>() != names)
    throw InputError(where, "record of another calibration (different parameters, --seed or "
                            "--rocks); start afresh with --force instead of --resume");
  Evaluation e;
  const std::string method = j.at("method").get<std::string>();
  if (!Stage::FromName(method, &e.stage))
    throw InputError(where, "not an evaluation record: method '" + method + "' (expected one of " +
                                MethodNames() + ", or posterior)");
  e.index = WholeField<int>(j, "evaluation", where);
  e.parameters = j.at("parameters").get<std::vector<double>>();
  e.misfit = j.at("misfit").get<double>();
  e.residuals = j.at("residuals").get<std::vector<double>>();
  e.penalised = j.at("penalised").get<bool>();
  e.seconds = j.at("seconds").get<double>();
  e.elapsed = j.at("elapsed").get<double>();
  return e;
}

// The records of the log at `path`, whose fingerprint must be
// `fingerprint` (but for the rocks when `rocks` is unknown), of the
// calibration at `seed`, `rocks` and parameter `names`. Reads only.
std::vector<Evaluation> ReadLog(const std::string& path, const Fingerprint& fingerprint,
                                std::uint64_t seed, std::optional<int> rocks,
                                const std::vector<std::string>& names) {
  sites::CheckInputFile(path);
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot resume: no evaluation log here");
  std::vector<Evaluation> records;
  std::string line;
  int number = 0;
  bool header = false;
  // Per method, the last evaluation logged and its line: a run appends its
  // evaluations in order, and a resumed run only after the last, so an
  // evaluation logged again or out of order is the line of another run
  // (two runs writing the same folder at once).
  std::map<Stage, std::pair<int, int>> last;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(number);
    sites::CheckJsonDepth(line, where);
    if (!header) {
      const Fingerprint logged =
          CheckLogHeader(line, where, fingerprint,
                         rocks ? std::vector<std::string>{} : std::vector<std::string>{"rocks"});
      if (!rocks) {
        // The records must hold the rocks the header names.
        rocks = -1;
        for (const auto& [name, value] : logged.parts)
          if (name == "rocks") {
            char* end = nullptr;
            const long n = std::strtol(value.c_str(), &end, 10);
            if (end != value.c_str() && *end == '\0' && n > 0 &&
                n <= std::numeric_limits<int>::max())
              rocks = static_cast<int>(n);
          }
        if (*rocks < 0)
          throw InputError(where,
                           "cannot resume: the header names no rock count; start afresh "
                           "with --force instead of --resume");
      }
      header = true;
      continue;
    }
    try {
      Evaluation e = ReadLogRecord(line, where, seed, *rocks, names);
      auto [before, inserted] = last.try_emplace(e.stage, e.index, number);
      if (!inserted && e.index <= before->second.first)
        throw InputError(where, e.stage.name() + " evaluation " + std::to_string(e.index) +
                                    " after its evaluation " +
                                    std::to_string(before->second.first) + " (line " +
                                    std::to_string(before->second.second) +
                                    "): the log holds the lines of two runs that wrote this "
                                    "folder at once, so it cannot be resumed; start afresh "
                                    "with --force instead of --resume");
      before->second = {e.index, number};
      records.push_back(std::move(e));
    } catch (const nlohmann::json::exception&) {
      // A line cut short by a killed run is the only damage expected: the
      // last line. Anything else is not ours.
      if (in.peek() == EOF) break;
      throw InputError(where, "not an evaluation record (expected one JSON object per line)");
    }
  }
  return records;
}

}  // namespace

EvaluationLog::EvaluationLog(std::string path, bool resume, const ParameterSpace& space,
                             std::uint64_t seed, int rocks, Fingerprint fingerprint,
                             const std::function<void()>& accepted)
    : path_(std::move(path)), seed_(seed), rocks_(rocks), fingerprint_(std::move(fingerprint)) {
  for (const auto& p : space.parameters()) names_.push_back(p.label());
  if (resume) ReadBack();
  if (accepted) accepted();
  Rewrite();
}

// The records of the log at path_, whose fingerprint must be this run's.
void EvaluationLog::ReadBack() { records_ = ReadLog(path_, fingerprint_, seed_, rocks_, names_); }

void EvaluationLog::Check(const std::string& path, const ParameterSpace& space, std::uint64_t seed,
                          std::optional<int> rocks, const Fingerprint& fingerprint) {
  std::vector<std::string> names;
  for (const auto& p : space.parameters()) names.push_back(p.label());
  ReadLog(path, fingerprint, seed, rocks, names);
}

// Rewrites the log with the good records only (drops a torn last line),
// through a temporary file renamed into place: a run killed meanwhile
// leaves the old log whole.
void EvaluationLog::Rewrite() const {
  const std::string temp = path_ + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::trunc);
    if (!out)
      throw std::runtime_error("cannot write the evaluation log " + path_ + " (its temporary " +
                               temp + "): " + std::strerror(errno));
    nlohmann::json parts = nlohmann::json::object();
    for (const auto& [name, value] : fingerprint_.parts) parts[name] = value;
    out << nlohmann::json{{"fingerprint", parts}}.dump() << '\n';
    for (const Evaluation& e : records_) {
      nlohmann::json j = ToJson(e);
      j["seed"] = seed_;
      j["rocks"] = rocks_;
      j["names"] = names_;
      out << j.dump() << '\n';
    }
    out.flush();
    if (!out) {
      const int error = errno;
      std::remove(temp.c_str());
      throw std::runtime_error("cannot write the evaluation log " + path_ + " (its temporary " +
                               temp + "): " + std::strerror(error));
    }
  }
  if (std::rename(temp.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    std::remove(temp.c_str());
    throw std::runtime_error("cannot write the evaluation log " + path_ +
                             " (renaming its temporary " + temp + "): " + std::strerror(error));
  }
}

const Evaluation* EvaluationLog::Find(const Stage& stage,
                                      const std::vector<double>& physical) const {
  for (const Evaluation& e : records_)
    if (e.stage == stage && e.parameters == physical) return &e;
  return nullptr;
}

void EvaluationLog::Append(const Evaluation& evaluation) {
  nlohmann::json j = ToJson(evaluation);
  j["seed"] = seed_;
  j["rocks"] = rocks_;
  j["names"] = names_;
  // The first write that fails (a full disk, a file size limit) stops the
  // run here, the records before it kept whole: the stream is flushed and
  // closed, and either failing is the write failing (docs/reference/errors.md).
  std::ofstream out(path_, std::ios::app);
  errno = 0;
  if (out) out << j.dump() << '\n';
  if (out) out.flush();
  if (out) out.close();
  if (!out)
    throw std::runtime_error("cannot write the evaluation log " + path_ + ": " +
                             std::strerror(errno != 0 ? errno : EIO));
  records_.push_back(evaluation);
}

MethodResult RunMethod(Method method, const ObjectiveFunction& objective,
                       const std::vector<double>& start, const MethodOptions& options,
                       EvaluationLog* log, const CalibrationProgress& progress) {
  const MethodInfo* info = core::FindEntry(kMethods, method);
  if (!info)
    throw InputError("calibration options", "method " + std::to_string(static_cast<int>(method)) +
                                                ": must be one of " + MethodNames());
  std::string error;
  if (!options.IsValid(&error)) throw InputError("calibration options", error);
  Evaluator ev(Stage{method}, objective, options, log, progress);
  // The smoothed estimate keeps evaluations back from the search; a budget
  // too small for it goes to the search whole.
  const int n = objective.space().size();
  const Smoothing smoothed = SmoothingFor(options, n);
  if (smoothed == Smoothing::kBoth) ev.Reserve(SmoothingEvaluations(n));
  if (smoothed == Smoothing::kFirstStage) ev.Reserve(1);
  const std::vector<double> unit = objective.space().ToUnit(start);
  if (info->ceres) {
    const Termination termination = RunCeres(unit, options, &ev);
    MethodResult result = Conclude(&ev, termination, smoothed, options, objective);
    result.uncertainty = CeresUncertainty(result, objective);
    return result;
  }
  Termination termination;
  if (!info->global) {
    // A Monte Carlo misfit is rugged: a local method that converged may sit
    // in a dip of the noise. Restart it from its best point with a fresh
    // step while budget remains; a restart that finds nothing better halves
    // the step, down to a sixteenth of the first.
    termination = RunNlopt(info->algorithm, unit, ev.remaining(), options, &ev);
    int restarts = 0;
    MethodOptions restart = options;
    while (!ev.exhausted() && ev.remaining() >= n + 2 &&
           restart.initial_step >= options.initial_step / 16) {
      const double before = ev.best_misfit();
      RunNlopt(info->algorithm, objective.space().ToUnit(ev.best()), ev.remaining(), restart, &ev);
      ++restarts;
      if (!(ev.best_misfit() < before * (1 - 1e-6))) restart.initial_step /= 2;
    }
    if (restarts > 0)
      termination.message += "; " + std::to_string(restarts) + " restart(s) from the best point";
    if (ev.exhausted() && termination.type != TerminationType::kBudgetUsed) {
      termination.message += "; budget used";
      termination.type = TerminationType::kBudgetUsed;
    }
  } else {
    // Global search, then a local polish from its best point.
    const int global = std::max(2, static_cast<int>(ev.remaining() * (1 - options.polish_fraction)));
    termination = RunNlopt(info->algorithm, unit, global, options, &ev);
    if (!ev.exhausted() && ev.remaining() >= 2 && !ev.best().empty()) {
      const Termination polish = RunNlopt(nlopt::LN_BOBYQA, objective.space().ToUnit(ev.best()),
                                          ev.remaining(), options, &ev);
      termination.message += "; polished with nlopt:bobyqa: " + polish.message;
      termination.type = polish.type;
    }
  }
  MethodResult result = Conclude(&ev, termination, smoothed, options, objective);
  // NLopt gives no curvature: take it from the search's own evaluations.
  result.uncertainty = LocalModelUncertainty(result.trace, objective.space(), result.best,
                                             result.best_misfit, options.smoothing_radius);
  return result;
}

double TimeToReach(const MethodResult& result, double target, double fraction) {
  double best = kInf;
  for (const Evaluation& e : result.trace) {
    best = std::min(best, e.misfit);
    if (best <= target * (1 + fraction) + 1e-300) return e.elapsed;
  }
  return -1.0;
}

}  // namespace rockcal::calibrate
