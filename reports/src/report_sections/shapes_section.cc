// The rock shapes section of report.html: the main results per shape.
#include <cmath>
#include <map>
#include <utility>

#include "rockcal/core/rock_shape.h"
#include "rockcal/core/statistics.h"
#include "sections.h"

namespace rockcal::reports::sections {

std::string ShapesSection(const Context& c) {
  std::map<core::Shape, std::vector<const core::RockRecord*>> by_shape;
  for (const core::RockRecord& r : c.result.rocks) by_shape[r.shape].push_back(&r);
  // One column per shape, one row per quantity.
  std::vector<std::pair<std::string, std::vector<std::string>>> rows;
  auto row = [&](const std::string& name) -> std::vector<std::string>& {
    for (auto& r : rows)
      if (r.first == name) return r.second;
    rows.push_back({name, {}});
    return rows.back().second;
  };
  std::string head = "<tr><th></th>";
  for (const auto& [shape, rocks] : by_shape) {
    head += Th(core::ShapeToString(shape));
    int st = 0, le = 0, to = 0;
    std::vector<core::RockRecord> these;
    for (const auto* r : rocks) {
      if (r->outcome == core::Outcome::kStopped) ++st;
      if (r->outcome == core::Outcome::kLeft) ++le;
      if (r->outcome == core::Outcome::kTimeout) ++to;
      these.push_back(*r);
    }
    const double n = static_cast<double>(rocks.size());
    const core::RunoutStats runout = core::ComputeRunout(these);
    auto distance = [&](double d) {
      return std::isfinite(d) ? Length(d, c.in.units) : std::string("beyond the edge");
    };
    row("rocks").push_back(Int(static_cast<long>(rocks.size())));
    row("stopped").push_back(Int(st) + " (" + Percent(st / n) + ")");
    row("left the slope").push_back(Int(le) + " (" + Percent(le / n) + ")");
    if (c.timeout > 0) row("still moving at the time limit").push_back(Int(to));
    row("median runout distance").push_back(distance(runout.distance_m.p50));
    row("95th percentile runout distance").push_back(distance(runout.distance_m.p95));
    for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
      const std::string& id = c.scene.partitions[p].id;
      std::vector<double> h, e;
      for (const auto* r : rocks)
        if (p < r->crossings.size() && r->crossings[p].crossed)
          h.push_back(r->crossings[p].height), e.push_back(r->crossings[p].energy);
      const core::Stats sh = core::Summarize(h), se = core::Summarize(e);
      row(id + ": passed")
          .push_back(Int(static_cast<long>(h.size())) + " (" + Percent(h.size() / n) + ")");
      row(id + ": 95th percentile bounce height")
          .push_back(h.empty() ? "-" : Length(sh.p95, c.in.units));
      row(id + ": 95th percentile energy").push_back(e.empty() ? "-" : Energy(se.p95, c.in.units));
    }
  }
  std::string s =
      "<p>The main results for each rock shape; runout distances over every rock of the shape, "
      "those that left the terrain beyond its edge (see Runout).</p><table "
      "class=\"stats\"><thead>" +
      head + "</tr></thead><tbody>";
  for (const auto& [name, cells] : rows) {
    s += "<tr><th>" + Escape(name) + "</th>";
    for (const std::string& cell : cells) s += Td(cell, true);
    s += "</tr>";
  }
  return s + "</tbody></table>";
}

}  // namespace rockcal::reports::sections
