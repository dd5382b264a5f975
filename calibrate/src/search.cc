// The conclusion of a method run, common to every method (search.h).
#include "search.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace rockcal::calibrate {
namespace {}  // namespace

int SmoothingEvaluations(int n) { return 2 * n + 2; }

namespace {
// The smallest budget that also leaves the search 2(n + 1) evaluations.
int SmoothingBudget(int n) { return 2 * (n + 1) + SmoothingEvaluations(n); }
// The smallest budget for the first stage alone: 2(n + 1) evaluations of
// the search for its model (a local search's first 2n + 1 are a stencil
// about its start: BOBYQA's initial model) and one for its estimate.
int FirstStageBudget(int n) { return 2 * (n + 1) + 1; }

}  // namespace

Smoothing SmoothingFor(const MethodOptions& options, int n) {
  if (options.estimate != Estimate::kSmoothed) return Smoothing::kNone;
  if (options.max_evals >= SmoothingBudget(n)) return Smoothing::kBoth;
  return options.max_evals >= FirstStageBudget(n) ? Smoothing::kFirstStage : Smoothing::kNone;
}

namespace {

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
  out << "misfit " << s.evaluated_misfit << " evaluated there against "
      << s.predicted_misfit + s.offset << " from the model, lowest " << lowest << ", scatter "
      << s.scatter;
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

}  // namespace

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
    msg << "first a " << first.message << ", which did not hold (" << Agreement(first, first_lowest)
        << "), so the lowest evaluation";
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

}  // namespace rockcal::calibrate
