// The fit section of report.html: observed against simulated quantiles,
// at the start and at the calibrated values, and the residuals.
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// A residual of a fraction (a passing fraction, the stopped share), not of a
// distance or height: no unit, one value rather than quantiles.
bool IsFraction(const observations::Residual& r) {
  return r.id.statistic == observations::Statistic::kFraction ||
         r.id.statistic == observations::Statistic::kShare;
}

}  // namespace

std::string FitSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const auto& after = rec.misfit_after.residuals;
  // The observations in order, and the "before" residual of each identity.
  std::vector<observations::ResidualId> observed;
  for (const auto& r : after)
    if (std::find(observed.begin(), observed.end(), r.id.observation_id()) == observed.end())
      observed.push_back(r.id.observation_id());
  std::map<observations::ResidualId, const observations::Residual*> before;
  for (const auto& r : rec.misfit_before.residuals) before[r.id] = &r;
  std::string s =
      "<p>Each observed quantile against its simulated counterpart, at the start (rings) and at "
      "the "
      "calibrated values (dots, with one uncertainty above and below). A perfect fit lies on the "
      "1:1 "
      "line.</p><ul class=\"legend\">" +
      LegendItem(Swatch("#888", "ring"), "at the start") +
      LegendItem(Swatch(kStopColour, "point"), "calibrated, with its uncertainty") +
      LegendItem(Swatch("#999", "dash"), "1:1") + "</ul><div class=\"figs\">";
  for (const observations::ResidualId& of : observed) {
    const std::string label = of.observation();
    std::vector<double> ox, sy, bx, by;
    double lo = kInf, hi = -kInf;
    std::string bars;
    for (const auto& r : after) {
      if (r.id.observation_id() != of) continue;
      ox.push_back(r.observed), sy.push_back(r.simulated);
      lo = std::min({lo, r.observed, r.simulated - r.sigma}),
      hi = std::max({hi, r.observed, r.simulated + r.sigma});
      const auto it = before.find(r.id);
      if (it != before.end()) {
        bx.push_back(it->second->observed), by.push_back(it->second->simulated);
        lo = std::min(lo, it->second->simulated), hi = std::max(hi, it->second->simulated);
      }
    }
    const bool fraction = after.empty() ? false : [&] {
      for (const auto& r : after)
        if (r.id.observation_id() == of) return IsFraction(r);
      return false;
    }();
    const double pad = 0.05 * (hi - lo > 0 ? hi - lo : 1.0);
    lo -= pad, hi += pad;
    svg::Plot::Options o;
    o.width = 330, o.height = 290, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
    o.title = "Observed against simulated quantiles: " + label;
    svg::Plot plot(lo, hi, lo, hi, o);
    const std::string unit = fraction ? "" : " [m]";
    plot.Axes("observed" + unit, "simulated" + unit);
    plot.Polyline({lo, hi}, {lo, hi}, "stroke=\"#999\" stroke-dasharray=\"4 3\"");
    for (const auto& r : after) {
      if (r.id.observation_id() != of) continue;
      plot.Polyline({r.observed, r.observed}, {r.simulated - r.sigma, r.simulated + r.sigma},
                    "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1\"");
    }
    plot.Points(bx, by, 3.5, "fill=\"none\" stroke=\"#888\" stroke-width=\"1.2\"");
    plot.Points(ox, sy, 3.0, "fill=\"" + std::string(kStopColour) + "\"");
    s += Figure(plot.Svg(),
                "<b>" + Escape(label) + "</b>" +
                    (fraction ? "" : " (quantiles p10 to p90 and the maximum)"),
                330);
  }
  s += "</div>";
  // Residual table.
  s += "<h3>Residuals</h3><table><thead><tr>" + Th("observation") + Th("quantity") +
       Th("observed") + Th("simulated at the start") + Th("simulated, calibrated") +
       Th("uncertainty") + Th("residual") + "</tr></thead><tbody>";
  for (std::size_t k = 0; k < after.size(); ++k) {
    const auto& r = after[k];
    const bool fraction = IsFraction(r);
    auto value = [&](double v) {
      if (fraction) return FormatNumber(v, "%.3f");
      return SiteLength(v, rec.units);
    };
    const auto it = before.find(r.id);
    const std::string base = "/fit/" + Int(static_cast<long>(k)) + "/";
    s += "<tr>" + Td(r.id.observation()) + Td(r.id.quantity()) +
         RefCell(Ref("calibration.json", base + "observed"), r.observed, value(r.observed)) +
         Td(it != before.end() ? value(it->second->simulated) : "-", true) +
         RefCell(Ref("calibration.json", base + "simulated"), r.simulated, value(r.simulated)) +
         Td(value(r.sigma), true) +
         RefCell(Ref("calibration.json", base + "residual"), r.value, Show(r.value)) + "</tr>";
  }
  s += "</tbody></table>";
  return s;
}

}  // namespace rockcal::reports::sections
