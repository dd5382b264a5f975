// The maps of a simulation as files a GIS opens: rasters.tif (one GeoTIFF,
// a band per map) and rasters/<band>.asc (ESRI ASCII grids, with a .prj when
// the CRS is known), on the site grid, in the site file's coordinates.
#ifndef ROCKCAL_REPORTS_RASTER_OUTPUTS_H_
#define ROCKCAL_REPORTS_RASTER_OUTPUTS_H_

#include <array>
#include <string>

#include "rockcal/core/rasters.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports {

// Written for every cell without a value (NaN in the RasterSet), in every
// band and file.
inline constexpr double kRasterNodata = -9999.0;

// Where the site grid lies: its CRS and the length unit of its coordinates.
struct RasterFrame {
  // The terrain's CRS as WKT (sites::Site::crs_wkt); empty: unknown, and the
  // files carry none.
  std::string crs_wkt;
  // The site file's units: the coordinates of the files are in its length
  // unit (feet for "us"), as the terrain's were. The values are not: every
  // band keeps its SI unit (RasterBand::unit: energies in kJ, heights in m).
  sites::Units units = sites::Units::kSI;
};
// Where the maps of `site` lie: its CRS and the unit of its coordinates.
RasterFrame SiteRasterFrame(const sites::Site& site);

// The GDAL geotransform of `rasters` in the length unit of `units`: north
// up, origin at the north-west corner of cell (0, ny - 1), a cell of
// `spacing` (converted) square, so {x_west, s, 0, y_north, 0, -s}.
std::array<double, 6> RasterGeoTransform(const core::RasterSet& rasters, sites::Units units);

// The description of `band` in rasters.tif: "<name>: <description> [<unit>]".
std::string RasterBandDescription(const core::RasterBand& band);

// Writes `folder`/rasters.tif (Float32, DEFLATE, one band per RasterSet band
// in its order, each with its description, unit and the nodata value; the
// CRS when known; rows north first) and `folder`/rasters/<band>.asc (same
// values, .prj beside each when the CRS is known). Everything is checked
// before anything is written, and the files appear under their names only
// once complete (temporary names renamed into place; an earlier rasters/ is
// replaced).
//  - A malformed RasterSet (no cells, a band of the wrong size, a band name
//    that is no file name) throws std::logic_error (a programmer error).
//  - A value that is neither finite nor NaN (nodata), or beyond Float32,
//    throws std::runtime_error: an internal failure, nothing written.
//  - A failure of GDAL or of the file system throws std::runtime_error naming
//    the file and the cause; no temporary file is left behind.
void WriteRasterFiles(const std::string& folder, const core::RasterSet& rasters,
                      const RasterFrame& frame);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_RASTER_OUTPUTS_H_
