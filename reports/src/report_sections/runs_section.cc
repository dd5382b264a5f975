// The tracked runs section of report.html: each run's observed runout
// against the median of its own rock group's simulated rocks, the mean
// per-run error in sample and held out, and the campaign's repeat scatter
// beside them.
#include <algorithm>
#include <cmath>

#include "sections.h"

namespace rockcal::reports::sections {

std::string RunsSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const observations::Misfit& fit = rec.misfit_after;
  // Metres, and feet beside them for a site in US units.
  auto length = [us = rec.units == sites::Units::kUS](double m) {
    return us ? Length(m) : Show(m) + " m";
  };
  std::vector<double> errors;
  for (const observations::RunFit& r : fit.runs)
    errors.push_back(std::abs(r.simulated - r.observed));
  std::sort(errors.begin(), errors.end());
  const std::size_t n = errors.size();
  std::string s =
      "<p>" + Int(static_cast<long>(n)) +
      " tracked runs, each compared with the simulated rocks of its own rock group, measured "
      "from its own release. Mean |median simulated &#8722; observed| runout at the calibrated "
      "values: " +
      RefSpan(Ref("calibration.json", "/runs/mean_abs_error_m"), fit.MeanRunError(),
              length(fit.MeanRunError())) +
      " in sample (the median run: " + Escape(length(core::Quantile(errors, 0.5))) + "); " +
      RefSpan(Ref("calibration.json", "/runs/stuck_at_release"), fit.StuckRocks(),
              Int(fit.StuckRocks())) +
      " simulated rocks stuck near their release.</p>";
  if (const calibrate::HoldoutSummary* h = c.in.holdout; h && h->mean_runout_error_m) {
    s += "<p><b>Held out</b> (" + Int(h->folds) +
         " folds over runs, each run predicted by a calibration that did not see it): mean "
         "per-run error " +
         RefSpan(Ref("holdout.json", "/mean_runout_median_abs_error_m"), *h->mean_runout_error_m,
                 length(*h->mean_runout_error_m)) +
         " (folds ";
    for (std::size_t k = 0; k < h->results.size(); ++k) {
      const auto& e = h->results[k].runout_error_m;
      s += (k ? ", " : "") +
           (e ? RefSpan(Ref("holdout.json", "/per_fold/" + Int(static_cast<long>(k)) +
                                                "/runout_median_abs_error_m"),
                        *e, Show(*e))
              : std::string("-"));
    }
    s += " m).</p>";
  }
  if (c.in.observations)
    if (const auto scatter = observations::RunRepeatScatter(*c.in.observations, c.scene)) {
      s += "<p>" + Escape(Capitalised(scatter->Sentence())) + ".";
      // The held-out error against what the repeats achieve against each
      // other: the yardstick a user reads it by.
      if (const calibrate::HoldoutSummary* h = c.in.holdout;
          h && h->mean_runout_error_m && scatter->others_median_error_m > 0)
        s +=
            " The held-out error is " +
            Escape(FormatNumber(*h->mean_runout_error_m / scatter->others_median_error_m, "%.2g")) +
            " times the repeats' error against the median of their set's other runs.";
      s += "</p>";
    }
  s += "<table><thead><tr>" + Th("run") + Th("observed runout") + Th("simulated median") +
       Th("|error|") + Th("predictive spread") + Th("rocks") + Th("stopped") +
       Th("stuck near release") + "</tr></thead><tbody>";
  for (std::size_t k = 0; k < fit.runs.size(); ++k) {
    const observations::RunFit& r = fit.runs[k];
    const std::string base = "/runs/per_run/" + Int(static_cast<long>(k)) + "/";
    s += "<tr>" + Td(r.id) +
         RefCell(Ref("calibration.json", base + "observed_m"), r.observed, length(r.observed)) +
         RefCell(Ref("calibration.json", base + "simulated_median_m"), r.simulated,
                 length(r.simulated)) +
         Td(length(std::abs(r.simulated - r.observed)), true) +
         RefCell(Ref("calibration.json", base + "spread_m"), r.spread, length(r.spread)) +
         RefCell(Ref("calibration.json", base + "rocks"), r.rocks, Int(r.rocks)) +
         RefCell(Ref("calibration.json", base + "stopped"), r.stopped, Int(r.stopped)) +
         RefCell(Ref("calibration.json", base + "stuck_at_release"), r.stuck, Int(r.stuck)) +
         "</tr>";
  }
  s += "</tbody></table>";
  return s;
}

}  // namespace rockcal::reports::sections
