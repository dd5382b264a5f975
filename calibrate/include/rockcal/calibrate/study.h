// Numerical studies of a site (`rockcal study stability|convergence`):
//  - the stability suite runs the site's scene and extreme variants of it
//    (hardness and contact time at their extremes, tiny and huge rocks,
//    cliffs, a flat runout, smooth and roughest slopes, a fast release) and
//    checks each against stated limits;
//  - the convergence study refines the time step (steps per contact N_c) and
//    the rock count, and reports the error of the summary quantiles against
//    the finest run, split into discretisation and Monte Carlo error, with
//    the wall time of each setting and a recommendation.
// The results are structs, read from and written to their JSON by to_json /
// from_json; the console report is written here; the files (JSON, CSV, the
// plot and report.html) by rockcal/reports/study_report.h. See
// calibrate/STUDIES.md.
#ifndef ROCKCAL_CALIBRATE_STUDY_H_
#define ROCKCAL_CALIBRATE_STUDY_H_

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"

namespace rockcal::calibrate {

// Called after each unit of work with (units done, units in all, what was done).
using StudyProgressFn = std::function<void(int done, int total, const std::string& what)>;

// ---- Stability ---------------------------------------------------------------

// The built-in stability cases, in the order they run (docs/studies.md).
enum class StabilityCaseId {
  kSite,       // "site": the site as it is
  kHardness0,  // "hardness_0"
  kHardness1,  // "hardness_1"
  kStiff,      // "contact_time_0.05ms"
  kSoft,       // "contact_time_50ms"
  kSizes,      // "sizes_1cm_10m"
  kCliff,      // "vertical_cliff"
  kFace,       // "near_vertical_face"
  kFlat,       // "flat_runout"
  kSmooth,     // "roughness_0"
  kRoughest,   // "roughness_max"
  kFast,       // "fast_release_hard"
};
// Their names from one table (stability.cc's, with how each case's scene is
// made) for parsing and printing. StringToStabilityCase returns false (and
// leaves *id alone) for a name not in the table; StabilityCaseNames lists
// the names, comma separated; AllStabilityCases the cases in order.
const char* StabilityCaseToString(StabilityCaseId id);
bool StringToStabilityCase(const std::string& name, StabilityCaseId* id);
std::string StabilityCaseNames();
const std::vector<StabilityCaseId>& AllStabilityCases();

// What each case may use and must meet: stability.json's "limits".
struct StabilityLimits {
  // Rocks per case, spread over the case's rock groups in proportion to their
  // counts; >= 1. Few rocks keep the suite quick: it looks for failures, not
  // for statistics.
  int rocks = 20;
  // Simulated seconds per rock, at most; the site's own max_time is used when
  // shorter. > 0. The flat runout case always gets this much time to stop.
  double max_time = 60.0;
  // Contact steps per case (all its rocks), at most, for the cases whose
  // step is smaller than the site's (the stiff contact time, hardness 0, the
  // fast release): they get at most max_case_steps / rocks * dt of simulated
  // time per rock (their stop duration shortened to half of that when
  // needed); >= 1000. Keeps the suite's cost bounded: a 0.05 ms contact
  // steps at 1 us.
  long max_case_steps = 10000000;
  // PASS limit on the largest relative energy gain of any rock (the gain of
  // mechanical energy including contact springs above its running minimum,
  // over the largest kinetic energy seen); >= 0.
  double energy_tolerance = 1e-3;
  // Advisory limit on the deepest overlap over the element radius; > 0.
  // Exceeding it is a warning, not a FAIL (see STUDIES.md): with the
  // mass-proportional stiffness the overlap is about v t_c / pi whatever the
  // rock's size, so small fast rocks overlap by more than their radius by the
  // contact law itself; what would be numerically wrong (passing through the
  // slope) is caught by the tunnelling check.
  double penetration_limit = 0.5;
};

struct StabilityOptions : StabilityLimits {
  // Seed of the runs; empty: the site's seed.
  std::optional<std::uint64_t> seed;
  int threads = 0;  // 0: OpenMP default; >= 0
  // The cases to run (StabilityCaseId); empty: all.
  std::vector<StabilityCaseId> cases;
  StudyProgressFn progress;  // after each rock of each case (may be empty)

  // Checks fields (and cases); on failure sets *error naming the field,
  // its value and the rule, and returns false.
  bool IsValid(std::string* error) const;
};

// One variant of the site: its scene and what it must show.
struct StabilityVariant {
  std::string name, description;
  core::Scene scene;
  bool must_stop = false;  // PASS also requires every rock to stop (flat runout)
};

// Builds the variants of `site_scene` selected by options.cases (all when
// empty). Throws std::invalid_argument when the options are not valid.
std::vector<StabilityVariant> StabilityVariants(const core::Scene& site_scene,
                                                const StabilityOptions& options);

struct StabilityCase {
  std::string name, description;
  double max_time = 0.0;  // s of simulated time allowed per rock in this case
  // The run's rocks, steps the engine chose (and the rocks whose step was
  // cut below t_c / N_c), contact steps and exact flights, the largest
  // relative energy gain (finite rocks), the deepest overlap / element
  // radius, non-finite and tunneled rocks.
  core::RunFigures figures;
  double wall_seconds = 0.0;  // simulation, all rocks
  int stopped = 0, left = 0, timeout = 0;
  bool must_stop = false;
  bool pass = false;
  std::string reason;   // why it failed ("" when it passed)
  std::string warning;  // advisory findings (penetration), "" when none
};

// The suite's result: what stability.json holds (with the limits, the
// criteria in words and the counts of PASS and FAIL beside it; to_json and
// from_json below), and the seed of its runs.
struct StabilityStudy {
  std::string site;  // the scene's name
  // The runs' seed (the options' or the site's); not in stability.json (the
  // report's footer names it).
  std::uint64_t seed = 0;
  StabilityLimits limits;
  std::vector<StabilityCase> cases;  // in AllStabilityCases() order

