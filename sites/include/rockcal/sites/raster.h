// Rasters of elevations: the one in-memory form of an ESRI ASCII grid and of
// any raster GDAL reads (GeoTIFF first), and its conversion to the site grid.
#ifndef ROCKCAL_SITES_RASTER_H_
#define ROCKCAL_SITES_RASTER_H_

#include <optional>
#include <string>
#include <vector>

#include "rockcal/core/terrain.h"

namespace rockcal::sites {

// A north-up raster with square cells, in the file's units.
struct RasterGrid {
  int ncols = 0, nrows = 0;
  double x_center = 0.0, y_center = 0.0;  // centre of the south-west (lower-left) cell
  double cellsize = 0.0;
  std::optional<double> nodata;
  // nrows * ncols values, row r (0 = north) at [r * ncols, (r + 1) * ncols).
  std::vector<double> values;

  // Elevation of column i (west to east) and row j counted from the SOUTH;
  // NaN for a NODATA (or NaN) cell.
  double at(int i, int j) const;
};

// Turns the raster into a height grid in SI units: each cell centre is a grid
// node; `length_scale` converts the file's length unit to metres. When
// `spacing` [m] equals the file's cell size (to 1e-9 relative) the nodes are
// the cell centres as they are; otherwise the grid covers the same extent
// (first centre to last centre) at `spacing` and takes bilinear interpolation
// of the four surrounding centres, a hole when any of them that has a
// positive weight is NODATA.
// Material indices are all 0.
core::HeightGrid RasterToHeightGrid(const RasterGrid& grid, double length_scale, double spacing);

// A raster read with GDAL.
struct RasterFile {
  RasterGrid grid;                 // nodata cells (and NaN values) are NaN; nodata unset
  std::string crs_wkt;             // the raster's CRS as WKT; empty when it has none
  std::string driver;              // GDAL's short driver name ("GTiff", "AAIGrid", ...)
  std::vector<std::string> files;  // the file and its side files, as GDAL lists them
};

// Reads band `band` (1-based) of the raster at `path` with GDAL: the
// geotransform gives the cell centres, the band's scale and offset (when
// set) apply to the values, the band's nodata value and NaN become NaN.
// Rows may run north to south (the usual) or south to north. Throws
// InputError(path, ...) saying what was expected when the file is not a
// raster GDAL reads, the band does not exist or is complex, the raster has
// no geotransform, a rotated geotransform (not supported), cells that are
// not square or run east to west, fewer than 2 x 2 or more than 1e8 cells,
// or only nodata.
RasterFile ReadRaster(const std::string& path, int band = 1);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_RASTER_H_
