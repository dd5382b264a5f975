#include "rockcal/core/rasters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rockcal::core {

const RasterBand* RasterSet::Find(const std::string& name) const {
  for (const RasterBand& b : bands)
    if (b.name == name) return &b;
  return nullptr;
}

RasterSet ComputeRasters(const Scene& scene, const SimulationResult& result) {
  if (!result.cells_recorded)
    throw std::logic_error("ComputeRasters: the simulation did not record the cells (passages)");
  const HeightGrid& g = scene.grid;
  RasterSet set;
  set.x0 = g.x0;
  set.y0 = g.y0;
  set.spacing = g.spacing;
  set.nx = g.nx;
  set.ny = g.ny;
  set.released = static_cast<int>(result.rocks.size());
  const std::size_t n = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  // Each rock's values per cell, gathered by cell.
  std::vector<std::vector<double>> heights(n), energies(n), speeds(n);
  std::vector<double> stops(n, 0.0);
  for (const RockRecord& r : result.rocks) {
    for (const CellVisit& v : r.cells) {
      heights[static_cast<std::size_t>(v.cell)].push_back(v.height);
      energies[static_cast<std::size_t>(v.cell)].push_back(v.energy / 1000.0);
      speeds[static_cast<std::size_t>(v.cell)].push_back(v.speed);
    }
    if (r.outcome != Outcome::kStopped) continue;
    const double fi = std::round((r.stop.x() - g.x0) / g.spacing);
    const double fj = std::round((r.stop.y() - g.y0) / g.spacing);
    if (fi >= 0.0 && fj >= 0.0 && fi < g.nx && fj < g.ny)
      stops[static_cast<std::size_t>(fj * g.nx + fi)] += 1.0;
  }

  set.bands.reserve(10);  // the references below stay valid
  auto band = [&](const char* name, const char* unit, const char* description) -> RasterBand& {
    set.bands.push_back({name, unit, description, std::vector<double>(n, nan)});
    return set.bands.back();
  };
  RasterBand& passages =
      band("passages", "rocks",
           "rocks whose centre passed over the cell: the count behind each cell's p95");
  RasterBand& reach = band("reach_probability", "1", "passages / rocks released");
  RasterBand& stop = band("stop_density", "1/m2", "rocks stopped in the cell / cell area");
  RasterBand& e_max = band("energy_max", "kJ", "largest kinetic energy over the cell");
  RasterBand& e_p95 = band("energy_p95", "kJ",
                           "95th percentile over the rocks of each rock's largest kinetic energy");
  RasterBand& h_max = band("height_max", "m", "largest height of a rock's centre above the ground");
  RasterBand& h_p95 = band("height_p95", "m",
                           "95th percentile over the rocks of each rock's largest centre height");
  RasterBand& v_max = band("speed_max", "m/s", "largest speed of a rock's centre over the cell");
  RasterBand& v_p95 = band("speed_p95", "m/s",
                           "95th percentile over the rocks of each rock's largest centre speed");
  const double area = g.spacing * g.spacing;
  for (std::size_t k = 0; k < n; ++k) {
    if (std::isnan(g.z[k])) continue;  // a hole: no map
    const double count = static_cast<double>(heights[k].size());
    passages.values[k] = count;
    reach.values[k] = set.released > 0 ? count / set.released : 0.0;
    stop.values[k] = stops[k] / area;
    if (heights[k].empty()) continue;
    std::sort(heights[k].begin(), heights[k].end());
    std::sort(energies[k].begin(), energies[k].end());
    e_max.values[k] = energies[k].back();
    e_p95.values[k] = Quantile(energies[k], 0.95);
    h_max.values[k] = heights[k].back();
    h_p95.values[k] = Quantile(heights[k], 0.95);
    std::sort(speeds[k].begin(), speeds[k].end());
    v_max.values[k] = speeds[k].back();
    v_p95.values[k] = Quantile(speeds[k], 0.95);
  }
  // A forest's strikes, in the cell of the stem struck (docs/physics.md, Trees).
  if (!scene.forest.empty() && result.strikes_recorded) {
    std::vector<double> strikes(n, nan);
    for (std::size_t k = 0; k < n; ++k)
      if (!std::isnan(g.z[k])) strikes[k] = 0.0;
    for (const RockRecord& r : result.rocks)
      for (const TreeStrike& s : r.strikes) {
        const Stem& stem = scene.forest.stems[static_cast<std::size_t>(s.tree)];
        const double fi = std::round((stem.x - g.x0) / g.spacing);
        const double fj = std::round((stem.y - g.y0) / g.spacing);
        if (fi < 0.0 || fj < 0.0 || fi >= g.nx || fj >= g.ny) continue;
        double& cell = strikes[static_cast<std::size_t>(fj * g.nx + fi)];
        if (!std::isnan(cell)) cell += 1.0;
      }
    set.bands.push_back({"strikes", "strikes", "strikes of rocks on the stems standing in the cell",
                         std::move(strikes)});
  }
  return set;
}

}  // namespace rockcal::core
