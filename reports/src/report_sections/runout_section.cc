// The runout section of report.html: how far every rock went from its own
// release (docs/reference/outputs.md#runout), the rocks that left the
// terrain counted beyond its edge in every figure.
#include <algorithm>
#include <cmath>
#include <map>

#include "rockcal/core/statistics.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// Where a rock that left the slope crossed out: the nearest grid edge, or a hole.
std::string ExitEdge(const core::HeightGrid& g, const Eigen::Vector3d& p) {
  const double s = g.spacing;
  const double d[4] = {p.x() - g.x0, g.x(g.nx - 1) - p.x(), p.y() - g.y0, g.y(g.ny - 1) - p.y()};
  const char* names[4] = {"the x-min edge", "the x-max edge", "the y-min edge", "the y-max edge"};
  int k = static_cast<int>(std::min_element(d, d + 4) - d);
  if (d[k] > s) return "a hole in the terrain data";
  return names[k];
}

// "beyond" for a figure among the rocks that left, as summary.json writes
// it; else the value shown by `show`.
template <typename ShowFn>
std::string BeyondCell(const std::string& pointer, double v, ShowFn show) {
  if (!std::isfinite(v))
    return "<td class=\"n\" data-json=\"" + Escape(Ref("summary.json", pointer)) +
           "\" data-value=\"beyond\">beyond</td>";
  return RefCell(Ref("summary.json", pointer), v, show(v));
}

// The opening sentence: outcomes, and where the rocks that left went out.
std::string Outcomes(const Context& c) {
  std::string s = "<p>" + Int(c.stopped) + " of " + Int(Rocks(c)) + " rocks stopped on the slope";
  if (c.left == 0)
    s += "; " +
         RefSpan(Ref("summary.json", "/runout/beyond_edge"), c.stats.runout.beyond_edge, "0") +
         " left the terrain";
  if (c.left > 0) {
    std::map<std::string, int> edges;
    for (const core::RockRecord& r : c.result.rocks)
      if (r.outcome == core::Outcome::kLeft) ++edges[ExitEdge(c.scene.grid, r.stop)];
    s += "; <b>" +
         RefSpan(Ref("summary.json", "/runout/beyond_edge"), c.stats.runout.beyond_edge,
                 Int(c.left)) +
         " (" + Percent(static_cast<double>(c.left) / Rocks(c)) + ") left the terrain</b> (";
    bool first = true;
    for (const auto& [edge, n] : edges)
      s += (first ? "" : ", ") + Int(n) + " over " + edge, first = false;
    s += "): they went beyond its edge, and every figure below counts them there, past every "
         "rock that stayed";
  }
  if (c.timeout > 0)
    s += "; " + Int(c.timeout) + (c.timeout == 1 ? " was" : " were") +
         " still moving at the time limit (counted where last seen)";
  return s +
         ". The runout of a rock is its distance in plan (x, y) from its centre at release to "
         "its centre where it stopped; its travel angle is the energy-line angle, atan(drop / "
         "plan distance) of its centre from release to stop.</p>";
}

