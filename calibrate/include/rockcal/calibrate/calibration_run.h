// A whole calibration as one call: the site's parameters searched by one or
// more methods against the observations, the best method's values applied,
// and the site simulated once more at them with what the report needs.
#ifndef ROCKCAL_CALIBRATE_CALIBRATION_RUN_H_
#define ROCKCAL_CALIBRATE_CALIBRATION_RUN_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/calibrate/reach.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// Which stage's objective the posterior samples (CalibrationOptions::
// posterior_stage) when a refining stage runs.
enum class PosteriorStage {
  // The first stage's (its rocks; the reach design's and the first search's
  // evaluations reused): some ten times cheaper per evaluation, the
  // intervals somewhat wider (the Monte Carlo error of fewer rocks is in
  // every residual's sigma).
  kFirst,
  kFinal,  // the refining stage's (its rocks; its search's evaluations reused)
};
const char* PosteriorStageToString(PosteriorStage stage);  // "first", "final"
// Sets *stage from its name; false for an unknown name.
bool StringToPosteriorStage(const std::string& name, PosteriorStage* stage);

// Options of Calibrate. Defaults in brackets: CalibrationOptions{} is what
// `rockcal calibrate` runs without flags (the command only maps its flags
// onto these fields).
struct CalibrationOptions {
  // A field left at kAuto takes the value Resolved gives it for the run's
  // parameters and budget.
  static constexpr int kAuto = -1;
  // The search alone, in one stage: no reach check, refining stage, race,
  // noise check or noise seeds (a campaign's search, and tests').
  static CalibrationOptions SingleStage();

  // The methods to run, in order [nlopt:bobyqa]; the one with the lowest
  // misfit gives the calibrated values.
  std::vector<Method> methods = {Method::kBobyqa};
  // The budget and settings of every method; its `seed` is replaced by the
  // run's seed (below).
  MethodOptions method;
  observations::MisfitOptions misfit;  // how the misfit is computed [its defaults]
  // Rocks per evaluation, spread over the rock groups in proportion to their
  // counts; 0 keeps the site's counts [0], >= 0.
  int rocks = 0;
  // The seed of every evaluation (common random numbers) and of the
  // stochastic methods; unset: the site file's [unset].
  std::optional<std::uint64_t> seed;
  int threads = 0;  // threads of each simulation, 0 = OpenMP's default [0], >= 0
  // The evaluation log (one JSON line per evaluation, DIR/evaluations.jsonl);
  // empty: none [empty].
  std::string log_path;
  // Continue the log at log_path: its evaluations are replayed, not
  // simulated again [false]. Needs log_path.
  bool resume = false;
  // Which part of the observations file the observations are (e.g. "fold 2
  // of 5, seed 1"); empty: all of it [empty]. Part of the log's fingerprint.
  std::string observations_subset;
  // Reach before fit: design points of a space-filling sample of the box
  // (RunReach) simulated before the search; 0: none [0]. The search starts
  // from the design's lowest misfit when that is lower than the site's
  // starting values', and the summary keeps the reach check (which observed
  // statistics the box reaches at all). kAuto: DefaultReachPoints [kAuto];
  // else >= 0, 1 is not a design.
  int reach_points = kAuto;
  // Enough rocks where the search ends (retrospective approximation): with
  // refine_factor > 1, after the methods have searched at `rocks` per
  // evaluation, the best of them searches again from its calibrated values
  // with refine_factor times as many rocks, a first step of refine_step (unit
  // box) and refine_share of max_evals (the first stage keeps the rest); its
  // values are the calibrated ones and the final simulation has as many
  // rocks. 1: one stage [1], >= 1. The refining log is the log's name with
  // "-refine" before ".jsonl". [4]
  int refine_factor = 4;
  double refine_share = 1.0 / 3.0;  // (0, 1)
  double refine_step = 0.05;        // (0, 1]
  // A race before the refining stage (with refine_factor > 1): the first
  // stage's best values, the site's starting values and the race_points
  // design points of lowest misfit (with reach_points) are simulated at the
  // refining stage's rocks, and the refining search starts from the lowest.
  // At a few dozen rocks the misfit's Monte Carlo noise is as large as the
  // differences the first stage ranks by, so its best is mostly the luckiest
  // draw; the race ranks the candidates again at the noise level the search
  // ends at. 0: none, the refining search starts from the first stage's
  // best. kAuto: with a refining stage the best twelfth of the reach design
  // (at least 2), else 0 [kAuto]; else >= 0.
  int race_points = kAuto;
  // The misfit's Monte Carlo noise where the search ended: the calibrated
  // values simulated again at this many other seeds (seed + 1, seed + 2, ...)
  // with the final rock count; 0: none [3], >= 0.
  int noise_seeds = 3;
  // The noise check before the search (NoiseCheck): the misfit at the start
  // at this many other seeds (seed + 1, ...), its spread against the spread
  // of the reach design's misfits (needs reach_points); 0: none [3], >= 0.
  int noise_check_seeds = 3;
  // Noise dominates when the start's spread over seeds is more than this
  // share of the design's spread [0.25], (0, 1].
  double noise_check_ratio = 0.25;
  // When the noise dominates, the rocks per evaluation are raised to the
  // whole multiple of `rocks` that brings the ratio to noise_check_ratio (a
  // multiple keeps every group's share and every inventory's blocks
  // balanced), at most this many times; the search, the refining stage
  // (refine_factor times the raised rocks) and the log then run at the
  // raised count. 1: never raise, only say how many are needed [4], >= 1.
  int noise_raise = 4;

