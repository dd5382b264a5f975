#include "sections.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace rockcal::reports::sections {

std::string Int(long v) { return std::to_string(v); }

bool HasPlanView(const Context& c) {
  return !c.one_cell_wide && c.scene.grid.nx >= 2 && c.scene.grid.ny >= 2;
}

const char* KindName(core::Partition::Kind kind) {
  return kind == core::Partition::Kind::kX ? "X" : kind == core::Partition::Kind::kZ ? "Z" : "line";
}

std::string PartitionWhere(const core::Partition& p, sites::Units units) {
  if (p.kind == core::Partition::Kind::kX)
    return "X partition: the vertical plane x = " + Coordinate(p.value, units);
  if (p.kind == core::Partition::Kind::kZ)
    return "Z partition: where the ground is at elevation " + Coordinate(p.value, units);
  return "Barrier: a " + html::PartitionPlace(p, units) + ", " + Length(p.height, units) +
         " high, capacity " + Energy(p.capacity, units) +
         (p.stops ? ", stops the rocks it catches" : "");
}

std::string DrawBandsTable(const std::vector<calibrate::DrawBand>& bands) {
  std::string s = "<table><thead><tr>" + Th("where") + Th("quantity") + Th("unit") + Th("5 %") +
                  Th("median") + Th("95 %") + "</tr></thead><tbody>";
  for (const calibrate::DrawBand& b : bands)
    s += "<tr>" + Td(Escape(b.where)) + Td(Escape(b.quantity)) + Td(Escape(b.unit)) +
         Td(FormatNumber(b.p05, "%.4g"), true) + Td(FormatNumber(b.median, "%.4g"), true) +
         Td(FormatNumber(b.p95, "%.4g"), true) + "</tr>";
  return s + "</tbody></table>";
}

std::string SiteLength(double m, sites::Units units) { return Length(m, units); }

bool Us(const Context& c) { return c.in.units == sites::Units::kUS; }

double FeetAxis(const Context& c) { return Us(c) ? 1.0 / kFoot : 0.0; }

std::string Capitalised(std::string s) {
  if (!s.empty() && s[0] >= 'a' && s[0] <= 'z') s[0] = static_cast<char>(s[0] - 'a' + 'A');
  return s;
}

int Rocks(const Context& c) { return static_cast<int>(c.result.rocks.size()); }

std::vector<const core::RockRecord*> SpreadSample(const std::vector<const core::RockRecord*>& rocks,
                                                  int max) {
  if (static_cast<int>(rocks.size()) <= max) return rocks;
  std::vector<int> counts;  // runs of one group, in rock order
  for (std::size_t k = 0; k < rocks.size(); ++k) {
    if (k == 0 || rocks[k]->group != rocks[k - 1]->group) counts.push_back(0);
    ++counts.back();
  }
  std::vector<const core::RockRecord*> out;
  for (int k : core::SpreadOverGroups(counts, max))
    out.push_back(rocks[static_cast<std::size_t>(k)]);
  return out;
}

std::string PerGroup(const std::vector<const core::RockRecord*>& rocks) {
  std::map<int, int> n;
  for (const core::RockRecord* r : rocks) ++n[r->group];
  std::string s;
  for (const auto& [group, count] : n)
    s += (s.empty() ? "" : ", ") + Int(count) + " of group " + Int(group + 1);
  return s;
}

Context MakeContext(const ReportInput& in) {
  if (!in.scene || !in.result)
    throw std::invalid_argument("HtmlReport: scene and result are required");
  std::string error;
  if (!in.options.IsValid(&error)) throw std::invalid_argument("HtmlReport: " + error);
  Context c{in, *in.scene, *in.result, core::ComputeStats(*in.scene, *in.result)};
  const core::HeightGrid& g = c.scene.grid;
  c.one_cell_wide = g.nx <= 2 || g.ny <= 2;
  std::set<core::Shape> shapes;
  for (const auto& grp : c.scene.groups) shapes.insert(grp.shape);
  c.several_shapes = shapes.size() > 1;
  c.stopped = c.result.count(core::Outcome::kStopped);
  c.left = c.result.count(core::Outcome::kLeft);
  c.timeout = c.result.count(core::Outcome::kTimeout);
  for (double z : g.z)
    if (std::isfinite(z)) c.zmin = std::min(c.zmin, z), c.zmax = std::max(c.zmax, z);
  if (!(c.zmax >= c.zmin)) c.zmin = 0.0, c.zmax = 1.0;
  if (c.zmax == c.zmin) c.zmax = c.zmin + 1.0;
  if (in.rasters && (in.rasters->nx != g.nx || in.rasters->ny != g.ny))
    throw std::invalid_argument("HtmlReport: the rasters are not on the scene's grid");
  if (in.rasters)  // not owned
    c.rasters = std::shared_ptr<const core::RasterSet>(std::shared_ptr<void>(), in.rasters);
  else if (c.result.cells_recorded)
    c.rasters = std::make_shared<const core::RasterSet>(core::ComputeRasters(c.scene, c.result));
  return c;
}

