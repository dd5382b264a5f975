// The search machinery shared by every method (private to calibrate/src):
// the Evaluator (budget, log replay, trace, best), the conclusion of a run
// (the smoothed estimate's stages) and the interface a search method
// implements (NLopt's algorithms in nlopt_search.cc, Ceres in
// ceres_search.cc). calibration.cc's method table names one SearchMethod
// per Method and RunMethod drives them alike.
#ifndef ROCKCAL_CALIBRATE_SRC_SEARCH_H_
#define ROCKCAL_CALIBRATE_SRC_SEARCH_H_

#include <chrono>
#include <limits>
#include <nlopt.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/core/error.h"
#include "rockcal/parallel/parallel.h"

namespace rockcal::calibrate {

// Everything a method asks of the objective: budget, log replay, trace, best.
using Clock = std::chrono::steady_clock;

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
      e = EvaluationOf(stage_, x, objective_.Evaluate(x));
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
  double best_misfit_ = std::numeric_limits<double>::infinity();
  int simulated_ = 0;
  int reserved_ = 0;
};

// How much of the smoothed estimate a budget has room for.
enum class Smoothing { kNone, kFirstStage, kBoth };
// The evaluations the smoothed estimate keeps back from the search: a
// stencil of 2n + 1 points and the estimate itself.
int SmoothingEvaluations(int n);
// Which stages of the smoothed estimate `options` have room for, n parameters.
Smoothing SmoothingFor(const MethodOptions& options, int n);

// The result of a method run, concluded from the evaluator's evaluations
// with `smoothing` (search.cc says how).
MethodResult Conclude(Evaluator* ev, Termination termination, Smoothing smoothing,
                      const MethodOptions& options, const ObjectiveFunction& objective);

// One way of searching the unit box: how it runs within an Evaluator's budget,
// and the uncertainty it reports at the concluded result.
class SearchMethod {
 public:
  virtual ~SearchMethod() = default;
  // Searches from `unit` until it stops or the evaluator's budget is used.
  virtual Termination Search(const std::vector<double>& unit, const MethodOptions& options,
                             const ParameterSpace& space, Evaluator* ev) const = 0;
  // The uncertainty of `result`, the concluded run.
  virtual Uncertainty UncertaintyOf(const MethodResult& result, const ObjectiveFunction& objective,
                                    const MethodOptions& options) const = 0;
};

// An NLopt algorithm: a local one restarted from its best point while budget
// remains, a global one (`global`) polished by BOBYQA; the uncertainty from
// its own evaluations (LocalModelUncertainty), NLopt giving no curvature.
class NloptSearch final : public SearchMethod {
 public:
  NloptSearch(nlopt::algorithm algorithm, bool global) : algorithm_(algorithm), global_(global) {}
  Termination Search(const std::vector<double>& unit, const MethodOptions& options,
                     const ParameterSpace& space, Evaluator* ev) const override;
  Uncertainty UncertaintyOf(const MethodResult& result, const ObjectiveFunction& objective,
                            const MethodOptions& options) const override;

 private:
  nlopt::algorithm algorithm_;
  bool global_;
};

// Ceres' least squares on the residuals; the uncertainty from the Jacobian
// at its calibrated values (JacobianUncertaintyAt).
class CeresSearch final : public SearchMethod {
 public:
  Termination Search(const std::vector<double>& unit, const MethodOptions& options,
                     const ParameterSpace& space, Evaluator* ev) const override;
  Uncertainty UncertaintyOf(const MethodResult& result, const ObjectiveFunction& objective,
                            const MethodOptions& options) const override;
};

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_SRC_SEARCH_H_