  // The reach design a calibration with `parameters` calibrated values and
  // `max_evals` evaluations gets by default: 4 (n + 1) points, or half the
  // evaluation budget when that is more (a global stage that grows with the
  // budget: a rugged misfit has basins a small design does not see).
  static int DefaultReachPoints(int parameters, int max_evals);
  // These options with every kAuto field resolved for a space of
  // `parameters` calibrated values (Calibrate resolves them itself).
  CalibrationOptions Resolved(int parameters) const;

  // The posterior of the calibrated values (SamplePosterior), after the
  // search, on the objective of `posterior_stage` (its rocks and seed; the
  // evaluations of that stage reused, new ones appended to its log);
  // unset: none [unset].
  std::optional<PosteriorOptions> posterior;
  PosteriorStage posterior_stage = PosteriorStage::kFirst;  // [first]

  // Checks each field (the methods' names, the method options, the misfit
  // options); on failure sets *error naming the field, its value and the rule.
  bool IsValid(std::string* error) const;
};

struct CalibrationSummary;

// Called as a calibration goes; every member may be empty.
struct CalibrationCallbacks {
  // Once the misfit at the start is known (summary.misfit_before, start,
  // space, rocks and seed are set).
  std::function<void(const CalibrationSummary&)> started;
  // After the reach check (CalibrationOptions::reach_points), before the search.
  std::function<void(const ReachResult&)> reach_done;
  // After the noise check (CalibrationOptions::noise_check_seeds), before the search.
  std::function<void(const CalibrationSummary&)> noise_checked;
  std::function<void(const Stage& stage)> method_started;
  CalibrationProgress evaluated;  // after every evaluation
  std::function<void(const MethodResult&)> method_finished;
  PosteriorProgress posterior;  // during the posterior stage
  // Once the first log of the run is open (a resumed one read and found to
  // belong to this run), before anything is written to it: the caller's
  // output folder may now change (a resumed folder loses its completion
  // marker). Called again by each fold; must be idempotent.
  std::function<void()> log_opened;
};

// Whether a misfit `own` at the calibration's seed lies below what the
// misfits at k >= 2 other seeds predict for one more seed: their mean less
// t s sqrt(1 + 1/k), s their sample standard deviation and t Student's
// 97.5 % quantile with k - 1 degrees of freedom (a one-sided prediction
// bound). False with fewer than 2 others.
bool NoiseDip(double own, const std::vector<double>& others);

