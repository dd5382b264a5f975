// Coordinate reference systems of a site, held as WKT strings (GDAL and PROJ
// underneath): the surface's "crs", a raster's own CRS, a zone file's.
#ifndef ROCKCAL_SITES_CRS_H_
#define ROCKCAL_SITES_CRS_H_

#include <string>

#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// Parses `text` as GDAL's OSRSetFromUserInput does ("EPSG:2154", WKT, a PROJ
// string, ...) into WKT. False, with GDAL's reason in *error, when it is not
// a CRS.
bool CrsFromUserInput(const std::string& text, std::string* wkt, std::string* error);

// True when the two CRSs are the same (OSRIsSame, the axis order of the
// data ignored). An empty string (no CRS) is the same only as another empty
// string.
bool SameCrs(const std::string& a, const std::string& b);

// A short label for messages: the CRS's name and, when it has one, its
// authority code, e.g. "RGF93 v1 / Lambert-93 (EPSG:2154)"; "none" for "".
std::string CrsLabel(const std::string& wkt);

// "" when the CRS's horizontal unit is the site's length unit (metre for
// "si"; the international or the US survey foot for "us", to 1e-5); else why
// not: a geographic CRS (degrees), or a projected one in another unit.
// Coordinates are never converted between CRSs or units: they must already
// be in the site's unit.
std::string CrsUnitMismatch(const std::string& wkt, Units units);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_CRS_H_
