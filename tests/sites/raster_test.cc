#include "rockcal/sites/raster.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "gis_files.h"
#include "rockcal/sites/esri_grid.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::RasterSpec;
using testing::TempDir;
using testing::WriteRaster;

// 4 x 3 cells of 2 m, north-west corner (1000, 2006): cell centres x 1001 to
// 1007, y 2001 to 2005; value 10 * row + column, row 0 the north row.
RasterSpec Small() {
  RasterSpec r;
  r.nx = 4;
  r.ny = 3;
  r.geotransform = {1000, 2, 0, 2006, 0, -2};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) r.values.push_back(10.0 * row + col);
  return r;
}

TEST(ReadRaster, GeoTiffGivesCentresValuesNodataAndCrs) {
  TempDir dir;
  RasterSpec spec = Small();
  spec.values[1] = -9999;  // north row, column 1
  spec.nodata = -9999;
  spec.crs = "EPSG:2154";
  const std::string path = dir.path() + "/dem.tif";
  WriteRaster(path, spec);
  const RasterFile r = ReadRaster(path);
  EXPECT_EQ(r.driver, "GTiff");
  ASSERT_FALSE(r.files.empty());
  EXPECT_EQ(r.files[0], path);
  EXPECT_EQ(r.grid.ncols, 4);
  EXPECT_EQ(r.grid.nrows, 3);
  EXPECT_DOUBLE_EQ(r.grid.cellsize, 2.0);
  EXPECT_DOUBLE_EQ(r.grid.x_center, 1001.0);
  EXPECT_DOUBLE_EQ(r.grid.y_center, 2001.0);
  EXPECT_DOUBLE_EQ(r.grid.at(0, 0), 20.0);  // south-west: the last row
  EXPECT_DOUBLE_EQ(r.grid.at(3, 2), 3.0);   // north-east
  EXPECT_TRUE(std::isnan(r.grid.at(1, 2)));
  EXPECT_THAT(r.crs_wkt, HasSubstr("Lambert-93"));
}

TEST(ReadRaster, SouthUpRowsAndOtherBands) {
  TempDir dir;
  RasterSpec spec = Small();
  spec.geotransform = {1000, 2, 0, 2000, 0, 2};  // the first row is the south row
  spec.bands = 2;
  const std::string path = dir.path() + "/dem.tif";
  WriteRaster(path, spec);
  RasterFile r = ReadRaster(path);
  EXPECT_DOUBLE_EQ(r.grid.y_center, 2001.0);
  EXPECT_DOUBLE_EQ(r.grid.at(0, 0), 0.0);
  EXPECT_DOUBLE_EQ(r.grid.at(3, 2), 23.0);
  EXPECT_TRUE(r.crs_wkt.empty());
  r = ReadRaster(path, 2);
  EXPECT_DOUBLE_EQ(r.grid.at(3, 2), 123.0);
}

TEST(ReadRaster, GdalReadsAnEsriGridAsTheEsriReaderDoes) {
  TempDir dir;
  const std::string path = dir.Write("dem.asc",
                                     "ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 5\n"
                                     "NODATA_value -1\n1 2 3\n4 -1 6\n");
  const RasterFile gdal = ReadRaster(path);
  const RasterGrid esri = ReadEsriGrid(path);
  EXPECT_EQ(gdal.driver, "AAIGrid");
  ASSERT_EQ(gdal.grid.ncols, esri.ncols);
  ASSERT_EQ(gdal.grid.nrows, esri.nrows);
  EXPECT_DOUBLE_EQ(gdal.grid.x_center, esri.x_center);
  EXPECT_DOUBLE_EQ(gdal.grid.y_center, esri.y_center);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) {
      const double a = gdal.grid.at(i, j), b = esri.at(i, j);
      EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << i << "," << j;
    }
  }
}

TEST(ReadRaster, ErrorsNameTheFileAndWhatWasExpected) {
  TempDir dir;
  const std::string text = dir.Write("notes.txt", "not a raster\n");
  EXPECT_THAT(ErrorOf([&] { ReadRaster(text); }), HasSubstr(text + ": not a raster GDAL can read"));

  auto error_of = [&](const RasterSpec& spec, int band = 1) {
    const std::string path = dir.path() + "/bad.tif";
    std::filesystem::remove(path);
    WriteRaster(path, spec);
    const std::string msg = ErrorOf([&] { ReadRaster(path, band); });
    EXPECT_THAT(msg, HasSubstr(path + ": "));
    return msg;
  };
  RasterSpec spec = Small();
  spec.georeferenced = false;
  EXPECT_THAT(error_of(spec), HasSubstr("has no georeferencing (no geotransform)"));
  spec = Small();
  spec.geotransform = {1000, 2, 0.5, 2006, 0.5, -2};
  EXPECT_THAT(error_of(spec), HasSubstr("rotated rasters are not supported"));
  spec = Small();
  spec.geotransform = {1000, 2, 0, 2006, 0, -3};
  EXPECT_THAT(error_of(spec), HasSubstr("has cells of 2 x 3, not square; expected square cells"));
  spec = Small();
  spec.nodata = -5;
  std::fill(spec.values.begin(), spec.values.end(), -5.0);
  EXPECT_THAT(error_of(spec), HasSubstr("every cell of band 1 is nodata (-5)"));
  EXPECT_THAT(error_of(Small(), 3), HasSubstr("has 1 band(s); band 3 does not exist"));
  spec = Small();
  spec.ny = 1;
  spec.values.resize(4);
  EXPECT_THAT(error_of(spec), HasSubstr("has 4 x 1 cells; expected at least 2 x 2"));
}

}  // namespace
}  // namespace rockcal::sites
