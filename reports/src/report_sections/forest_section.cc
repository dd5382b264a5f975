// The forest section of report.html (docs/physics.md, "Trees"): what the
// stems took from the rocks (the figures of summary.json's "forest"), the
// energy each strike gave a trunk against the stem's capacity, the stems
// struck most, and the observed scars at stems against the heights of the
// strikes on them.
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/reports/forest_outputs.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// Per stem: its strikes' heights and whether a rock broke it.
struct StemStrikes {
  std::vector<double> heights;
  int broken = 0;
};

std::map<int, StemStrikes> StrikesByStem(const core::SimulationResult& result) {
  std::map<int, StemStrikes> by;
  for (const core::RockRecord& r : result.rocks)
    for (const core::TreeStrike& s : r.strikes) {
      StemStrikes& t = by[s.tree];
      t.heights.push_back(s.height);
      t.broken += s.broken;
    }
  return by;
}

// The opening sentence: every figure of summary.json's "forest", as
// ForestSummaryJson writes it.
std::string Figures(const Context& c) {
  const nlohmann::json f = ForestSummaryJson(c.scene, c.result);
  const auto span = [&f](const char* key, const std::string& shown) {
    return RefSpan(Ref("summary.json", std::string("/forest/") + key), f.at(key).get<double>(),
                   shown);
  };
  const auto count = [&f](const char* key) { return Int(f.at(key).get<long>()); };
  const double absorbed = f.at("energy_absorbed_j").get<double>();
  const int rocks = Rocks(c);
  const long struck = f.at("rocks_struck").get<long>();
  return "<p>" + span("stems", count("stems")) + " stems stand on the slope. " +
         span("rocks_struck", count("rocks_struck")) + " of " + Int(rocks) + " rocks (" +
         Percent(rocks > 0 ? static_cast<double>(struck) / rocks : 0.0) + ") struck a stem, " +
         span("strikes", count("strikes")) + " strikes in all; " +
         span("rocks_stopped_after_strike", count("rocks_stopped_after_strike")) +
         " of the rocks that struck a stem stopped on the slope. The trunks took " +
         span("energy_absorbed_j", Int(std::lround(absorbed)) + " J") + " (" +
         Label(absorbed / 1e6, 3) + " MJ) from the rocks, and " + span("breaks", count("breaks")) +
         " strikes broke their stem, " + span("stems_broken", count("stems_broken")) +
         " different stems (a stem broken by one rock stands again for the next). "
         "A rock that struck no stem ran as on a bare slope.</p>";
}