// Everything a calibration produced, as its outputs need it.
struct CalibrationSummary {
  std::string site;  // the site's name
  sites::Units units = sites::Units::kSI;
  double grid_spacing_m = 0.0;  // the terrain grid's = virtual spheres' spacing (0: unknown)
  ParameterSpace space;
  std::vector<double> start;           // physical values before (the site's)
  // The reach check, when run; the search then started from `search_start`.
  std::optional<ReachResult> reach;
  std::vector<double> search_start;    // where the methods started
  // At start; with a refining stage, at its rocks (as misfit_after), once
  // it has run (the `started` callback sees the first stage's).
  observations::Misfit misfit_before;
  observations::Misfit misfit_after;   // at the calibrated values, of `simulation`
  std::vector<MethodResult> methods;   // in the order run
  int best = 0;                        // index into methods
  int rocks = 0;                       // per evaluation
  std::uint64_t seed = 1;
  double wall_seconds = 0.0;  // the whole calibration
  Termination termination;    // the best method's
  // With CalibrationOptions::refine_factor > 1: the first stage's rocks per
  // evaluation are `rocks`, the refining stage's (the last of `methods`, its
  // Stage::rocks set, named "<method> (<N> rocks)", and the best)
  // `final_rocks`; else both are `rocks`.
  int final_rocks = 0;
  // CalibrationOptions::race_points: the candidates raced at final_rocks
  // before the refining stage, in the order raced (the first stage's best,
  // the site's start, then the design points by their design misfit), with
  // where each came from and its misfit there; `race_winner` indexes the one
  // the refining search started from (-1: no race).
  struct RaceEntry {
    std::string from;  // "first stage", "start" or "design point N" (1-based)
    std::vector<double> physical;
    double misfit_before = 0.0;  // at `rocks` (the stage or design it came from)
    double misfit = 0.0;         // at final_rocks
    bool penalised = false;
  };
  std::vector<RaceEntry> race;
  int race_winner = -1;
  // CalibrationOptions::noise_seeds: the misfit at the calibrated values at
  // other seeds, and the standard deviation of those and misfit_after.value.
  std::vector<std::uint64_t> noise_seeds;
  std::vector<double> noise_misfits;
  double misfit_noise_sd = 0.0;
  // The search found a dip of its own seed's noise (NoiseDip(misfit_after,
  // noise_misfits)): its fit is to be judged at the other seeds.
  bool noise_dip = false;
  // CalibrationOptions::noise_check_seeds: is the misfit's Monte Carlo noise
  // small against what the search ranks by? Set before the search.
  struct NoiseCheck {
    bool done = false;
    std::vector<double> start_misfits;  // at the start, the run's seed first, then the others
    double start_sd = 0.0;   // their sample standard deviation
    // The spread of the misfits the search ranks between: the sample
    // standard deviation of the best quarter of the design's unpenalised
    // misfits (SpreadOfContenders; `contenders` points).
    double design_spread = 0.0;
    int contenders = 0;
    double ratio = 0.0;      // start_sd / design_spread (inf when the design has no spread)
    bool noise_dominates = false;  // ratio > noise_check_ratio
    // The rocks per evaluation at which the ratio would fall to
    // noise_check_ratio (the noise's standard deviation as 1 / sqrt(rocks)),
    // or the rocks as they are when the noise does not dominate.
    int rocks_needed = 0;
    // The rocks per evaluation the search ran at: the checked ones, or
    // raised (CalibrationOptions::noise_raise) when the noise dominated.
    int rocks_checked = 0;
    int rocks_used = 0;
    // The noise still dominates the search: it dominated and the raise
    // (capped by noise_raise, or none) did not reach rocks_needed.
    bool still_dominates() const { return noise_dominates && rocks_used < rocks_needed; }
    std::string message;  // one plain sentence
  };
  NoiseCheck noise_check;

  // CalibrationOptions::posterior: the posterior of the calibrated values.
  std::optional<PosteriorResult> posterior;
  // The site's scene at the calibrated values, recording what the files of
  // a simulation need (summary.json, rocks.csv, the misfit); no trajectories.
  core::Scene calibrated;
  // Its simulation, recorded also for the report (passages, a few trajectories).
  core::SimulationResult simulation;

  const MethodResult& best_method() const { return methods[static_cast<std::size_t>(best)]; }
  // A few lines: the misfit before and after, the best method, why it
  // stopped, the evaluations and the wall time.
  std::string BriefReport() const;
};

// What determines the evaluations of Calibrate(site, observations, options):
// the bytes of the site file and of every data file it read (Site::inputs),
// of the observations file and its CSV files (Observations::inputs), the seed, the rock count, the
// methods, the method options (not the budget: a resumed run may be given more evaluations or
// time), the misfit options and the parameters' bounds and starting values (`space`, the
// site's ParameterSpace::FromSite, built once by the run). The thread count is left out (it
// changes no result).
Fingerprint CalibrationFingerprint(const sites::Site& site,
                                   const observations::Observations& observations,
                                   const CalibrationOptions& options, const ParameterSpace& space);