std::string Swatch(const std::string& colour, const std::string& kind) {
  std::string s =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"18\" height=\"12\" viewBox=\"0 0 18 12\">";
  if (kind == "line")
    s +=
        "<line x1=\"1\" y1=\"6\" x2=\"17\" y2=\"6\" stroke=\"" + colour + "\" stroke-width=\"2\"/>";
  else if (kind == "dash")
    s += "<line x1=\"1\" y1=\"6\" x2=\"17\" y2=\"6\" stroke=\"" + colour +
         "\" stroke-width=\"2\" stroke-dasharray=\"4 2\"/>";
  else if (kind == "point")
    s += "<circle cx=\"9\" cy=\"6\" r=\"3\" fill=\"" + colour + "\"/>";
  else if (kind == "ring")
    s += "<circle cx=\"9\" cy=\"6\" r=\"4\" fill=\"none\" stroke=\"" + colour +
         "\" stroke-width=\"1.5\"/>";
  else if (kind == "cross")
    s += "<path d=\"M5 2L13 10M13 2L5 10\" stroke=\"" + colour + "\" stroke-width=\"1.5\"/>";
  else if (kind == "zone")
    s += "<rect x=\"1\" y=\"1\" width=\"16\" height=\"10\" fill=\"" + colour +
         "\" fill-opacity=\"0.3\" stroke=\"" + colour + "\" stroke-width=\"1.5\"/>";
  else
    s += "<rect x=\"1\" y=\"1\" width=\"16\" height=\"10\" fill=\"" + colour +
         "\" stroke=\"#999\" stroke-width=\"0.5\"/>";
  return s + "</svg>";
}

std::string LegendItem(const std::string& swatch, const std::string& label) {
  return "<li>" + swatch + " " + Escape(label) + "</li>";
}

std::string Histogram(const std::vector<double>& values, const std::string& x_label,
                      double top_scale, const std::string& top_label, double mark,
                      const std::string& mark_label, const std::string& title, double xmin_hint) {
  if (values.empty()) return "";
  double lo = std::min(xmin_hint, *std::min_element(values.begin(), values.end()));
  double hi = *std::max_element(values.begin(), values.end());
  if (std::isfinite(mark) && mark > hi && mark < 2.0 * hi + 1e-12) hi = mark;
  if (!(hi > lo)) hi = lo + (lo != 0 ? std::fabs(lo) * 0.1 : 1.0);
  const int bins = std::clamp(
      static_cast<int>(std::ceil(std::sqrt(static_cast<double>(values.size())) * 1.5)), 6, 24);
  const double step = svg::NiceStep(hi - lo, bins);
  const double start = std::floor(lo / step) * step;
  int n = static_cast<int>(std::ceil((hi - start) / step - 1e-9));
  n = std::max(n, 1);
  if (start + n * step <= hi) ++n;
  std::vector<double> edges, counts(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k <= n; ++k) edges.push_back(start + k * step);
  for (double v : values) {
    const int k = std::clamp(static_cast<int>(std::floor((v - start) / step)), 0, n - 1);
    counts[static_cast<std::size_t>(k)] += 1.0;
  }
  const double cmax = *std::max_element(counts.begin(), counts.end());
  svg::Plot::Options o;
  o.width = 300, o.height = 220, o.left = 48, o.right = 12, o.top = 40, o.bottom = 42;
  o.title = title;
  svg::Plot plot(edges.front(), edges.back(), 0.0, cmax * 1.12, o);
  plot.Axes(x_label, "rocks");
  plot.TopAxis(top_scale, top_label);
  plot.Bars(edges, counts, "#6b8fb3");
  if (std::isfinite(mark) && mark <= edges.back()) {
    plot.VLine(mark,
               "stroke=\"" + std::string(kFenceColour) +
                   "\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"",
               mark_label);
  } else if (std::isfinite(mark)) {
    plot.Text(plot.right() - 4, plot.top() + 12, mark_label + " beyond the axis \u2192",
              "text-anchor=\"end\" fill=\"" + std::string(kFenceColour) + "\" class=\"halo\"");
  }
  return plot.Svg();
}

}  // namespace rockcal::reports::sections
