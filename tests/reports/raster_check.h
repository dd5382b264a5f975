// Reading rasters back with GDAL in the tests of the raster outputs
// (raster_outputs_test.cc, tests/cli/rasters_test.cc): what a GIS sees.
#ifndef ROCKCAL_TESTS_REPORTS_RASTER_CHECK_H_
#define ROCKCAL_TESTS_REPORTS_RASTER_CHECK_H_

#include <cpl_conv.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rockcal/sites/gdal_util.h"

namespace rockcal::testing {

// One band as GDAL reads it: rows north first.
struct ReadBand {
  std::string description, unit;
  bool has_nodata = false;
  double nodata = 0.0;
  GDALDataType type = GDT_Unknown;
  std::vector<double> values;
};

struct ReadRaster {
  bool opened = false;
  int nx = 0, ny = 0;
  std::array<double, 6> transform{};
  bool has_transform = false;
  std::string wkt;  // empty: no CRS
  std::string compression;
  std::string driver;
  std::map<std::string, std::string> metadata;  // the default domain
  std::vector<ReadBand> bands;
};

inline ReadRaster OpenRaster(const std::string& path) {
  GDALAllRegister();
  ReadRaster out;
  const sites::gdal::Dataset dataset(
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!dataset) return out;
  const auto ds = static_cast<GDALDatasetH>(dataset.get());
  out.opened = true;
  out.driver = GDALGetDescription(GDALGetDatasetDriver(ds));
  out.nx = GDALGetRasterXSize(ds);
  out.ny = GDALGetRasterYSize(ds);
  out.has_transform = GDALGetGeoTransform(ds, out.transform.data()) == CE_None;
  if (OGRSpatialReferenceH srs = GDALGetSpatialRef(ds)) {
    char* wkt = nullptr;
    OSRExportToWkt(srs, &wkt);
    out.wkt = wkt ? wkt : "";
    CPLFree(wkt);
  }
  if (const char* c = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE"))
    out.compression = c;
  if (char** md = GDALGetMetadata(ds, nullptr)) {
    for (char** item = md; *item != nullptr; ++item) {
      const std::string kv = *item;
      const std::size_t eq = kv.find('=');
      if (eq != std::string::npos) out.metadata[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
  }
  for (int b = 1; b <= GDALGetRasterCount(ds); ++b) {
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    ReadBand r;
    r.description = GDALGetDescription(band);
    r.unit = GDALGetRasterUnitType(band);
    int has = 0;
    r.nodata = GDALGetRasterNoDataValue(band, &has);
    r.has_nodata = has != 0;
    r.type = GDALGetRasterDataType(band);
    r.values.resize(static_cast<std::size_t>(out.nx) * static_cast<std::size_t>(out.ny));
    EXPECT_EQ(GDALRasterIO(band, GF_Read, 0, 0, out.nx, out.ny, r.values.data(), out.nx, out.ny,
                           GDT_Float64, 0, 0),
              CE_None);
    out.bands.push_back(std::move(r));
  }
  return out;
}

// Whether the CRS of WKT `a` and `b` are the same (both empty: the same).
inline bool SameCrs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  const sites::gdal::Srs sa = sites::gdal::SrsFromWkt(a), sb = sites::gdal::SrsFromWkt(b);
  if (!sa || !sb) return false;
  const char* options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", "CRITERION=EQUIVALENT",
                           nullptr};
  return OSRIsSameEx(static_cast<OGRSpatialReferenceH>(sa.get()),
                     static_cast<OGRSpatialReferenceH>(sb.get()), options) != 0;
}

// The WKT of "EPSG:<code>".
inline std::string EpsgWkt(int code) {
  const sites::gdal::Srs srs(OSRNewSpatialReference(nullptr));
  const auto h = static_cast<OGRSpatialReferenceH>(srs.get());
  EXPECT_EQ(OSRImportFromEPSG(h, code), OGRERR_NONE);
  char* wkt = nullptr;
  OSRExportToWkt(h, &wkt);
  const std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

}  // namespace rockcal::testing

#endif  // ROCKCAL_TESTS_REPORTS_RASTER_CHECK_H_
