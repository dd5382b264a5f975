// The runout section of report.html: where the rocks stopped.
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

}  // namespace

std::string RunoutSection(const Context& c) {
  const core::Stats& rx = c.stats.runout_x;
  std::vector<double> xs, ys;
  for (const core::RockRecord& r : c.result.rocks)
    if (r.outcome == core::Outcome::kStopped) xs.push_back(r.stop.x()), ys.push_back(r.stop.y());
  std::string s = "<p>" + Int(c.stopped) + " of " + Int(Rocks(c)) + " rocks stopped on the slope";
  if (c.left > 0) {
    std::map<std::string, int> edges;
    for (const core::RockRecord& r : c.result.rocks)
      if (r.outcome == core::Outcome::kLeft) ++edges[ExitEdge(c.scene.grid, r.stop)];
    s += "; " + Int(c.left) + " left it (";
    bool first = true;
    for (const auto& [edge, n] : edges)
      s += (first ? "" : ", ") + Int(n) + " over " + edge, first = false;
    s += ")";
  }
  if (c.timeout > 0)
    s += "; " + Int(c.timeout) + (c.timeout == 1 ? " was" : " were") +
         " still moving at the time limit";
  s += ". Stop positions of the stopped rocks:</p>";
  const core::Stats ry = core::Summarize(ys);
  s += "<table class=\"stats\"><thead><tr><th></th><th colspan=\"2\">stop x</th>";
  const bool lateral = !c.one_cell_wide;
  if (lateral) s += "<th colspan=\"2\">stop y</th>";
  s += "</tr><tr><th></th>" + Th("m") + Th("ft") + (lateral ? Th("m") + Th("ft") : std::string()) +
       "</tr></thead><tbody>";
  const std::vector<double> sorted_y = [&] {
    auto v = ys;
    std::sort(v.begin(), v.end());
    return v;
  }();
  const std::vector<double> sorted_x = [&] {
    auto v = xs;
    std::sort(v.begin(), v.end());
    return v;
  }();
  struct Row {
    const char* name;
    const char* key;
    double x, y;
  };
  const Row rows[] = {
      {"minimum", nullptr, sorted_x.front(), sorted_y.front()},
      {"10th percentile", nullptr, core::Quantile(sorted_x, 0.1), core::Quantile(sorted_y, 0.1)},
      {"mean", "mean", rx.mean, ry.mean},
      {"median (p50)", "p50", rx.p50, ry.p50},
      {"90th percentile", "p90", rx.p90, ry.p90},
      {"95th percentile", "p95", rx.p95, ry.p95},
      {"maximum", "max", rx.max, ry.max}};
  for (const Row& row : rows) {
    s += "<tr><th>" + std::string(row.name) + "</th>" +
         (row.key ? RefCell(Ref("summary.json", std::string("/runout/x_m/") + row.key), row.x,
                            Show(row.x))
                  : Td(Show(row.x), true)) +
         Td(Show(row.x / kFoot), true);
    if (lateral) s += Td(Show(row.y), true) + Td(Show(row.y / kFoot), true);
    s += "</tr>";
  }
  s += "</tbody></table>";
  // Histogram and exceedance curve of stop x.
  s += "<div class=\"figs\">";
  s += Figure(Histogram(xs, "stop x [m]", 1.0 / kFoot, "stop x [ft]", std::nan(""), "",
                        "Histogram of stop x", sorted_x.front()),
              "<b>Stop x</b> of the " + Int(c.stopped) + " stopped rocks.", 300);
  svg::Plot::Options o;
  o.width = 380, o.height = 220, o.left = 48, o.right = 12, o.top = 40, o.bottom = 42;
  o.title = "Share of the released rocks that stopped beyond x";
  svg::Plot plot(sorted_x.front(), sorted_x.back(), 0.0, 100.0, o);
  plot.Axes("x [m]", "rocks beyond x [%]");
  plot.TopAxis(1.0 / kFoot, "x [ft]");
  std::vector<double> px, py;
  const double n = Rocks(c);
  for (std::size_t k = 0; k < sorted_x.size(); ++k) {
    px.push_back(sorted_x[k]), py.push_back(100.0 * (sorted_x.size() - k) / n);
    px.push_back(sorted_x[k]), py.push_back(100.0 * (sorted_x.size() - k - 1) / n);
  }
  plot.Polyline(px, py, "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1.8\"");
  s += Figure(
      plot.Svg(),
      "<b>Runout exceedance:</b> the share of all " + Int(Rocks(c)) +
          " released rocks that stopped beyond x" +
          (c.left + c.timeout > 0 ? " (rocks that left the slope or timed out are not counted)."
                                  : "."),
      380);
  s += "</div>";
  return s;
}

}  // namespace rockcal::reports::sections
