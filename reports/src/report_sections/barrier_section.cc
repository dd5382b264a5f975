// The barrier check of report.html: how many rocks would defeat a fence at
// each partition (docs/reference/outputs.md#barrier-check).
#include "sections.h"

namespace rockcal::reports::sections {

std::string BarrierSection(const Context& c) {
  const double fh = c.in.options.barrier_height_m, fe = c.in.options.barrier_energy_j;
  const ReportOptions defaults;
  const bool by_default = fh == defaults.barrier_height_m && fe == defaults.barrier_energy_j;
  std::string s =
      "<p>A fence <b>" + Escape(Length(fh, c.in.units)) +
      "</b> high with an energy capacity of <b>" + Escape(Energy(fe, c.in.units)) + "</b>" +
      (by_default ? " (rockcal's default; the site file's "
                    "<code>report.barrier_height</code>, in its length units, and "
                    "<code>report.barrier_energy_kj</code> set them)"
                  : " (the site file's <code>report</code>)") +
      ", the same fence checked at each partition: a rock flies over it when its <b>lowest "
      "point</b> is above the fence (its centre's height above the ground less its bounding "
      "radius, the farthest any part of the rock reaches from its centre, so the lowest it "
      "could be in any orientation), and breaks through it when its kinetic energy is above "
      "the capacity. Beside it, the counts by the centre alone (the bounce height) and by the "
      "rock's top (centre plus bounding radius: a rock that reaches the fence's top edge, which "
      "a fence does not catch reliably; the freeboard a designer adds). The 95th percentiles "
      "are the usual design values.</p>";
  s += "<table><thead><tr>" + Th("partition") + Th("passed") + Th("over the fence (lowest point)") +
       Th("centre above the fence") + Th("top above the fence") + Th("energy above capacity") +
       Th("either (fence defeated)") + Th("of all released rocks") +
       Th("p95 bounce height (centre)") + Th("p95 energy") + "</tr></thead><tbody>";
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    // A barrier line is checked by its own height and capacity (the Barriers section).
    if (c.scene.partitions[p].kind == core::Partition::Kind::kLine) continue;
    const core::PartitionStats& ps = c.stats.partitions[p];
    const core::FenceCheck f = core::CheckFence(c.result, p, fh, fe);
    auto share = [&](int n) {
      return f.passed ? Int(n) + " (" + Percent(static_cast<double>(n) / f.passed) + ")"
                      : std::string("-");
    };
    s += "<tr><td><a href=\"#" + Escape(PartitionSectionId(c.scene.partitions[p].id)) + "\">" +
         Escape(c.scene.partitions[p].id) + "</a></td>" + Td(Int(f.passed), true) +
         Td(share(f.over), true) + Td(share(f.over_by_centre), true) +
         Td(share(f.over_by_top), true) + Td(share(f.over_capacity), true) +
         Td(share(f.defeated), true) +
         Td(Percent(Rocks(c) ? static_cast<double>(f.defeated) / Rocks(c) : 0.0), true) +
         Td(ps.passed ? Length(ps.height.p95, c.in.units) : "-", true) +
         Td(ps.passed ? Energy(ps.energy.p95, c.in.units) : "-", true) + "</tr>";
  }
  return s + "</tbody></table>";
}

}  // namespace rockcal::reports::sections
