// Helpers of the sites tests: small rasters and vector files written with
// GDAL into a test's temporary folder (no binary files in the repository).
#ifndef ROCKCAL_TESTS_SITES_GIS_FILES_H_
#define ROCKCAL_TESTS_SITES_GIS_FILES_H_

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rockcal::sites::testing {

// A raster to write: `values` row 0 the first row of the file (the north
// row for a usual negative pixel height), nx * ny of them.
struct RasterSpec {
  int nx = 0, ny = 0;
  std::array<double, 6> geotransform{0, 1, 0, 0, 0, -1};
  bool georeferenced = true;  // false: no geotransform written
  std::vector<double> values;
  std::optional<double> nodata;
  std::string crs;  // e.g. "EPSG:2154"; "" for none
  GDALDataType type = GDT_Float32;
  int bands = 1;  // every band holds `values` (+ 100 per band after the first)
  std::string driver = "GTiff";
};

inline void WriteRaster(const std::string& path, const RasterSpec& spec) {
  GDALAllRegister();
  GDALDriverH driver = GDALGetDriverByName(spec.driver.c_str());
  ASSERT_NE(driver, nullptr) << spec.driver;
  GDALDatasetH ds =
      GDALCreate(driver, path.c_str(), spec.nx, spec.ny, spec.bands, spec.type, nullptr);
  ASSERT_NE(ds, nullptr) << path;
  if (spec.georeferenced) {
    std::array<double, 6> gt = spec.geotransform;
    ASSERT_EQ(GDALSetGeoTransform(ds, gt.data()), CE_None);
  }
  if (!spec.crs.empty()) {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    ASSERT_EQ(OSRSetFromUserInput(srs, spec.crs.c_str()), OGRERR_NONE) << spec.crs;
    ASSERT_EQ(GDALSetSpatialRef(ds, srs), CE_None);
    OSRRelease(srs);
  }
  for (int b = 1; b <= spec.bands; ++b) {
    std::vector<double> v = spec.values;
    for (double& x : v)
      if (!(spec.nodata && x == *spec.nodata)) x += 100.0 * (b - 1);
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    if (spec.nodata) {
      ASSERT_EQ(GDALSetRasterNoDataValue(band, *spec.nodata), CE_None);
    }
    ASSERT_EQ(GDALRasterIO(band, GF_Write, 0, 0, spec.nx, spec.ny, v.data(), spec.nx, spec.ny,
                           GDT_Float64, 0, 0),
              CE_None);
  }
  GDALClose(ds);
}

// A polygon feature: WKT geometry and the value of the "material" field.
struct ZoneFeature {
  std::string wkt;
  std::string material;
};

// Writes the features into one layer `layer` of a new vector file
// (driver "GPKG", "GeoJSON" or "ESRI Shapefile"), field "material" (string).
inline void WriteZones(
    const std::string& path, const std::vector<ZoneFeature>& features, const std::string& crs = "",
    const std::string& driver_name = "GPKG", const std::string& layer_name = "zones",
    const std::vector<std::pair<std::string, std::vector<ZoneFeature>>>& more_layers = {}) {
  GDALAllRegister();
  GDALDriverH driver = GDALGetDriverByName(driver_name.c_str());
  ASSERT_NE(driver, nullptr) << driver_name;
  GDALDatasetH ds = GDALCreate(driver, path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  ASSERT_NE(ds, nullptr) << path;
  OGRSpatialReferenceH srs = nullptr;
  if (!crs.empty()) {
    srs = OSRNewSpatialReference(nullptr);
    ASSERT_EQ(OSRSetFromUserInput(srs, crs.c_str()), OGRERR_NONE) << crs;
  }
  std::vector<std::pair<std::string, std::vector<ZoneFeature>>> layers = {{layer_name, features}};
  layers.insert(layers.end(), more_layers.begin(), more_layers.end());
  for (const auto& [name, list] : layers) {
    OGRLayerH layer = GDALDatasetCreateLayer(ds, name.c_str(), srs, wkbUnknown, nullptr);
    ASSERT_NE(layer, nullptr);
    OGRFieldDefnH field = OGR_Fld_Create("material", OFTString);
    ASSERT_EQ(OGR_L_CreateField(layer, field, TRUE), OGRERR_NONE);
    OGR_Fld_Destroy(field);
    for (const ZoneFeature& z : list) {
      OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(layer));
      if (!z.material.empty()) OGR_F_SetFieldString(f, 0, z.material.c_str());
      OGRGeometryH g = nullptr;
      char* text = const_cast<char*>(z.wkt.c_str());
      ASSERT_EQ(OGR_G_CreateFromWkt(&text, nullptr, &g), OGRERR_NONE) << z.wkt;
      OGR_F_SetGeometryDirectly(f, g);
      ASSERT_EQ(OGR_L_CreateFeature(layer, f), OGRERR_NONE);
      OGR_F_Destroy(f);
    }
  }
  if (srs) OSRRelease(srs);
  GDALClose(ds);
}

}  // namespace rockcal::sites::testing

#endif  // ROCKCAL_TESTS_SITES_GIS_FILES_H_
