// The sections of report.html (simulate and calibrate), one source file each,
// and what they share: the context of one report and the small drawing helpers.
// html_report.cc lists the sections in order; the outline and the body both
// come from that list. Private to reports/src.
#ifndef ROCKCAL_REPORTS_SRC_REPORT_SECTIONS_SECTIONS_H_
#define ROCKCAL_REPORTS_SRC_REPORT_SECTIONS_SECTIONS_H_

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rockcal/core/format.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/rasters.h"
#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/reports/html_page.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/svg.h"

namespace rockcal::reports::sections {

using core::FormatNumber;
using core::kFoot;

using svg::Escape;
using svg::Label;
using svg::Px;

using html::Coordinate;
using html::CoordinateNumber;
using html::Energy;
using html::Exact;
using html::Figure;
using html::kFtTon;
using html::Kv;
using html::Length;
using html::Percent;
using html::Ref;
using html::RefCell;
using html::RefSpan;
using html::Show;
using html::Speed;
using html::Td;
using html::Th;

using core::kInf;

// Colours shared by the sections' figures and legends.
inline constexpr const char* kPartitionColour = "#6a3d9a";
inline constexpr const char* kReleaseColour = "#009E73";
inline constexpr const char* kStopColour = "#0072B2";
inline constexpr const char* kTimeoutColour = "#CC79A7";
inline constexpr const char* kFenceColour = "#d62728";

// What every section reads: the report's input and figures of the run
// computed once.
struct Context {
  const ReportInput& in;
  const core::Scene& scene;
  const core::SimulationResult& result;
  core::ResultStats stats;
  bool one_cell_wide = false;  // a 2D profile: no plan view
  bool several_shapes = false;
  int stopped = 0, left = 0, timeout = 0;
  double zmin = kInf, zmax = -kInf;  // terrain elevation range (valid nodes)
  // The maps of the run (ReportInput::rasters, or computed when the scene
  // recorded the cells); null when the cells were not recorded.
  std::shared_ptr<const core::RasterSet> rasters = nullptr;
};

// Checks the input (scene, result and options) and computes the context;
// throws std::invalid_argument when the input is incomplete or invalid.
Context MakeContext(const ReportInput& in);

// ---- Small helpers ---------------------------------------------------------------

std::string Int(long v);
// "X" or "Z".
const char* KindName(core::Partition::Kind kind);
// "X partition: the vertical plane x = 12.3 m", ... (in `units`).
std::string PartitionWhere(const core::Partition& p, sites::Units units);
// `s` with its first letter in upper case.
std::string Capitalised(std::string s);
// A length in metres, with feet beside it for a site in US units ("12.3 m"
// or "12.3 m (40.4 ft)"): html::Length.
std::string SiteLength(double m, sites::Units units);
// True for a site in US units: figures show US units beside SI.
bool Us(const Context& c);
// The scale from metres to the secondary axis' unit of a plot (feet) for
// a US site, 0 for an SI site (no secondary axis).
double FeetAxis(const Context& c);
// Number of rocks of the run.
int Rocks(const Context& c);
// True when the report draws a plan view (a grid at least two nodes wide
// each way, not a one-cell-wide profile).
bool HasPlanView(const Context& c);
// At most `max` of `rocks` (in rock order) spread over every group
// (core::SpreadOverGroups), not the first ones; all of them when they fit.
std::vector<const core::RockRecord*> SpreadSample(const std::vector<const core::RockRecord*>& rocks,
                                                  int max);
// "12 of group 1, 18 of group 2" for `rocks`.
std::string PerGroup(const std::vector<const core::RockRecord*>& rocks);

// A legend swatch of `colour`: kind "bar" (a filled box), "line", "dash",
// "point", "ring", "cross" or "zone".
std::string Swatch(const std::string& colour, const std::string& kind = "bar");
// A legend item: a swatch and its escaped label.
std::string LegendItem(const std::string& swatch, const std::string& label);

// A table of bands over posterior draws (where, quantity, unit, 5 %, median,
// 95 %): rockcal simulate's of a posterior, calibrate --posterior's.
std::string DrawBandsTable(const std::vector<calibrate::DrawBand>& bands);

// A histogram of `values` (display units); `top_scale` converts to the
// secondary units on top; a dashed line marks `mark` when finite.
std::string Histogram(const std::vector<double>& values, const std::string& x_label,
                      double top_scale, const std::string& top_label, double mark,
                      const std::string& mark_label, const std::string& title,
                      double xmin_hint = 0.0);

// ---- The sections' bodies (HTML), one source file each ------------------------------

std::string SiteSection(const Context& c);              // site_section.cc
std::string PlanSection(const Context& c);              // plan_section.cc
std::string ProfileSection(const Context& c);           // profile_section.cc
std::string PartitionSection(const Context& c, int p);  // partition_section.cc
std::string BarrierSection(const Context& c);           // barrier_section.cc
// True when the scene has barriers (partitions of Partition::Kind::kLine).
bool HasBarriers(const core::Scene& scene);             // barriers_section.cc
std::string BarriersSection(const Context& c);          // barriers_section.cc
std::string RunoutSection(const Context& c);            // runout_section.cc
std::string ShapesSection(const Context& c);            // shapes_section.cc
// True when a rock group or an inventory block has a scanned shape.
bool HasScannedShapes(const core::Scene& scene);                // scanned_shapes_section.cc
std::string ScannedShapesSection(const Context& c);     // scanned_shapes_section.cc
std::string CalibrationSection(const Context& c);       // calibration_section.cc
std::string TraceSection(const Context& c);             // trace_section.cc
std::string FitSection(const Context& c);               // fit_section.cc
std::string RunsSection(const Context& c);              // runs_section.cc
std::string TracksSection(const Context& c);            // tracks_section.cc
std::string ImpactsSection(const Context& c);           // impacts_section.cc
std::string PosteriorSection(const Context& c);         // posterior_section.cc
std::string PosteriorDrawsSection(const Context& c);    // posterior_draws_section.cc
std::string ClassesSection(const Context& c);           // classes_section.cc
std::string DiagnosticsSection(const Context& c);       // diagnostics_section.cc
// True when the scene has a forest and the run recorded its strikes.
bool HasForestStrikes(const Context& c);                // forest_section.cc
std::string ForestSection(const Context& c);            // forest_section.cc
// The reach section is reach_report.h's ReachSection.

}  // namespace rockcal::reports::sections

#endif  // ROCKCAL_REPORTS_SRC_REPORT_SECTIONS_SECTIONS_H_
