// Maps of a simulation on the site grid: what a hazard map is drawn from.
#ifndef ROCKCAL_CORE_RASTERS_H_
#define ROCKCAL_CORE_RASTERS_H_

#include <string>
#include <vector>

#include "rockcal/core/simulate.h"

namespace rockcal::core {

// One band: a value per cell, row j = 0 at the SOUTH (smallest y), index
// j * nx + i; NaN where there is no value (nodata).
struct RasterBand {
  std::string name;         // file-safe: "passages", "reach_probability", ...
  std::string unit;         // "rocks", "1", "1/m2", "kJ", "m"
  std::string description;  // one line, for the band's description and the report
  std::vector<double> values;
};

// The site grid's cells: cell (i, j) is centred on grid node (i, j), so the
// rasters have the terrain's nodes as cell centres (an ESRI grid or GeoTIFF
// read at its own resolution comes back with its own geotransform).
struct RasterSet {
  double x0 = 0.0, y0 = 0.0;  // SI: centre of cell (0, 0) = node (0, 0)
  double spacing = 1.0;       // m
  int nx = 0, ny = 0;
  int released = 0;           // rocks simulated
  std::vector<RasterBand> bands;
  // The band named `name`, or nullptr.
  const RasterBand* Find(const std::string& name) const;
};

// The bands, in this order (cells whose node is a hole of the terrain are
// NaN in every band):
//   passages           rocks whose centre passed over the cell (each rock
//                      once): the count a viewer masks the p95 bands by
//   reach_probability  passages / rocks released
//   stop_density       rocks that stopped in the cell / cell area [1/m2]
//   energy_max         largest kinetic energy (translational + rotational) of
//                      a rock over the cell [kJ]; NaN where none passed
//   energy_p95         95th percentile over the rocks that passed of each
//                      rock's largest energy over the cell [kJ]; NaN where none
//   height_max         largest height of a rock's centre above the ground over
//                      the cell [m] (as at partitions); NaN where none passed
//   height_p95         95th percentile, as energy_p95 [m]
//   speed_max          largest speed of a rock's centre over the cell [m/s];
//                      NaN where none passed
//   speed_p95          95th percentile, as energy_p95 [m/s]
//   strikes            only for a scene with a forest whose strikes were
//                      recorded (RecordOptions::tree_strikes): strikes of
//                      rocks on the stems standing in the cell (the cell of
//                      the stem's axis, not of the rock) [strikes]
// Needs a result simulated with RecordOptions::passages
// (SimulationResult::cells_recorded; throws std::logic_error otherwise).
RasterSet ComputeRasters(const Scene& scene, const SimulationResult& result);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_RASTERS_H_
