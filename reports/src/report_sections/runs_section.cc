// The tracked runs section of report.html: each run's observed runout
// against the median of its own rock group's simulated rocks, the mean
// per-run error in sample and held out, and the campaign's repeat scatter
// beside them.
#include <algorithm>
#include <cmath>

#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// Each run's observed runout against its group's simulated median, with
// one predictive spread above and below, on a 1:1 line.
std::string RunsPlot(const observations::Misfit& fit) {
  std::vector<double> ox, sy;
  double lo = kInf, hi = -kInf;
  for (const observations::RunFit& r : fit.runs) {
    ox.push_back(r.observed), sy.push_back(r.simulated);
    lo = std::min({lo, r.observed, r.simulated - r.spread});
    hi = std::max({hi, r.observed, r.simulated + r.spread});
  }
  const double pad = 0.05 * (hi - lo > 0 ? hi - lo : 1.0);
  lo -= pad, hi += pad;
  svg::Plot::Options o;
  o.width = 360, o.height = 320, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
  o.title = "Tracked runs: observed runout against the simulated median";
  svg::Plot plot(lo, hi, lo, hi, o);
  plot.Axes("observed runout [m]", "simulated median [m]");
  plot.Polyline({lo, hi}, {lo, hi}, "stroke=\"#999\" stroke-dasharray=\"4 3\"");
  for (const observations::RunFit& r : fit.runs)
    plot.Polyline({r.observed, r.observed}, {r.simulated - r.spread, r.simulated + r.spread},
                  "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1\"");
  plot.Points(ox, sy, 3.0, "fill=\"" + std::string(kStopColour) + "\"");
  return Figure(plot.Svg(),
                "Each run's observed runout against the median of its group's simulated rocks, "
                "with one predictive spread above and below; a perfect prediction lies on the "
                "1:1 line.",
                360);
}

}  // namespace

std::string RunsSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const observations::Misfit& fit = rec.misfit_after;
  auto length = [&rec](double m) { return SiteLength(m, rec.units); };
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
      " simulated rocks stuck near their release.";
  // The runs' own residuals apart from the pooled quantiles: which part of
  // the fit fails.
  int far = 0, scaled = 0;
  for (const observations::RunFit& r : fit.runs)
    if (r.sigma > 0) {
      ++scaled;
      far += std::abs(r.simulated - r.observed) > 2.0 * r.sigma ? 1 : 0;
    }
  if (scaled > 0)
    s += " " + Int(far) + " of " + Int(scaled) +
         " runs lie beyond 2 sigma of their prediction (a correct model puts about 1 in 20 "
         "there).";
  s += "</p>";
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
  s += RunsPlot(fit);
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
