// Calibration methods (NLopt and Ceres) over an ObjectiveFunction, with an evaluation
// log that a stopped calibration resumes from without repeating work.
#ifndef ROCKCAL_CALIBRATE_CALIBRATION_H_
#define ROCKCAL_CALIBRATE_CALIBRATION_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rockcal/calibrate/evaluation.h"
#include "rockcal/calibrate/evaluation_log.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/uncertainty.h"

namespace rockcal::calibrate {

// The robust loss Ceres puts on the residuals (scale 1: they are in sigmas).
enum class CeresLoss { kNone, kHuber, kCauchy };
// How the calibrated values are taken from the evaluations
// (MethodOptions::estimate).
enum class Estimate { kLowest, kSmoothed };
// Their names ("none", "huber", "cauchy"; "lowest", "smoothed"), from one
// table each for parsing and printing. StringTo* returns false (and leaves
// *value alone) for a name not in the table; *Names lists the table, comma
// separated, for messages.
const char* CeresLossToString(CeresLoss loss);
bool StringToCeresLoss(const std::string& name, CeresLoss* loss);
std::string CeresLossNames();
const char* EstimateToString(Estimate estimate);
bool StringToEstimate(const std::string& name, Estimate* estimate);
std::string EstimateNames();

// Options of one method run. Defaults in brackets.
struct MethodOptions {
  static constexpr int kMinEvals = 2;  // the smallest max_evals
  int max_evals = 100;                 // evaluations (replayed ones count) [100], >= kMinEvals
  double max_seconds = 0.0;            // wall seconds for the method, 0 = no limit [0]
  std::uint64_t seed = 1;              // random seed of the stochastic global methods
  double polish_fraction = 0.3;  // share of a global method's budget for the local polish, [0, 0.9]
  double initial_step = 0.2;     // first step of the local methods, in the unit box, (0, 1]
  // Ceres: finite-difference step in the unbounded parameters t (unit-box
  // value u = 1 / (1 + exp(-t))). 0.2 moves a mid-range parameter by 5 % of
  // its range: large enough to see through the jumps of a Monte Carlo
  // objective, small enough to follow its trend. (0, 2]
  double ceres_step = 0.2;
  CeresLoss ceres_loss = CeresLoss::kNone;  // [none]
  // How the calibrated values are taken from the evaluations:
  //  - kSmoothed: the Gauss-Newton minimiser of a linear model of the
  //    residuals fitted by least squares to the evaluations near the best,
  //    in two stages (FitSmoothedEstimate): a first estimate from the
  //    search's evaluations near the lowest misfit; then a stencil of 2n + 1
  //    evaluations around it (its centre, and smoothing_radius / 2 either way
  //    along each parameter) and the estimate refitted to them and the
  //    evaluations nearby, then evaluated; each stage is kept only where the
  //    misfit evaluated there agrees with its model and is not visibly worse than
  //    the lowest (see SmoothedEstimate). The search keeps 2n + 2
  //    evaluations of max_evals back for this; of a budget below 4(n + 1),
  //    one, for the first stage alone, and of one below 2(n + 1) + 1, none:
  //    the lowest is taken. A time limit covers the search only. A Monte
  //    Carlo misfit is rugged: its lowest evaluation sits in a dip of the
  //    noise (the winner's curse), which the fit averages out;
  //  - kLowest (the default): the evaluation with the lowest misfit.
  // The smoothed estimate pays where each evaluation has enough rocks for
  // the misfit's trend to stand out of its noise (the twin experiment, 1000
  // rocks: every parameter within 7 % of its range where the lowest was up
  // to 20 % off); with a few dozen rocks its model fits noise.
  Estimate estimate = Estimate::kLowest;
  // Half-width, in the unit box, of the neighbourhood whose evaluations the
  // smoothed estimate fits (widened until it holds 2(n + 1) of them); also
  // the largest move of each stage, and twice the stencil's step. (0, 1]
  double smoothing_radius = 0.2;

  bool IsValid(std::string* error) const;
};

// Why a method stopped.
enum class TerminationType {
  kConverged,   // the optimiser's own tolerance was met
  kBudgetUsed,  // the evaluation or time budget of MethodOptions ran out
  kStopped,     // the optimiser gave up (round-off, a stop it reports)
  kFailed,      // the optimiser threw an error
};
// "converged", "budget used", "stopped", "failed".
const char* TerminationName(TerminationType type);

struct Termination {
  TerminationType type = TerminationType::kConverged;
  // The detail as the optimiser gave it, with what rockcal added (restarts,
  // the polish), e.g. "parameters converged (xtol); 2 restart(s) from the best point".
  std::string message;
};

struct MethodResult {
  Stage stage;               // the method, and a refining stage's rocks
  Termination termination;   // why it stopped
  std::vector<double> best;  // the calibrated values (physical)
  double best_misfit = 0.0;  // the misfit evaluated at `best`
  // The evaluation with the lowest misfit (equal to best/best_misfit unless
  // the smoothed estimate moved away from it).
  std::vector<double> lowest;
  double lowest_misfit = 0.0;
  SmoothedEstimate smoothed;
  int evaluations = 0;  // in all
  int simulated = 0;    // that ran a simulation (the rest were replayed)
  double wall_seconds = 0.0;
  std::vector<Evaluation> trace;  // in order
  Uncertainty uncertainty;
};

// Called after every evaluation with (method, evaluation, best misfit so far).
using CalibrationProgress = std::function<void(const Evaluation&, double best)>;

// Runs `method` from `start` (physical values) within the options' budget.
// Throws InputError for invalid options.
MethodResult RunMethod(Method method, const ObjectiveFunction& objective,
                       const std::vector<double>& start, const MethodOptions& options,
                       EvaluationLog* log, const CalibrationProgress& progress = nullptr);

// Wall seconds at which a method's best misfit first came within `fraction`
// of `target` (best_misfit <= target * (1 + fraction)); negative if never.
double TimeToReach(const MethodResult& result, double target, double fraction = 0.1);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_CALIBRATION_H_
