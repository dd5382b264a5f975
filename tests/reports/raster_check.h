// Reading rasters back with GDAL in the tests of the raster outputs
// (raster_outputs_test.cc, tests/cli/rasters_test.cc): what a GIS sees.
#ifndef ROCKCAL_TESTS_REPORTS_RASTER_CHECK_H_
#define ROCKCAL_TESTS_REPORTS_RASTER_CHECK_H_

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

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
  std::unique_ptr<GDALDataset, GDALDatasetUniquePtrDeleter> ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) return out;
  out.opened = true;
  out.driver = ds->GetDriver()->GetDescription();
  out.nx = ds->GetRasterXSize();
  out.ny = ds->GetRasterYSize();
  out.has_transform = ds->GetGeoTransform(out.transform.data()) == CE_None;
  if (const OGRSpatialReference* srs = ds->GetSpatialRef()) {
    char* wkt = nullptr;
    srs->exportToWkt(&wkt);
    out.wkt = wkt ? wkt : "";
    CPLFree(wkt);
  }
  if (const char* c = ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE")) out.compression = c;
  if (char** md = ds->GetMetadata()) {
    for (char** item = md; *item != nullptr; ++item) {
      const std::string kv = *item;
      const std::size_t eq = kv.find('=');
      if (eq != std::string::npos) out.metadata[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
  }
  for (int b = 1; b <= ds->GetRasterCount(); ++b) {
    GDALRasterBand* band = ds->GetRasterBand(b);
    ReadBand r;
    r.description = band->GetDescription();
    r.unit = band->GetUnitType();
    int has = 0;
    r.nodata = band->GetNoDataValue(&has);
    r.has_nodata = has != 0;
    r.type = band->GetRasterDataType();
    r.values.resize(static_cast<std::size_t>(out.nx) * static_cast<std::size_t>(out.ny));
    EXPECT_EQ(band->RasterIO(GF_Read, 0, 0, out.nx, out.ny, r.values.data(), out.nx, out.ny,
                             GDT_Float64, 0, 0, nullptr),
              CE_None);
    out.bands.push_back(std::move(r));
  }
  return out;
}

// Whether the CRS of WKT `a` and `b` are the same (both empty: the same).
inline bool SameCrs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  OGRSpatialReference sa, sb;
  if (sa.importFromWkt(a.c_str()) != OGRERR_NONE || sb.importFromWkt(b.c_str()) != OGRERR_NONE)
    return false;
  const char* options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", "CRITERION=EQUIVALENT",
                           nullptr};
  return sa.IsSame(&sb, options) != 0;
}

// The WKT of "EPSG:<code>".
inline std::string EpsgWkt(int code) {
  OGRSpatialReference srs;
  EXPECT_EQ(srs.importFromEPSG(code), OGRERR_NONE);
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  const std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

}  // namespace rockcal::testing

#endif  // ROCKCAL_TESTS_REPORTS_RASTER_CHECK_H_
