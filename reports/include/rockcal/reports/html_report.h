// report.html: the self-contained report of a simulation (and of the
// calibration that produced it) that an engineer hands in. One file, no
// network, no scripts, SVG plots inline, printable; XHTML-compatible markup.
// Each section appears only when the run has what it shows; see
// reports/README.md for the list.
#ifndef ROCKCAL_REPORTS_HTML_REPORT_H_
#define ROCKCAL_REPORTS_HTML_REPORT_H_

#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/posterior_draws.h"
#include "rockcal/core/rasters.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports {

struct ReportOptions {
  // The barrier check: the share of the rocks passing each partition whose
  // bounce height (rock centre above the ground) or kinetic energy exceeds
  // these. Defaults: a 10 ft (3.048 m), 500 kJ fence. Both > 0.
  double barrier_height_m = 3.048;
  double barrier_energy_j = 500e3;
  // At most this many sampled trajectories are drawn in the profile view, >= 0.
  int max_trajectories = 30;
  // At most this many stop points are drawn in the plan view, >= 1.
  int max_stop_points = 5000;

  bool IsValid(std::string* error) const;
};

// The materials whose values came from a class table, and whether the run
// drew them (else it took the medians).
struct ClassRun {
  const std::vector<sites::ClassMaterial>* materials = nullptr;
  bool drawn = false;
};

// What the report shows. `scene` and `result` are required; the result should
// be simulated with RecordOptions::passages (the density map) and a few
// trajectories (the profile view); without them those views say so.
struct ReportInput {
  const core::Scene* scene = nullptr;
  const core::SimulationResult* result = nullptr;
  // The maps of `result` (core::ComputeRasters), drawn by the plan view so
  // that it shows what rasters.tif holds. Null: computed here when `scene`
  // records the cells (RecordOptions::passages); else the plan has no
  // passage map and says so.
  const core::RasterSet* rasters = nullptr;
  std::string site_file;  // shown as given
  sites::Units units =
      sites::Units::kSI;           // the site's units (US values are shown beside SI anyway)
  std::vector<std::string> notes;  // what the site reader found and did
  // Optional: the calibration that chose the scene's parameters; adds the
  // calibration, trace and fit sections.
  const CalibrationSummary* calibration = nullptr;
  // Optional: the posterior draws the run took (rockcal simulate --parameters
  // of a posterior); adds the section "posterior-draws" (the draws and the
  // predictive bands of the runout and the partitions' statistics).
  const calibrate::PosteriorRun* posterior_run = nullptr;
  // Optional: the site's materials that took values from a class table
  // (SiteReport sets it); adds the section "classes".
  std::optional<ClassRun> classes;
  // Optional: field observations; observed stop points are drawn on the plan,
  // and tracked runs that repeat one another give their scatter (section
  // "runs").
  const observations::Observations* observations = nullptr;
  // Optional: the calibration's cross-validation (rockcal calibrate
  // --holdout); with tracked runs the "runs" section gives its held-out
  // per-run error.
  const calibrate::HoldoutSummary* holdout = nullptr;
  // Optional: the same rocks on the slope without its forest (rockcal
  // simulate --compare-bare); the forest section sets their runout beside
  // the forest's.
  const core::SimulationResult* bare = nullptr;
  ReportOptions options;
};

// The whole report.html. Throws std::invalid_argument when scene or result is
// missing or the options are invalid (programmer errors).
std::string HtmlReport(const ReportInput& in);

// The section ids HtmlReport writes for `in`, in order ("site", "plan",
// "profile", "partition-<id>", ...): what the tests and readers can rely on.
std::vector<std::string> ReportSections(const ReportInput& in);

// "partition-" + the partition id with every character other than a letter,
// digit, '-' or '_' replaced by '_'.
std::string PartitionSectionId(const std::string& partition_id);

// The report of `result` (simulated from `scene`) with what the site file
// gives it: the file, its units, the reader's notes and the barrier; its plan
// view draws `rasters` (the maps of `result`, as written to rasters.tif).
ReportInput SiteReport(const sites::Site& site, const core::Scene& scene,
                       const core::SimulationResult& result, const core::RasterSet* rasters);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_HTML_REPORT_H_
