// ESRI ASCII grids (.asc): a raster of elevations, rows from north to south,
// read line by line so that every error names its line (GDAL reads them too,
// through the "raster" surface, but without line numbers).
#ifndef ROCKCAL_SITES_ESRI_GRID_H_
#define ROCKCAL_SITES_ESRI_GRID_H_

#include <string>

#include "rockcal/sites/raster.h"

namespace rockcal::sites {

// Reads an ESRI ASCII grid. Header lines "key value" in any order and case:
// ncols, nrows, xllcorner or xllcenter, yllcorner or yllcenter, cellsize, and
// optionally NODATA_value; then nrows lines of exactly ncols numbers. A bad
// header key or value, a short or long row, a non-number or missing rows are
// InputError "file:LINE: ...".
RasterGrid ReadEsriGrid(const std::string& path);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_ESRI_GRID_H_
