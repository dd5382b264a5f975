// One section per partition of report.html: the statistics at the partition
// and histograms of bounce height, speed and kinetic energy.
#include <algorithm>
#include <cmath>

#include "sections.h"

namespace rockcal::reports::sections {
namespace {

std::string StatsRow(const std::string& name, const std::string& key, int p,
                     const core::PartitionStats& ps, bool us) {
  auto pick = [&](const core::Stats& st) {
    if (key == "mean") return st.mean;
    if (key == "p50") return st.p50;
    if (key == "p90") return st.p90;
    if (key == "p95") return st.p95;
    return st.max;
  };
  const std::string base = "/partitions/" + Int(p) + "/";
  const double h = pick(ps.height), v = pick(ps.velocity), e = pick(ps.energy) * 1e-3;
  auto us_cell = [us](double value) { return us ? Td(Show(value), true) : std::string(); };
  return "<tr><th>" + Escape(name) + "</th>" +
         RefCell(Ref("summary.json", base + "height_m/" + key), h, Show(h)) + us_cell(h / kFoot) +
         RefCell(Ref("summary.json", base + "velocity_mps/" + key), v, Show(v)) +
         us_cell(v / kFoot) + RefCell(Ref("summary.json", base + "energy_kj/" + key), e, Show(e)) +
         us_cell(e * 1e3 / kFtTon) + "</tr>";
}

}  // namespace

std::string PartitionSection(const Context& c, int p) {
  const core::Partition& part = c.scene.partitions[static_cast<std::size_t>(p)];
  const core::PartitionStats& ps = c.stats.partitions[static_cast<std::size_t>(p)];
  std::string s =
      "<p>" + Escape(Capitalised(PartitionWhere(part, c.in.units))) + ". " +
      RefSpan(Ref("summary.json", "/partitions/" + Int(p) + "/passed"), ps.passed, Int(ps.passed)) +
      " of " + Int(Rocks(c)) + " released rocks passed it (" +
      Percent(Rocks(c) ? static_cast<double>(ps.passed) / Rocks(c) : 0.0) +
      "). Values when a rock's centre first crossed it: bounce height (rock centre above the "
      "ground "
      "below it), translational speed and kinetic energy (translational plus rotational).</p>";
  const bool us = Us(c);
  const std::string span = us ? " colspan=\"2\"" : "";
  s += "<table class=\"stats\"><thead><tr><th rowspan=\"2\"></th><th" + span +
       ">bounce height</th><th" + span + ">speed</th><th" + span + ">kinetic energy</th></tr><tr>" +
       Th("m") + (us ? Th("ft") : "") + Th("m/s") + (us ? Th("ft/s") : "") + Th("kJ") +
       (us ? Th("ft-tons") : "") + "</tr></thead><tbody>";
  s += StatsRow("mean", "mean", p, ps, us) + StatsRow("median (p50)", "p50", p, ps, us) +
       StatsRow("90th percentile", "p90", p, ps, us) +
       StatsRow("95th percentile", "p95", p, ps, us) + StatsRow("maximum", "max", p, ps, us);
  s += "</tbody></table>";
  if (ps.passed == 0) return s + "<p>No rock crossed this partition: no histograms.</p>";
  std::vector<double> h, v, e;
  for (const core::RockRecord& r : c.result.rocks) {
    if (static_cast<std::size_t>(p) < r.crossings.size() &&
        r.crossings[static_cast<std::size_t>(p)].crossed) {
      const core::Crossing& cr = r.crossings[static_cast<std::size_t>(p)];
      h.push_back(cr.height), v.push_back(cr.speed), e.push_back(cr.energy * 1e-3);
    }
  }
  // The report's fence, or a barrier's own height and capacity.
  const bool line = part.kind == core::Partition::Kind::kLine;
  const double fh = line ? part.height : c.in.options.barrier_height_m;
  const double fe = (line ? part.capacity : c.in.options.barrier_energy_j) * 1e-3;
  s += "<div class=\"figs\">";
  const std::string n = Int(ps.passed) + " rocks at " + Escape(part.id);
  s += Figure(Histogram(h, "bounce height [m]", FeetAxis(c), "bounce height [ft]", fh,
                        "fence " + Label(fh, 3) + " m", "Histogram of bounce height at " + part.id,
                        std::min(0.0, *std::min_element(h.begin(), h.end()))),
              "<b>Bounce height</b>, " + n + "; dashed: the fence height.", 300);
  s += Figure(Histogram(v, "speed [m/s]", FeetAxis(c), "speed [ft/s]", std::nan(""), "",
                        "Histogram of speed at " + part.id),
              "<b>Speed</b>, " + n + ".", 300);
  s += Figure(
      Histogram(e, "kinetic energy [kJ]", Us(c) ? 1e3 / kFtTon : 0.0, "kinetic energy [ft-tons]",
                fe, "fence " + Label(fe, 3) + " kJ", "Histogram of kinetic energy at " + part.id),
      "<b>Kinetic energy</b>, " + n + "; dashed: the fence capacity.", 300);
  s += "</div>";
  return s;
}

}  // namespace rockcal::reports::sections
