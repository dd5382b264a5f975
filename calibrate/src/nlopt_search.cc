// NLopt's algorithms as search methods (search.h).
#include <algorithm>
#include <exception>
#include <string>
#include <vector>

#include "search.h"

namespace rockcal::calibrate {
namespace {

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

}  // namespace

Termination NloptSearch::Search(const std::vector<double>& unit, const MethodOptions& options,
                                const ParameterSpace& space, Evaluator* ev) const {
  const int n = space.size();
  Termination termination;
  if (!global_) {
    // A Monte Carlo misfit is rugged: a local method that converged may sit
    // in a dip of the noise. Restart it from its best point with a fresh
    // step while budget remains; a restart that finds nothing better halves
    // the step, down to a sixteenth of the first.
    termination = RunNlopt(algorithm_, unit, ev->remaining(), options, ev);
    int restarts = 0;
    MethodOptions restart = options;
    while (!ev->exhausted() && ev->remaining() >= n + 2 &&
           restart.initial_step >= options.initial_step / 16) {
      const double before = ev->best_misfit();
      RunNlopt(algorithm_, space.ToUnit(ev->best()), ev->remaining(), restart, ev);
      ++restarts;
      if (!(ev->best_misfit() < before * (1 - 1e-6))) restart.initial_step /= 2;
    }
    if (restarts > 0)
      termination.message += "; " + std::to_string(restarts) + " restart(s) from the best point";
    if (ev->exhausted() && termination.type != TerminationType::kBudgetUsed) {
      termination.message += "; budget used";
      termination.type = TerminationType::kBudgetUsed;
    }
    return termination;
  }
  // Global search, then a local polish from its best point.
  const int global = std::max(2, static_cast<int>(ev->remaining() * (1 - options.polish_fraction)));
  termination = RunNlopt(algorithm_, unit, global, options, ev);
  if (!ev->exhausted() && ev->remaining() >= 2 && !ev->best().empty()) {
    const Termination polish =
        RunNlopt(nlopt::LN_BOBYQA, space.ToUnit(ev->best()), ev->remaining(), options, ev);
    termination.message += "; polished with nlopt:bobyqa: " + polish.message;
    termination.type = polish.type;
  }
  return termination;
}

Uncertainty NloptSearch::UncertaintyOf(const MethodResult& result,
                                       const ObjectiveFunction& objective,
                                       const MethodOptions& options) const {
  return LocalModelUncertainty(result.trace, objective.space(), result.best, result.best_misfit,
                               options.smoothing_radius);
}

}  // namespace rockcal::calibrate