// Energy a strike gave the trunk against the stem's DBH, with the capacity
// curve of each species class at the forest's capacity factor.
std::string EnergyPlot(const Context& c) {
  const core::Forest& forest = c.scene.forest;
  std::vector<double> dbh, kj;
  double dmax = 0.0;
  for (const core::Stem& s : forest.stems) dmax = std::max(dmax, 100.0 * s.dbh);
  for (const core::RockRecord& r : c.result.rocks)
    for (const core::TreeStrike& s : r.strikes) {
      const core::Stem& stem = forest.stems[static_cast<std::size_t>(s.tree)];
      dbh.push_back(100.0 * stem.dbh);
      kj.push_back(s.absorbed / 1e3);
    }
  dmax = std::max(dmax * 1.1, 1.0);
  const double cap_max =
      core::StemCapacity(dmax / 100.0, core::SpeciesClass::kBroadleaf, forest.capacity_factor) /
      1e3;
  double ymax = 0.0;
  for (const double v : kj) ymax = std::max(ymax, v);
  ymax = std::max(1e-3, std::min(1.1 * std::max(ymax, 1e-3), 1.05 * cap_max));
  svg::Plot::Options o;
  o.width = 380, o.height = 240, o.left = 58, o.bottom = 42;
  o.title = "Energy each strike gave the trunk against the stem's diameter";
  svg::Plot plot(0.0, dmax, 0.0, ymax, o);
  plot.Axes("DBH [cm]", "energy absorbed [kJ]");
  const core::SpeciesClass classes[] = {core::SpeciesClass::kConifer,
                                        core::SpeciesClass::kBroadleaf};
  std::vector<svg::Plot::LegendEntry> legend;
  for (int k = 0; k < 2; ++k) {
    std::vector<double> xs, ys;
    for (int i = 1; i <= 60; ++i) {
      const double d = dmax * i / 60.0;
      xs.push_back(d);
      ys.push_back(core::StemCapacity(d / 100.0, classes[k], forest.capacity_factor) / 1e3);
    }
    plot.Polyline(xs, ys,
                  std::string("stroke=\"") + svg::Colour(k + 1) + "\" stroke-width=\"1.5\"" +
                      (k == 1 ? " stroke-dasharray=\"4 3\"" : ""));
    legend.push_back(
        {svg::Colour(k + 1), k == 0 ? "capacity, conifer" : "capacity, broadleaf", "line"});
  }
  plot.Points(dbh, kj, 2.2, "fill=\"#000\" fill-opacity=\"0.45\"");
  legend.push_back({"#000", "a strike", "point"});
  plot.Legend(legend);
  return Figure(plot.Svg(),
                "Energy each strike gave the trunk (its work on the rock, tree_impacts.csv "
                "column <code>absorbed</code>) against the stem's DBH. The curves are the "
                "stems' capacity, Dorren &amp; Berger's (2006) 38.7 DBH<sup>2.31</sup> J times "
                "the class factor and the forest's capacity factor (" +
                    Label(forest.capacity_factor, 3) +
                    "): a strike at the curve broke its stem; one of several strikes on a stem "
                    "stays below it, as the capacity is taken over a rock's strikes together.",
                o.width);
}

// The stems struck most: position, DBH, class, strikes, breaks, heights.
std::string StruckStems(const Context& c, const std::map<int, StemStrikes>& by) {
  std::vector<std::pair<int, const StemStrikes*>> order;
  for (const auto& [stem, s] : by) order.push_back({stem, &s});
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.second->heights.size() > b.second->heights.size();
  });
  const std::size_t shown = std::min<std::size_t>(order.size(), 10);
  const sites::Units units = c.in.units;
  std::string t = "<table><thead><tr>" + Th("stem") + Th("x") + Th("y") + Th("DBH") + Th("class") +
                  Th("strikes") + Th("broken") + Th("strike height, median") +
                  Th("strike height, 90 %") + "</tr></thead><tbody>";
  for (std::size_t k = 0; k < shown; ++k) {
    const core::Stem& stem = c.scene.forest.stems[static_cast<std::size_t>(order[k].first)];
    std::vector<double> h = order[k].second->heights;
    std::sort(h.begin(), h.end());
    t += "<tr>" + Td(Int(order[k].first), true) + Td(SiteLength(stem.x, units), true) +
         Td(SiteLength(stem.y, units), true) + Td(Label(100.0 * stem.dbh, 3) + " cm", true) +
         Td(stem.species == core::SpeciesClass::kConifer ? "conifer" : "broadleaf") +
         Td(Int(static_cast<long>(h.size())), true) + Td(Int(order[k].second->broken), true) +
         Td(SiteLength(core::Quantile(h, 0.5), units), true) +
         Td(SiteLength(core::Quantile(h, 0.9), units), true) + "</tr>";
  }
  t += "</tbody></table>";
  return "<h3>Stems struck most</h3><p>The " + Int(static_cast<long>(shown)) + " of " +
         Int(static_cast<long>(by.size())) +
         " struck stems with the most strikes (every strike in tree_impacts.csv); a strike's "
         "height is its contact point above the stem's foot.</p>" +
         t;
}

