// The barrier check of report.html: how many rocks would defeat a fence at
// each partition.
#include "sections.h"

namespace rockcal::reports::sections {

std::string BarrierSection(const Context& c) {
  const double fh = c.in.options.barrier_height_m, fe = c.in.options.barrier_energy_j;
  std::string s =
      "<p>A fence <b>" + Escape(Length(fh)) + "</b> high with a capacity of <b>" +
      Escape(Show(fe * 1e-3)) + " kJ (" + Escape(Show(fe / kFtTon)) +
      " ft-tons)</b>, checked at each partition: the share of the passing rocks that would fly "
      "over it "
      "(bounce height above the fence) or break through it (kinetic energy above the capacity). "
      "Bounce height is that of the rock centre; add half the rock size for its top. The 95th "
      "percentiles are the usual design values.</p>";
  s += "<table><thead><tr>" + Th("partition") + Th("passed") + Th("height above fence") +
       Th("energy above capacity") + Th("either (fence defeated)") + Th("of all released rocks") +
       Th("p95 bounce height") + Th("p95 energy") + "</tr></thead><tbody>";
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    const core::PartitionStats& ps = c.stats.partitions[p];
    int over_h = 0, over_e = 0, either = 0;
    for (const core::RockRecord& r : c.result.rocks) {
      if (p >= r.crossings.size() || !r.crossings[p].crossed) continue;
      const bool a = r.crossings[p].height > fh, b = r.crossings[p].energy > fe;
      over_h += a, over_e += b, either += (a || b);
    }
    auto share = [&](int n) {
      return ps.passed ? Int(n) + " (" + Percent(static_cast<double>(n) / ps.passed) + ")"
                       : std::string("-");
    };
    s += "<tr><td><a href=\"#" + Escape(PartitionSectionId(c.scene.partitions[p].id)) + "\">" +
         Escape(c.scene.partitions[p].id) + "</a></td>" + Td(Int(ps.passed), true) +
         Td(share(over_h), true) + Td(share(over_e), true) + Td(share(either), true) +
         Td(Percent(Rocks(c) ? static_cast<double>(either) / Rocks(c) : 0.0), true) +
         Td(ps.passed ? Length(ps.height.p95) : "-", true) +
         Td(ps.passed
                ? Show(ps.energy.p95 * 1e-3) + " kJ (" + Show(ps.energy.p95 / kFtTon) + " ft-tons)"
                : "-",
            true) +
         "</tr>";
  }
  return s + "</tbody></table>";
}

}  // namespace rockcal::reports::sections
