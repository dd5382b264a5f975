#include "rockcal/reports/html_report.h"

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "report_sections/sections.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/reports/reach_report.h"

namespace rockcal::reports {
namespace {

// The misfit's Monte Carlo noise (CalibrationSummary::noise_seeds): the
// calibrated values' misfit at the other seeds, and a plain warning when the
// calibration's own seed scores below what they predict (noise_dip);
// and the noise check's warning (CalibrationSummary::noise_check) when the
// noise dominated what the first stage ranked by.
std::string NoiseSentence(const calibrate::CalibrationSummary& rec) {
  // "a", "a and b", "a, b and c".
  auto list = [](std::size_t count, const std::function<std::string(std::size_t)>& item) {
    std::string out;
    for (std::size_t k = 0; k < count; ++k)
      out += (k == 0 ? "" : k + 1 == count ? " and " : ", ") + item(k);
    return out;
  };
  std::string s;
  if (!rec.noise_seeds.empty()) {
    const std::size_t n = rec.noise_seeds.size();
    s = std::string("; at seed") + (n > 1 ? "s " : " ") +
        list(n, [&](std::size_t k) { return std::to_string(rec.noise_seeds[k]); }) +
        " the same values score " +
        list(n, [&](std::size_t k) { return sections::Label(rec.noise_misfits[k], 3); }) +
        " (Monte Carlo noise: standard deviation " + sections::Label(rec.misfit_noise_sd, 2) + ")";
    if (rec.noise_dip)
      s += "; the search found a dip of its own seed's noise: judge the fit at the other seeds";
  }
  if (rec.noise_check.done && rec.noise_check.noise_dominates)
    s += "; the noise check before the search: " + rec.noise_check.message;
  return sections::Escape(s);
}

using sections::Context;
using sections::Escape;
using sections::Int;
using sections::Label;
using sections::Rocks;

// One section of the report: its entry in the outline, its heading (empty:
// the escaped title) and how its body is drawn.
struct ReportSection {
  std::string id, title, heading_html;
  std::function<std::string()> body;
};

// The <h2> of partition p: its id (tied to summary.json), kind and place.
std::string PartitionHeading(const Context& c, int p) {
  const core::Partition& part = c.scene.partitions[static_cast<std::size_t>(p)];
  return "Partition " + html::RefText("summary.json#/partitions/" + Int(p) + "/id", part.id) +
         " (" + sections::KindName(part.kind) + " partition, " +
         Escape(html::PartitionPlace(part, c.in.units)) + ")";
}

// The report's sections in order, each only when the run has what it shows.
// The outline (ReportSections) and the page (HtmlReport) both come from here.
std::vector<ReportSection> Sections(const Context& c) {
  std::vector<ReportSection> out;
  auto add = [&](const char* id, const char* title, std::string (*body)(const Context&)) {
    out.push_back({id, title, "", [&c, body] { return body(c); }});
  };
  add("site", "Project and site", sections::SiteSection);
  if (sections::HasPlanView(c)) add("plan", "Plan view", sections::PlanSection);
  add("profile", "Profile view", sections::ProfileSection);
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    const core::Partition& part = c.scene.partitions[p];
    const int k = static_cast<int>(p);
    out.push_back({PartitionSectionId(part.id),
                   "Partition " + part.id + " (" + sections::KindName(part.kind) + ")",
                   PartitionHeading(c, k), [&c, k] { return sections::PartitionSection(c, k); }});
  }
  // The report's one fence at the partitions; each barrier line by its own.
  bool planes = false;
  for (const core::Partition& p : c.scene.partitions)
    planes = planes || p.kind != core::Partition::Kind::kLine;
  if (planes) add("barrier", "Barrier check", sections::BarrierSection);
  if (sections::HasBarriers(c.scene)) add("barriers", "Barriers", sections::BarriersSection);
  if (Rocks(c) > 0) add("runout", "Runout", sections::RunoutSection);
  if (sections::HasForestStrikes(c)) add("forest", "Forest", sections::ForestSection);
  if (c.several_shapes) add("shapes", "Rock shapes", sections::ShapesSection);
  if (sections::HasScannedShapes(c.scene))
    add("scanned", "Scanned shapes", sections::ScannedShapesSection);
  if (c.in.calibration && !c.in.calibration->methods.empty()) {
    const CalibrationSummary& rec = *c.in.calibration;
    if (rec.reach)
      out.push_back({"reach", "Reach before fit", "", [&rec] { return ReachSection(*rec.reach); }});
    add("calibration", "Calibration", sections::CalibrationSection);
    bool trace = false;
    for (const auto& m : rec.methods) trace = trace || !m.trace.empty();
    if (trace) add("trace", "Error against run time", sections::TraceSection);
    if (!rec.misfit_after.residuals.empty())
      add("fit", "Fit to the observations", sections::FitSection);
    if (!rec.misfit_after.runs.empty()) add("runs", "Tracked runs", sections::RunsSection);
    if (rec.misfit_after.tracks.tracks > 0) add("tracks", "Tracks", sections::TracksSection);
    if (!rec.misfit_after.impacts.empty())
      add("impacts", "Measured impacts", sections::ImpactsSection);
    if (rec.posterior && !rec.posterior->samples.empty())
      add("posterior", "Posterior and predictive bands", sections::PosteriorSection);
  }
  if (c.in.classes && !c.in.classes->materials->empty())
    add("classes", "Values from the class table", sections::ClassesSection);
  if (c.in.posterior_run && c.in.posterior_run->class_draws)
    add("class-draws", "Draws from the class table and bands", sections::PosteriorDrawsSection);
  else if (c.in.posterior_run)
    add("posterior-draws", "Posterior draws and predictive bands", sections::PosteriorDrawsSection);
  add("diagnostics", "Numerical diagnostics", sections::DiagnosticsSection);
  return out;
}

// The first paragraph: the rocks' outcomes, the partitions passed, and the
// calibration's verdict when there is one.
std::string Lead(const Context& c) {
  std::string lead = Int(Rocks(c)) + " rocks: " + Int(c.stopped) + " stopped, " + Int(c.left) +
                     " left the slope, " + Int(c.timeout) + " still moving at the time limit";
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    const auto& ps = c.stats.partitions[p];
    lead += "; " + Escape(ps.id) + " passed by " +
            html::Percent(Rocks(c) ? static_cast<double>(ps.passed) / Rocks(c) : 0.0);
  }
  if (Rocks(c) > 0) {
    const core::BeyondStats& d = c.stats.runout.distance_m;
    auto distance = [&](double v) {
      return std::isfinite(v) ? Escape(html::Length(v, c.in.units))
                              : std::string("beyond the edge");
    };
    lead += "; runout from the release " + distance(d.p50) + " at the median, " + distance(d.p90) +
            " at the 90th percentile";
    if (c.left > 0)
      lead += " (<b>" + Int(c.left) + " rocks, " +
              html::Percent(static_cast<double>(c.left) / Rocks(c)) +
              ", left the terrain: beyond its edge</b>, counted so in every runout figure)";
  }
  lead += ". Simulated by rockcal (CRSP-3D method) in " +
          Escape(html::Show(c.result.wall_seconds)) + " s wall time.";
  if (c.in.calibration && !c.in.calibration->methods.empty()) {
    const auto& rec = *c.in.calibration;
    const observations::FitVerdict verdict = observations::AssessFit(rec.misfit_after);
    lead +=
        std::string(verdict.poor ? " Calibration searched with " : " Parameters calibrated with ") +
        Escape(rec.methods[static_cast<std::size_t>(rec.best)].stage.name()) + ": misfit " +
        Escape(Label(rec.misfit_before.value, 3)) + " at the start, " +
        Escape(Label(rec.misfit_after.value, 3)) + " at the calibrated values" + " (" +
        Int(rec.final_rocks) + " rocks)" + NoiseSentence(rec) + ". <b>Fit " +
        Escape(verdict.Sentence()) + ".</b>" +
        (verdict.poor ? " The calibrated values do not reproduce the observations: do not use "
                        "them as if they did (widen the box, change the model, or check the "
                        "observations)."
                      : "");
  }
  return lead;
}

}  // namespace

