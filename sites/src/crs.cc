#include "rockcal/sites/crs.h"

#include <cmath>

#include "rockcal/sites/gdal_util.h"

namespace rockcal::sites {

bool CrsFromUserInput(const std::string& text, std::string* wkt, std::string* error) {
  gdal::Init();
  gdal::ErrorCapture errors;
  gdal::Srs srs(OSRNewSpatialReference(nullptr));
  if (text.empty() || OSRSetFromUserInput(static_cast<OGRSpatialReferenceH>(srs.get()),
                                          text.c_str()) != OGRERR_NONE) {
    *error = errors.message().empty() ? "not a coordinate reference system GDAL knows"
                                      : errors.message();
    return false;
  }
  *wkt = gdal::WktOf(static_cast<OGRSpatialReferenceH>(srs.get()));
  if (wkt->empty()) {
    *error = "GDAL cannot write it as WKT";
    return false;
  }
  return true;
}

bool SameCrs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  gdal::ErrorCapture errors;
  const gdal::Srs sa = gdal::SrsFromWkt(a), sb = gdal::SrsFromWkt(b);
  if (!sa || !sb) return a == b;
  const char* const options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", nullptr};
  return OSRIsSameEx(static_cast<OGRSpatialReferenceH>(sa.get()),
                     static_cast<OGRSpatialReferenceH>(sb.get()), options) != 0;
}

std::string CrsLabel(const std::string& wkt) {
  if (wkt.empty()) return "none";
  gdal::ErrorCapture errors;
  const gdal::Srs srs = gdal::SrsFromWkt(wkt);
  if (!srs) return "an unreadable CRS";
  const auto h = static_cast<OGRSpatialReferenceH>(srs.get());
  const char* name = OSRGetName(h);
  std::string label = name && *name ? name : "unnamed CRS";
  const char* authority = OSRGetAuthorityName(h, nullptr);
  const char* code = OSRGetAuthorityCode(h, nullptr);
  if (authority && code) label += std::string(" (") + authority + ":" + code + ")";
  return label;
}

std::string CrsUnitMismatch(const std::string& wkt, Units units) {
  if (wkt.empty()) return "";
  gdal::ErrorCapture errors;
  const gdal::Srs srs = gdal::SrsFromWkt(wkt);
  if (!srs) return "";
  const auto h = static_cast<OGRSpatialReferenceH>(srs.get());
  const std::string label = CrsLabel(wkt);
  if (OSRIsGeographic(h)) {
    return "the CRS " + label +
           " is geographic (longitude and latitude in degrees); expected a projected CRS in " +
           (units == Units::kSI ? "metres" : "feet") +
           " (reproject first, with gdalwarp or ogr2ogr -t_srs)";
  }
  char* unit_name = nullptr;
  const double to_metres = OSRGetLinearUnits(h, &unit_name);
  const std::string name = unit_name ? unit_name : "?";
  const double want = LengthToSI(1.0, units);
  // (The US survey foot is within 2e-6 of the international foot.)
  if (std::abs(to_metres / want - 1.0) <= 1e-5) return "";
  return "the CRS " + label + " measures coordinates in " + name + " (" + FormatNumber(to_metres) +
         " m), not in the site's unit (" + LengthUnit(units) + "); expected a CRS in " +
         (units == Units::kSI ? "metres" : "feet") + " or a site whose \"units\" match it";
}

}  // namespace rockcal::sites