// Observed scars at trees that are stems, against the strikes on them.
std::string ScarsAtStems(const Context& c, const std::map<int, StemStrikes>& by) {
  if (!c.in.observations) return "";
  std::string rows;
  const sites::Units units = c.in.units;
  for (const observations::ScarSet& set : c.in.observations->tree_scars)
    for (const observations::Tree& tree : set.trees) {
      if (tree.stem < 0) continue;
      std::vector<double> observed = tree.heights;
      std::sort(observed.begin(), observed.end());
      const auto found = by.find(tree.stem);
      std::vector<double> struck;
      if (found != by.end()) struck = found->second.heights;
      std::sort(struck.begin(), struck.end());
      const auto median = [&](const std::vector<double>& v) {
        return v.empty() ? std::string("-") : SiteLength(core::Quantile(v, 0.5), units);
      };
      rows += "<tr>" + Td(Escape(set.label)) + Td(Int(tree.stem), true) +
              Td(Int(static_cast<long>(observed.size())), true) + Td(median(observed), true) +
              Td(Int(static_cast<long>(struck.size())), true) + Td(median(struck), true) + "</tr>";
    }
  if (rows.empty()) return "";
  return "<h3>Scars at stems against the strikes</h3><p>Each observed tree that is a stem of "
         "the forest is compared with the heights at which rocks struck that stem "
         "(docs/reference/observations-file.md); the misfit pools them per set, as the Fit "
         "section shows.</p><table><thead><tr>" +
         Th("scar set") + Th("stem") + Th("scars") + Th("scar height, median") + Th("strikes") +
         Th("strike height, median") + "</tr></thead><tbody>" + rows + "</tbody></table>";
}

// The runout with the forest against the same rocks on the bare slope
// (rockcal simulate --compare-bare): the summary.json figures of each run.
std::string BareComparison(const Context& c) {
  if (!c.in.bare) return "";
  const core::RunoutStats with = core::ComputeRunout(c.result.rocks);
  const core::RunoutStats without = core::ComputeRunout(c.in.bare->rocks);
  const sites::Units units = c.in.units;
  const auto length = [units](double m) {
    return std::isfinite(m) ? SiteLength(m, units) : std::string("beyond the edge");
  };
  const auto row = [&](const std::string& what, const std::string& a, const std::string& b) {
    return "<tr>" + Td(what) + Td(a, true) + Td(b, true) + "</tr>";
  };
  const auto stopped = [](const core::SimulationResult& r) {
    return Int(r.count(core::Outcome::kStopped)) + " of " + Int(static_cast<long>(r.rocks.size()));
  };
  std::string t = "<table><thead><tr>" + Th("") + Th("with the forest") + Th("bare slope") +
                  "</tr></thead><tbody>";
  t += row("rocks stopped", stopped(c.result), stopped(*c.in.bare));
  t += row("rocks that left the terrain", Int(with.beyond_edge), Int(without.beyond_edge));
  t += row("runout, median", length(with.distance_m.p50), length(without.distance_m.p50));
  t += row("runout, 90 %", length(with.distance_m.p90), length(without.distance_m.p90));
  t += row("runout, 95 %", length(with.distance_m.p95), length(without.distance_m.p95));
  t += row("runout, longest", length(with.distance_m.max), length(without.distance_m.max));
  return "<h3>Runout with and without the forest</h3><p>The same rocks (seed, count and "
         "parameters) run again on the slope without its stems (<code>--compare-bare</code>); "
         "the runout is the plan distance from release to stop "
         "(docs/reference/outputs.md#runout), a rock that left the terrain ranking beyond "
         "every other.</p>" +
         t + "</tbody></table>";
}

}  // namespace

bool HasForestStrikes(const Context& c) {
  return !c.scene.forest.empty() && c.result.strikes_recorded;
}

std::string ForestSection(const Context& c) {
  const std::map<int, StemStrikes> by = StrikesByStem(c.result);
  std::string html = Figures(c) + BareComparison(c);
  if (by.empty()) return html + ScarsAtStems(c, by);
  return html + EnergyPlot(c) + StruckStems(c, by) + ScarsAtStems(c, by);
}

}  // namespace rockcal::reports::sections
