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

#include "rockcal/calibrate/objective.h"

namespace rockcal::calibrate {

// The calibration methods: NLopt's local algorithms (BOBYQA, Subplex,
// Nelder-Mead, COBYLA), its global ones (DIRECT-L, CRS2, ISRES, MLSL; each
// polished by BOBYQA), and Ceres' least squares on the residuals.
enum class Method {
  kBobyqa,
  kSbplx,
  kNelderMead,
  kCobyla,
  kDirectL,
  kCrs2,
  kIsres,
  kMlsl,
  kCeres,
};
// Their names ("nlopt:bobyqa", "nlopt:sbplx", "nlopt:neldermead",
// "nlopt:cobyla", "nlopt:direct_l", "nlopt:crs2", "nlopt:isres",
// "nlopt:mlsl", "ceres") from one table for parsing and printing, as the
// loss's. StringToMethod returns false (and leaves *method alone) for a name
// not in the table; MethodNames lists the table, comma separated, for
// messages; AllMethods lists the methods in its order.
const char* MethodToString(Method method);
bool StringToMethod(const std::string& name, Method* method);
std::string MethodNames();
const std::vector<Method>& AllMethods();

// Which search made an evaluation or a result: a method at the run's rocks,
// the same method again in a refining stage at more rocks, or the
// posterior's sampling. Its name is what the evaluation log, trace.csv and
// the reports show: "nlopt:bobyqa", "nlopt:bobyqa (160 rocks)", "posterior".
struct Stage {
  Method method = Method::kBobyqa;
  int rocks = 0;           // a refining stage's rocks per evaluation; 0: the first stage
  bool posterior = false;  // the posterior's evaluations (method and rocks unused)

  static Stage Posterior();
  std::string name() const;
  // The stage of a name() (the log's "method"); false for another name.
  static bool FromName(const std::string& name, Stage* stage);
  bool operator==(const Stage& other) const;
  bool operator!=(const Stage& other) const { return !(*this == other); }
  bool operator<(const Stage& other) const;  // any strict order, for maps
};

// One evaluation of the objective.
struct Evaluation {
  Stage stage;                     // logged as its name ("method")
  int index = 0;                   // 1-based within the method
  std::vector<double> parameters;  // physical values
  double misfit = 0.0;
  std::vector<double> residuals;
  bool penalised = false;
  double seconds = 0.0;  // wall seconds of its simulation
  double elapsed = 0.0;  // wall seconds since the method started, when it finished
  bool replayed = false;  // taken from the log of an earlier run
};

// What determines a calibration's evaluations, as named parts: the hash of a
// file's bytes, or a value written out ("seed" = "1"). Stored as the first
// line of the evaluation log, so that a resume can name what changed.
struct Fingerprint {
  std::vector<std::pair<std::string, std::string>> parts;  // (what, hash or value), in order

  void Add(std::string what, std::string value) {
    parts.emplace_back(std::move(what), std::move(value));
  }
  // The names of the parts that differ from `logged`'s (changed, added or
  // missing), in this one's order and then `logged`'s.
  std::vector<std::string> Differences(const Fingerprint& logged) const;
};

// FNV-1a (64 bits) of the bytes of `path`, in hex. Throws InputError when the
// file cannot be read.
std::string HashFile(const std::string& path);

// DIR/evaluations.jsonl: a header line {"fingerprint": {...}}, then one JSON
// object per evaluation, appended (and flushed) as each finishes.
class EvaluationLog final {
 public:
  // Starts a new log at `path` (truncating it), or with `resume` reads the
  // records already there first. A log whose header's fingerprint differs
  // from `fingerprint` (the InputError names the parts), a log without a
  // header (an older rockcal's), or a record that does not belong to this
  // calibration (other parameters, seed or rock count) is an InputError.
  // `accepted`, if given, is called once the log is found to be this run's
  // and before the log is first written (rewritten without a torn last line):
  // a resumed output folder ceases to say it is complete before it changes.
  EvaluationLog(std::string path, bool resume, const ParameterSpace& space, std::uint64_t seed,
                int rocks, Fingerprint fingerprint = {},
                const std::function<void()>& accepted = {});
  // Reads the log at `path` as a resume would and throws the InputError it
  // would throw, changing nothing: so that a refused --resume is refused
  // before the folder is touched or anything simulated. `rocks` unknown
  // (nullopt: the rocks a noise check may raise) leaves the fingerprint's
  // "rocks" uncompared, and the records must hold the header's.
  static void Check(const std::string& path, const ParameterSpace& space, std::uint64_t seed,
                    std::optional<int> rocks, const Fingerprint& fingerprint);
  // The logged evaluation of `stage` at exactly `physical`, if any.
  const Evaluation* Find(const Stage& stage, const std::vector<double>& physical) const;
  void Append(const Evaluation& evaluation);
  int size() const { return static_cast<int>(records_.size()); }
  const std::string& path() const { return path_; }

 private:
  void ReadBack();       // the records of a log resumed
  void Rewrite() const;  // the log anew with the records kept, atomically
  std::string path_;
  std::uint64_t seed_;
  int rocks_;
  Fingerprint fingerprint_;
  std::vector<std::string> names_;
  std::vector<Evaluation> records_;
};

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
  int max_evals = 100;            // evaluations (replayed ones count) [100], >= 2
  double max_seconds = 0.0;       // wall seconds for the method, 0 = no limit [0]
  std::uint64_t seed = 1;         // random seed of the stochastic global methods
  double polish_fraction = 0.3;   // share of a global method's budget for the local polish, [0, 0.9]
  double initial_step = 0.2;      // first step of the local methods, in the unit box, (0, 1]
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
  bool used = false;    // false: the calibrated values are the lowest evaluation
  std::string message;  // how it was made, or why it was not
  int points = 0;       // evaluations the linear model was fitted to
  double radius = 0.0;  // their neighbourhood's half-width in the unit box
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
  Stage stage;              // the method, and a refining stage's rocks
  Termination termination;  // why it stopped
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

// Standard errors and correlations at `at` (physical values, misfit
// `misfit` there): the Jacobian of the scaled residuals by central
// differences in the unit box (2n evaluations, spread over the ranks under
// mpirun, a step of 5 % of each range or less near a bound), then the
// Gauss-Newton covariance (J^T J)^-1, scaled by the reduced chi-square when
// that is above 1, mapped to physical units. What the ceres method reports
// at its calibrated values.
Uncertainty JacobianUncertaintyAt(const ObjectiveFunction& objective,
                                  const std::vector<double>& at, double misfit);

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

// Wall seconds at which a method's best misfit first came within `fraction`
// of `target` (best_misfit <= target * (1 + fraction)); negative if never.
double TimeToReach(const MethodResult& result, double target, double fraction = 0.1);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_CALIBRATION_H_