// One fold of a cross-validation (CrossValidate).
struct FoldResult {
  int fold = 1;                   // 1-based
  int held_out_values = 0;        // observed values held out (scar heights, stop points)
  double in_sample_misfit = 0.0;  // the fold's calibration against its training values
  double held_out_misfit = 0.0;   // its calibrated values against the held-out values
  // The median over p10 ... p90 of |simulated - observed| runout distance,
  // the observed quantiles those of the held-out stop points [m]; with
  // tracked runs (observations::Runout::has_runs), the mean over the
  // held-out runs of |median simulated - observed| runout (Misfit::
  // MeanRunError); unset without runout observations.
  std::optional<double> runout_error_m;
  std::vector<double> calibrated;  // the fold's calibrated values (physical)
  Termination termination;
};

struct HoldoutSummary {
  int folds = 0;
  std::uint64_t seed = 1;  // of the split
  std::vector<FoldResult> results;
  double mean_in_sample_misfit = 0.0, mean_held_out_misfit = 0.0;
  std::optional<double> mean_runout_error_m;
  // With tracked runs: the scatter of the campaign's repeated runs, the
  // yardstick of mean_runout_error_m (observations::RunRepeatScatter).
  std::optional<observations::RepeatScatter> repeat_scatter;
};

// K-fold cross-validation: observations::MakeFolds(observations, folds,
// seed); for each fold, Calibrate on the other folds' values (the log, when
// options.log_path is set, is "evaluations-fold-<k>.jsonl" beside it; with
// options.resume, a fold without a log yet starts afresh) and Score the
// fold's held-out values at its calibrated values.
HoldoutSummary CrossValidate(const sites::Site& site,
                             const observations::Observations& observations,
                             const CalibrationOptions& options, int folds,
                             const CalibrationCallbacks& callbacks = {});

// The search of a calibration, on any objective (a site's Objective, a
// campaign's CampaignObjective): each of `methods` in turn from `start`
// (physical values) with `options`, through `log` (none: null) and the
// callbacks' method_started, evaluated and method_finished; appends the
// results to summary->methods and makes summary->best the lowest misfit's.
// Throws std::runtime_error when no evaluation finished.
void SearchMethods(const ObjectiveFunction& objective, const std::vector<double>& start,
                   const std::vector<Method>& methods, const MethodOptions& options,
                   EvaluationLog* log, const CalibrationCallbacks& callbacks,
                   CalibrationSummary* summary);

// Throws the InputError Calibrate would throw before its first evaluation
// (invalid options, a site without calibrated parameters), so that a caller
// can check before it writes anything.
void CheckCalibration(const sites::Site& site, const CalibrationOptions& options);

// With options.resume: reads every log Calibrate (and CrossValidate with
// `folds` > 0) would resume, changing nothing and simulating nothing, and
// throws the InputError the resume would throw (a changed input or option,
// a log two runs wrote). The rocks a noise check may raise are compared
// later, when the log is opened (CalibrationCallbacks::log_opened).
void CheckResume(const sites::Site& site, const observations::Observations& observations,
                 const CalibrationOptions& options, int folds = 0);

// The noise check's yardstick: the misfits the search ranks between are the
// design's best, not its far points (which set a spread that any noise looks
// small against). `spread` is the sample standard deviation of the lowest
// quarter of `misfits` (at least 4 of them, all when fewer); `points` how
// many; both 0 with fewer than 2 misfits.
struct ContenderSpread {
  double spread = 0.0;
  int points = 0;
};
ContenderSpread SpreadOfContenders(std::vector<double> misfits);

// Calibrates `site` against `observations`. Throws InputError for invalid
// options, a site without calibrated parameters or a log that cannot be
// resumed; std::runtime_error when no evaluation finished.
CalibrationSummary Calibrate(const sites::Site& site,
                             const observations::Observations& observations,
                             const CalibrationOptions& options,
                             const CalibrationCallbacks& callbacks = {});

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_CALIBRATION_RUN_H_
