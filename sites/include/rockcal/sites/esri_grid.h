// ESRI ASCII grids (.asc): a raster of elevations, rows from north to south.
#ifndef ROCKCAL_SITES_ESRI_GRID_H_
#define ROCKCAL_SITES_ESRI_GRID_H_

#include <optional>
#include <string>
#include <vector>

#include "rockcal/core/terrain.h"

namespace rockcal::sites {

// The raster as read, in the file's units.
struct EsriGrid {
  int ncols = 0, nrows = 0;
  double x_center = 0.0, y_center = 0.0;  // centre of the south-west (lower-left) cell
  double cellsize = 0.0;
  std::optional<double> nodata;
  // nrows * ncols values, row r (0 = north) at [r * ncols, (r + 1) * ncols).
  std::vector<double> values;

  // Elevation of column i (west to east) and row j counted from the SOUTH;
  // NaN for a NODATA cell.
  double at(int i, int j) const;
};

// Reads an ESRI ASCII grid. Header lines "key value" in any order and case:
// ncols, nrows, xllcorner or xllcenter, yllcorner or yllcenter, cellsize, and
// optionally NODATA_value; then nrows lines of exactly ncols numbers. A bad
// header key or value, a short or long row, a non-number or missing rows are
// InputError "file:LINE: ...".
EsriGrid ReadEsriGrid(const std::string& path);

// Turns the raster into a height grid in SI units: each cell centre is a grid
// node; `length_scale` converts the file's length unit to metres. When
// `spacing` [m] equals the file's cell size (to 1e-9 relative) the nodes are
// the cell centres as they are; otherwise the grid covers the same extent
// (first centre to last centre) at `spacing` and takes bilinear interpolation
// of the four surrounding centres, a hole when any of them that has a
// positive weight is NODATA.
// Material indices are all 0.
core::HeightGrid EsriToHeightGrid(const EsriGrid& grid, double length_scale, double spacing);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_ESRI_GRID_H_
