// The Barriers section of report.html: what each barrier drawn in plan met,
// by its own height and capacity (docs/reference/outputs.md#barrierscsv).
#include "sections.h"

namespace rockcal::reports::sections {

bool HasBarriers(const core::Scene& scene) {
  for (const core::Partition& p : scene.partitions)
    if (p.kind == core::Partition::Kind::kLine) return true;
  return false;
}

std::string BarriersSection(const Context& c) {
  const std::vector<core::BarrierStats> barriers = core::ComputeBarriers(c.scene, c.result);
  bool stops = false;
  for (const core::BarrierStats& b : barriers)
    stops = stops || c.scene.partitions[b.partition].stops;
  std::string s =
      "<p>Each barrier of the site file (<code>barriers</code>, <code>barriers_file</code>) is a "
      "line in plan with its own height and energy capacity" +
      std::string(HasPlanView(c) ? ", drawn as a solid line on the <a href=\"#plan\">plan "
                                   "view</a>"
                                 : "") +
      ". A rock <b>reaches</b> it where its centre's path crosses the line; it <b>passes "
      "over</b> it when its <b>lowest point</b> there is above the barrier (its centre's height "
      "above the ground less its bounding radius, the lowest any part of the rock could be), and "
      "it <b>exceeds the capacity</b> when its kinetic energy there is above it. Beside it, the "
      "rocks whose centre alone was above the barrier (the bounce height CRSP compares). The "
      "95th and 99th percentiles of the lowest point's and the centre's height above the ground "
      "and of the kinetic energy at the crossing are the values a barrier is sized by. " +
      (stops ? std::string("A barrier that <b>stops</b> ends the run of a rock that reaches it "
                           "below its height and capacity, where it crossed: that rock counts "
                           "as stopped, its runout the distance to the line; a rock over the "
                           "height or the capacity passes on with its energy unchanged. ")
             : std::string()) +
      "<code>barriers.csv</code> and <code>summary.json</code>'s <code>barriers</code> hold "
      "the same figures.</p>";
  s += "<table><thead><tr>" + Th("barrier") + Th("height") + Th("capacity") + Th("stops") +
       Th("reaching") + Th("passing over (lowest point)") + Th("centre above") +
       Th("energy above capacity") + Th("stopped") + Th("lowest point p95 / p99") +
       Th("centre p95 / p99") + Th("energy p95 / p99") + "</tr></thead><tbody>";
  for (const core::BarrierStats& b : barriers) {
    const core::Partition& part = c.scene.partitions[b.partition];
    const int n = b.check.passed;
    auto share = [&](int k) {
      return n ? Int(k) + " (" + Percent(static_cast<double>(k) / n) + ")" : Int(k);
    };
    auto pair = [&](double p95, double p99, bool energy) {
      if (n == 0) return std::string("-");
      return energy ? Energy(p95, c.in.units) + " / " + Energy(p99, c.in.units)
                    : Length(p95, c.in.units) + " / " + Length(p99, c.in.units);
    };
    s +=
        "<tr><td><a href=\"#" + Escape(PartitionSectionId(part.id)) + "\">" + Escape(part.id) +
        "</a></td>" + Td(Length(part.height, c.in.units), true) +
        Td(Energy(part.capacity, c.in.units), true) + Td(part.stops ? "yes" : "no") +
        Td(Int(n) + " (" + Percent(Rocks(c) ? static_cast<double>(n) / Rocks(c) : 0.0) + " of all)",
           true) +
        Td(share(b.check.over), true) + Td(share(b.check.over_by_centre), true) +
        Td(share(b.check.over_capacity), true) +
        Td(part.stops ? share(b.stopped) : std::string("-"), true) +
        Td(pair(b.lowest_p95, b.lowest_p99, false), true) +
        Td(pair(b.centre_p95, b.centre_p99, false), true) +
        Td(pair(b.energy_p95, b.energy_p99, true), true) + "</tr>";
  }
  return s + "</tbody></table>";
}

}  // namespace rockcal::reports::sections
