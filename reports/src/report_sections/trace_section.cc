// The error against run time section of report.html: misfit against wall
// time and against evaluations for each method.
#include <algorithm>
#include <cmath>

#include "sections.h"

namespace rockcal::reports::sections {
namespace {

std::string TracePlot(const CalibrationSummary& rec, bool by_time) {
  double xmax = 0.0, ymin = kInf, ymax = 0.0;
  const double start = rec.misfit_before.penalised ? std::nan("") : rec.misfit_before.value;
  if (start > 0) ymin = ymax = start;
  for (const auto& m : rec.methods)
    for (const auto& e : m.trace) {
      if (e.penalised) continue;
      xmax = std::max(xmax, by_time ? e.elapsed : static_cast<double>(e.index));
      if (e.misfit > 0) ymin = std::min(ymin, e.misfit);
      ymax = std::max(ymax, e.misfit);
    }
  if (!std::isfinite(ymin)) ymin = 1e-3;
  if (!(ymax > 0)) ymax = 1.0;
  const bool log_y = ymax / ymin > 20.0;
  svg::Plot::Options o;
  o.width = 420, o.height = 290, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
  o.log_y = log_y;
  o.title = by_time ? "Misfit against wall time" : "Misfit against evaluations";
  svg::Plot plot(0.0, std::max(xmax, by_time ? 1e-3 : 1.0), log_y ? ymin / 1.5 : 0.0,
                 ymax * (log_y ? 1.5 : 1.08), o);
  plot.Axes(by_time ? "wall time [s]" : "evaluation", log_y ? "misfit (log scale)" : "misfit");
  if (std::isfinite(start))
    plot.HLine(start, "stroke=\"#777\" stroke-dasharray=\"3 3\"", "at the start");
  for (std::size_t m = 0; m < rec.methods.size(); ++m) {
    const auto& mr = rec.methods[m];
    std::vector<double> xs, ys, bx, by;
    double best = kInf;
    for (const auto& e : mr.trace) {
      const double x = by_time ? e.elapsed : e.index;
      if (!e.penalised) xs.push_back(x), ys.push_back(e.misfit);
      if (e.misfit < best) {
        best = e.misfit;
        bx.push_back(x), by.push_back(best);
      }
    }
    if (!bx.empty())
      bx.push_back(by_time ? std::max(mr.wall_seconds, bx.back()) : mr.trace.back().index),
          by.push_back(best);
    const std::string colour = svg::Colour(static_cast<int>(m));
    plot.Points(xs, ys, 2.4, "fill=\"" + colour + "\" fill-opacity=\"0.5\"");
    plot.Steps(bx, by, "stroke=\"" + colour + "\" stroke-width=\"2\"");
  }
  return plot.Svg();
}

}  // namespace

std::string TraceSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  int penalised = 0;
  for (const auto& m : rec.methods)
    for (const auto& e : m.trace) penalised += e.penalised ? 1 : 0;
  std::string s =
      "<p><b>Error against run time.</b> The misfit of every evaluation (dots) and the best so far "
      "(line) for each method, against wall time since the method started and against the number "
      "of "
      "evaluations.";
  if (penalised > 0)
    s += " " + Int(penalised) + " penalised evaluations (failed comparisons) are not drawn.";
  s += "</p><ul class=\"legend\">";
  for (std::size_t m = 0; m < rec.methods.size(); ++m) {
    const std::string colour = svg::Colour(static_cast<int>(m));
    s += LegendItem(Swatch(colour, "line"), rec.methods[m].stage.name() + ": best so far");
    s += LegendItem(Swatch(colour, "point"), rec.methods[m].stage.name() + ": each evaluation");
  }
  s += "</ul><div class=\"figs\">";
  s += Figure(TracePlot(rec, true), "<b>Misfit against wall time</b> since each method started.",
              420);
  s += Figure(TracePlot(rec, false), "<b>Misfit against evaluations.</b>", 420);
  s += "</div>";
  return s;
}

}  // namespace rockcal::reports::sections