  int passed() const;  // cases that passed
  int failed() const { return static_cast<int>(cases.size()) - passed(); }
};

// Runs the suite on `site_scene`. Throws std::invalid_argument when the
// options are not valid (the caller checks IsValid first to report it).
StabilityStudy RunStabilitySuite(const core::Scene& site_scene, const StabilityOptions& options);
// Runs one variant and judges it against the options' limits.
StabilityCase RunStabilityVariant(const StabilityVariant& variant, const StabilityOptions& options);

// stability.json (calibrate/src/results_json.cc; reports/ writes the file
// and its CSV).
void to_json(nlohmann::json& j, const StabilityStudy& study);
void from_json(const nlohmann::json& j, StabilityStudy& study);
// A human table, one line per case with PASS/FAIL, then reasons and warnings.
std::string StabilityReport(const std::vector<StabilityCase>& cases);

// ---- Convergence -------------------------------------------------------------

struct ConvergenceOptions {
  // Steps per contact N_c to try (each >= 4, dt <= t_c / N_c); the largest is
  // the reference. At least one value.
  std::vector<int> steps_per_contact = {10, 20, 50, 100, 200};
  // Rock counts to try (each >= 1); the largest is the reference. The site's
  // groups keep their proportions.
  std::vector<int> rock_counts = {100, 300, 1000, 3000, 10000};
  // Recommend the cheapest setting whose error estimate is at most `target`
  // (a fraction of each quantity's reference value); in (0, 10].
  double target = 0.05;
  int bootstrap = 200;       // bootstrap resamples for the Monte Carlo error; >= 20
  double confidence = 0.90;  // level of the bootstrap interval; in (0.5, 1)
  // A quantity measured on fewer values (crossing or stopped rocks) than this
  // has an unknown Monte Carlo error in that run; >= 2.
  int min_values = 10;
  std::optional<std::uint64_t> seed;  // empty: the site's seed
  int threads = 0;                    // 0: OpenMP default; >= 0
  StudyProgressFn progress;           // after each rock of each run (may be empty)

  bool IsValid(std::string* error) const;
};

// One summary quantity in one run; errors are relative to the reference's
// value, +inf when unknown (the quantity is absent or rests on too few values).
struct QuantityError {
  std::string name;                   // "<partition>.height.p90" or "runout.p50"
  double value = 0.0;                 // NaN when absent in this run
  int count = 0;                      // values it was computed from
  double total_error = 0.0;           // |value - reference value|
  double mc_error = 0.0;              // half-width of the bootstrap interval at this rock count
  double discretisation_error = 0.0;  // |value - value at the finest N_c, same rocks and seed|
  // Half-width of the paired bootstrap interval of that difference: a
  // discretisation error below it is not resolved from Monte Carlo noise
  // (single trajectories are chaotic, so a step change scatters them).
  double discretisation_noise = 0.0;
  // The discretisation error of this N_c at the largest rock count (where
  // it is best resolved; it does not depend on the count) + mc_error.
  double estimate = 0.0;
};

struct ConvergenceRow {
  int steps_per_contact = 0, rocks = 0;
  // The run's steps the engine chose (and the rocks whose step the
  // stability bound cut below t_c / N_c), contact steps and flights.
  core::RunFigures figures;
  double wall_seconds = 0.0;
  int stopped = 0, left = 0, timeout = 0;
  std::vector<QuantityError> quantities;  // ConvergenceResult::quantities order
  // Largest of each error over the quantities.
  double max_total_error = 0.0, max_mc_error = 0.0, max_discretisation_error = 0.0,
         max_discretisation_noise = 0.0, max_estimate = 0.0;
  bool meets_target = false;  // max_estimate <= target
};

struct ConvergenceResult {
  std::string site;                     // the scene's name
  std::vector<ConvergenceRow> rows;     // N_c ascending, then rock count ascending
  std::vector<std::string> quantities;  // measured (present at the reference)
  std::vector<std::string> notes;       // quantities left out and why, other remarks
  int reference = -1;                   // row index of the finest N_c at the largest rock count
  int recommended = -1;                 // row index of the recommendation, -1: none
  double target = 0.0;
  int bootstrap = 0;
  double confidence = 0.0;
  std::uint64_t seed = 0;
  int threads = 0;
  std::string recommendation;  // one sentence
};

// Runs every combination of the options' N_c and rock counts on `scene`.
// Throws std::invalid_argument when the options are not valid.
ConvergenceResult RunConvergence(const core::Scene& scene, const ConvergenceOptions& options);

// convergence.json (calibrate/src/results_json.cc; reports/ writes the
// file, its CSV and the plot, reports::ConvergenceSvg).
void to_json(nlohmann::json& j, const ConvergenceResult& result);
void from_json(const nlohmann::json& j, ConvergenceResult& result);
// A human table, one line per setting, and the recommendation.
std::string ConvergenceReport(const ConvergenceResult& result);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_STUDY_H_