bool ReportOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!(barrier_height_m > 0.0) || !std::isfinite(barrier_height_m))
    return fail("barrier_height_m = " + Label(barrier_height_m) + ": must be a finite number > 0");
  if (!(barrier_energy_j > 0.0) || !std::isfinite(barrier_energy_j))
    return fail("barrier_energy_j = " + Label(barrier_energy_j) + ": must be a finite number > 0");
  if (max_trajectories < 0)
    return fail("max_trajectories = " + Int(max_trajectories) + ": must be >= 0");
  if (max_stop_points < 1)
    return fail("max_stop_points = " + Int(max_stop_points) + ": must be >= 1");
  return true;
}

std::string PartitionSectionId(const std::string& partition_id) {
  std::string id = "partition-";
  for (char ch : partition_id) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '-' || ch == '_';
    id += ok ? ch : '_';
  }
  return id;
}

std::vector<std::string> ReportSections(const ReportInput& in) {
  const Context c = sections::MakeContext(in);
  std::vector<std::string> ids;
  for (const ReportSection& s : Sections(c)) ids.push_back(s.id);
  return ids;
}

std::string HtmlReport(const ReportInput& in) {
  const Context c = sections::MakeContext(in);
  const bool calibrated = in.calibration && !in.calibration->methods.empty();
  html::Page page;
  page.title = "rockcal report: " + c.scene.name;
  page.heading_html =
      std::string(calibrated ? "Rockfall calibration report: " : "Rockfall simulation report: ") +
      html::RefText("summary.json#/site", c.scene.name);
  page.lead_html = Lead(c);
  page.note_html =
      std::string(in.units == sites::Units::kUS
                      ? "SI units with US units beside them, as the site file is in US units: "
                        "1 ft = 0.3048 m; 1 ft/s = 0.3048 m/s; 1 ft-ton (foot times short "
                        "ton-force, as CRSP reports kinetic energy) = 2.7116 kJ; 1 lbf/ft&#179; "
                        "= 0.15709 kN/m&#179;. "
                      : "SI units, as the site file; coordinates are the site's own. ") +
      "The machine-readable record is summary.json and rocks.csv (SI).";
  for (const ReportSection& s : Sections(c))
    page.sections.push_back({s.id, s.title, s.heading_html, s.body()});
  page.footer_html =
      "Generated by rockcal, a rockfall simulator after CRSP-3D (FHWA-CFL/TD-12-007, 2012). "
      "Random seed " +
      std::to_string(c.scene.options.seed) + ", " + Int(Rocks(c)) +
      " rocks. This file is self-contained: no scripts, no network.";
  return html::PageHtml(page);
}

ReportInput SiteReport(const sites::Site& site, const core::Scene& scene,
                       const core::SimulationResult& result, const core::RasterSet* rasters) {
  ReportInput report;
  report.scene = &scene;
  report.result = &result;
  report.rasters = rasters;
  report.site_file = site.path;
  report.units = site.units;
  report.notes = site.notes;
  if (!site.class_materials.empty()) report.classes = ClassRun{&site.class_materials, false};
  report.options.barrier_height_m = site.barrier_height_m;
  report.options.barrier_energy_j = site.barrier_energy_j;
  return report;
}

}  // namespace rockcal::reports