// The share of every released rock that went further than each distance;
// those that left the terrain hold the curve up at their share to the right.
std::string Exceedance(const Context& c, const std::vector<double>& sorted) {
  const double n = Rocks(c);
  const int beyond = c.stats.runout.beyond_edge;
  const double dmax = sorted.empty() ? 1.0 : std::max(sorted.back(), 1e-3);
  svg::Plot::Options o;
  o.width = 380, o.height = 220, o.left = 48, o.right = 12, o.top = Us(c) ? 40 : 14, o.bottom = 42;
  o.title = "Share of the released rocks whose runout exceeds a distance";
  svg::Plot plot(0.0, dmax * (beyond > 0 ? 1.15 : 1.0), 0.0, 100.0, o);
  plot.Axes("runout distance [m]", "rocks beyond [%]");
  plot.TopAxis(FeetAxis(c), "runout distance [ft]");
  std::vector<double> px = {0.0}, py = {100.0};
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    const double above = static_cast<double>(sorted.size() - k) + beyond;
    px.push_back(sorted[k]), py.push_back(100.0 * above / n);
    px.push_back(sorted[k]), py.push_back(100.0 * (above - 1.0) / n);
  }
  const std::string stroke = "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1.8\"";
  plot.Polyline(px, py, stroke);
  if (beyond > 0) {
    const double share = 100.0 * beyond / n;
    plot.Polyline({dmax, plot.xhi()}, {share, share}, stroke + " stroke-dasharray=\"5 3\"");
    plot.Text(plot.right() - 4, plot.Y(share) - 5,
              Int(beyond) + " left: beyond the edge (" + Label(share, 3) + " %)",
              "text-anchor=\"end\" fill=\"" + std::string(kStopColour) + "\" class=\"halo\"");
  }
  std::string cap = "<b>Runout exceedance:</b> the share of all " + Int(Rocks(c)) +
                    " released rocks whose runout distance exceeds each distance";
  if (beyond > 0)
    cap += "; the " + Int(beyond) + " rocks that left the terrain (" +
           Percent(static_cast<double>(beyond) / n) +
           ") went beyond its edge and hold the curve up at their share (dashed): no distance on "
           "this terrain bounds them";
  return Figure(plot.Svg(), cap + ".", 380);
}

}  // namespace

std::string RunoutSection(const Context& c) {
  const core::RunoutStats& ro = c.stats.runout;
  std::vector<double> sorted;
  for (const core::RockRecord& r : c.result.rocks)
    if (r.outcome != core::Outcome::kLeft) sorted.push_back(core::RunoutDistance(r));
  std::sort(sorted.begin(), sorted.end());
  std::string s = Outcomes(c);
  s += "<table class=\"stats\"><thead><tr><th>over all " +
       RefSpan(Ref("summary.json", "/runout/rocks"), ro.rocks, Int(ro.rocks)) + " rocks</th>" +
       Th(Us(c) ? "runout distance" : "runout distance [m]") + Th("travel angle [°]") +
       "</tr></thead><tbody>";
  struct Row {
    const char* name;
    const char* key;
    double distance, angle;
  };
  // The angle's figures are read the other way: the rocks that went furthest
  // have the lowest angles, so the 90th percentile runout pairs with the
  // 10th percentile angle.
  const core::BeyondStats& d = ro.distance_m;
  const core::BeyondStats& a = ro.travel_angle_deg;
  const Row rows[] = {
      {"10th percentile", "p10", d.p10, a.p10}, {"median (p50)", "p50", d.p50, a.p50},
      {"90th percentile", "p90", d.p90, a.p90}, {"95th percentile", "p95", d.p95, a.p95},
      {"maximum", "max", d.max, a.max},         {"minimum", "min", d.min, a.min}};
  auto length = [&](double v) { return Us(c) ? Length(v, c.in.units) : Show(v); };
  auto angle = [](double v) { return Show(v); };
  for (const Row& row : rows) {
    s += "<tr><th>" + std::string(row.name) + "</th>" +
         BeyondCell(std::string("/runout/distance_m/") + row.key, row.distance, length) +
         BeyondCell(std::string("/runout/travel_angle_deg/") + row.key, row.angle, angle) + "</tr>";
  }
  s += "</tbody></table><p class=\"note\">Each column's percentiles are its own: the rocks "
       "that went furthest have the lowest travel angles, so the 10th percentile angle (the "
       "energy line 90 % of the rocks stayed above) pairs with the 90th percentile distance. "
       "&#8220;Beyond&#8221;: the figure falls among the rocks that left the terrain, beyond its "
       "edge (as summary.json writes it).</p>";
  s += "<div class=\"figs\">" + Exceedance(c, sorted) + "</div>";
  return s;
}

}  // namespace rockcal::reports::sections
