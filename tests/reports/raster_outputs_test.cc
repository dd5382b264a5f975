// rasters.tif and rasters/<band>.asc: what a GIS reads back from a RasterSet
// built by hand (bands, descriptions, nodata, geotransform in the site's
// units, CRS), and nothing half-written on failure.
#include "rockcal/reports/raster_outputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "raster_check.h"

namespace rockcal::reports {
namespace {

namespace fs = std::filesystem;
using rockcal::testing::EpsgWkt;
using rockcal::testing::OpenRaster;
using rockcal::testing::ReadRaster;
using rockcal::testing::SameCrs;
using ::testing::HasSubstr;

// A fresh folder named after the running test.
std::string Folder() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir = ::testing::TempDir() + "/rockcal_raster_outputs_" + info->name() + "_" +
                          std::to_string(::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// 4 x 3 cells of 1 m, node (0, 0) at (100.5, 200.5): the cells cover
// x 100..104, y 200..203. Cell (i, j) of "passages" holds 10 j + i, but
// (3, 2) (the north-east corner) is nodata; "energy_max" holds 0.25 (i + 1)
// where j = 1 and nodata elsewhere.
core::RasterSet HandBuilt() {
  core::RasterSet r;
  r.x0 = 100.5;
  r.y0 = 200.5;
  r.spacing = 1.0;
  r.nx = 4;
  r.ny = 3;
  r.released = 40;
  core::RasterBand passages{"passages", "rocks", "rocks whose centre passed over the cell", {}};
  core::RasterBand energy{"energy_max", "kJ", "largest kinetic energy over the cell", {}};
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i) {
      passages.values.push_back(i == 3 && j == 2 ? NAN : 10.0 * j + i);
      energy.values.push_back(j == 1 ? 0.25 * (i + 1) : NAN);
    }
  }
  r.bands = {passages, energy};
  return r;
}

// The names in folder `dir`, sorted.
std::vector<std::string> Entries(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(RasterOutputs, GeoTiffHasEveryBandDescribedWithNodataCrsAndNorthUpGrid) {
  const std::string dir = Folder();
  const core::RasterSet r = HandBuilt();
  RasterFrame frame;
  frame.crs_wkt = EpsgWkt(2154);
  WriteRasterFiles(dir, r, frame);
  EXPECT_EQ(Entries(dir), (std::vector<std::string>{"rasters", "rasters.tif"}))
      << "no temporary or side file is left";

  const ReadRaster tif = OpenRaster(dir + "/rasters.tif");
  ASSERT_TRUE(tif.opened);
  EXPECT_EQ(tif.driver, "GTiff");
  EXPECT_EQ(tif.compression, "DEFLATE");
  EXPECT_EQ(tif.nx, 4);
  EXPECT_EQ(tif.ny, 3);
  ASSERT_TRUE(tif.has_transform);
  EXPECT_EQ(tif.transform, (std::array<double, 6>{100.0, 1.0, 0.0, 203.0, 0.0, -1.0}));
  EXPECT_TRUE(SameCrs(tif.wkt, frame.crs_wkt)) << tif.wkt;
  EXPECT_EQ(tif.metadata.at("ROCKS_RELEASED"), "40");
  ASSERT_EQ(tif.bands.size(), 2u);
  EXPECT_EQ(tif.bands[0].description, "passages: rocks whose centre passed over the cell [rocks]");
  EXPECT_EQ(tif.bands[1].description, "energy_max: largest kinetic energy over the cell [kJ]");
  EXPECT_EQ(tif.bands[1].unit, "kJ");
  for (const auto& b : tif.bands) {
    EXPECT_EQ(b.type, GDT_Float32) << b.description;
    EXPECT_TRUE(b.has_nodata) << b.description;
    EXPECT_EQ(b.nodata, kRasterNodata) << b.description;
  }
  // Row 0 is the north (j = 2): passages 20, 21, 22, nodata.
  const std::vector<double> passages = {20, 21, 22, kRasterNodata, 10, 11, 12, 13, 0, 1, 2, 3};
  EXPECT_EQ(tif.bands[0].values, passages);
  const double n = kRasterNodata;
  const std::vector<double> energy = {n, n, n, n, 0.25, 0.5, 0.75, 1.0, n, n, n, n};
  EXPECT_EQ(tif.bands[1].values, energy);
}

TEST(RasterOutputs, AsciiGridsHoldTheSameValuesWithHeaderNodataAndPrj) {
  const std::string dir = Folder();
  const core::RasterSet r = HandBuilt();
  RasterFrame frame;
  frame.crs_wkt = EpsgWkt(2154);
  WriteRasterFiles(dir, r, frame);
  EXPECT_EQ(Entries(dir + "/rasters"), (std::vector<std::string>{"energy_max.asc", "energy_max.prj",
                                                                 "passages.asc", "passages.prj"}));
  const ReadRaster tif = OpenRaster(dir + "/rasters.tif");
  ASSERT_EQ(tif.bands.size(), 2u);
  for (std::size_t k = 0; k < r.bands.size(); ++k) {
    const std::string path = dir + "/rasters/" + r.bands[k].name + ".asc";
    std::istringstream text(ReadText(path));
    std::string key;
    double value = 0;
    const std::vector<std::pair<std::string, double>> header = {
        {"ncols", 4},       {"nrows", 3},    {"xllcorner", 100},
        {"yllcorner", 200}, {"cellsize", 1}, {"NODATA_value", kRasterNodata}};
    for (const auto& [want_key, want] : header) {
      text >> key >> value;
      EXPECT_EQ(key, want_key) << path;
      EXPECT_EQ(value, want) << path << " " << key;
    }
    const ReadRaster asc = OpenRaster(path);
    ASSERT_TRUE(asc.opened) << path;
    EXPECT_EQ(asc.driver, "AAIGrid");
    EXPECT_EQ(asc.transform, tif.transform) << path;
    EXPECT_TRUE(SameCrs(asc.wkt, tif.wkt)) << path << ": " << asc.wkt;
    ASSERT_EQ(asc.bands.size(), 1u);
    EXPECT_EQ(asc.bands[0].nodata, kRasterNodata);
    ASSERT_EQ(asc.bands[0].values.size(), tif.bands[k].values.size());
    for (std::size_t c = 0; c < asc.bands[0].values.size(); ++c)
      EXPECT_NEAR(asc.bands[0].values[c], tif.bands[k].values[c],
                  1e-6 * std::fabs(tif.bands[k].values[c]))
          << path << " cell " << c;
  }
}

TEST(RasterOutputs, WithoutCrsTheFilesCarryNone) {
  const std::string dir = Folder();
  WriteRasterFiles(dir, HandBuilt(), RasterFrame{});
  const ReadRaster tif = OpenRaster(dir + "/rasters.tif");
  ASSERT_TRUE(tif.opened);
  EXPECT_EQ(tif.wkt, "");
  EXPECT_EQ(Entries(dir + "/rasters"),
            (std::vector<std::string>{"energy_max.asc", "passages.asc"}));
}

// A "us" site's coordinates are feet: cells of 10 ft (3.048 m), the south-west
// corner at (1000 ft, 2000 ft), 3 rows: the north edge at 2030 ft.
TEST(RasterOutputs, UsSiteGeotransformIsInFeet) {
  core::RasterSet r = HandBuilt();
  r.spacing = 3.048;
  r.x0 = 304.8 + 1.524;
  r.y0 = 609.6 + 1.524;
  const std::array<double, 6> t = RasterGeoTransform(r, sites::Units::kUS);
  const std::array<double, 6> want = {1000.0, 10.0, 0.0, 2030.0, 0.0, -10.0};
  EXPECT_EQ(t, want) << "exactly: no noise of the round trip through metres";
  const std::string dir = Folder();
  RasterFrame frame;
  frame.units = sites::Units::kUS;
  WriteRasterFiles(dir, r, frame);
  const ReadRaster tif = OpenRaster(dir + "/rasters.tif");
  ASSERT_TRUE(tif.has_transform);
  EXPECT_EQ(tif.transform, want);
  const ReadRaster asc = OpenRaster(dir + "/rasters/passages.asc");
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(asc.transform[k], want[k], 1e-6) << k;
  // The values keep their SI units whatever the site's.
  EXPECT_EQ(tif.bands[1].values[4], 0.25);
  EXPECT_THAT(tif.bands[1].description, HasSubstr("[kJ]"));
}

TEST(RasterOutputs, ANonFiniteValueIsAnInternalFailureAndNothingIsWritten) {
  const std::string dir = Folder();
  core::RasterSet r = HandBuilt();
  r.bands[1].values[2 * 4 + 1] = INFINITY;  // cell (1, 2)
  try {
    WriteRasterFiles(dir, r, RasterFrame{});
    ADD_FAILURE() << "expected a std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("internal failure: rasters.tif band energy_max cell (1, 2) "
                                    "is inf"));
  }
  r.bands[1].values[2 * 4 + 1] = 1e300;  // beyond Float32
  EXPECT_THROW(WriteRasterFiles(dir, r, RasterFrame{}), std::runtime_error);
  EXPECT_TRUE(Entries(dir).empty());
  // A malformed set is a programmer error.
  r = HandBuilt();
  r.bands[0].values.pop_back();
  EXPECT_THROW(WriteRasterFiles(dir, r, RasterFrame{}), std::logic_error);
  r = HandBuilt();
  r.bands[0].name = "../passages";
  EXPECT_THROW(WriteRasterFiles(dir, r, RasterFrame{}), std::logic_error);
  EXPECT_TRUE(Entries(dir).empty());
}

TEST(RasterOutputs, AFailedWriteNamesTheFileAndLeavesNothing) {
  const std::string dir = Folder();
  RasterFrame frame;
  frame.crs_wkt = "not a CRS";
  EXPECT_THROW(WriteRasterFiles(dir, HandBuilt(), frame), std::runtime_error);
  EXPECT_TRUE(Entries(dir).empty());
  // A folder that is not there: GDAL cannot create the file.
  try {
    WriteRasterFiles(dir + "/missing", HandBuilt(), RasterFrame{});
    ADD_FAILURE() << "expected a std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot write " + dir + "/missing/rasters.tif"));
  }
  EXPECT_TRUE(Entries(dir).empty());
}

TEST(RasterOutputs, AnEarlierRasterFolderIsReplacedWhole) {
  const std::string dir = Folder();
  fs::create_directories(dir + "/rasters");
  std::ofstream(dir + "/rasters/height_p95.asc") << "old";
  std::ofstream(dir + "/rasters.tif") << "old";
  WriteRasterFiles(dir, HandBuilt(), RasterFrame{});
  EXPECT_EQ(Entries(dir + "/rasters"),
            (std::vector<std::string>{"energy_max.asc", "passages.asc"}));
  EXPECT_TRUE(OpenRaster(dir + "/rasters.tif").opened);
  EXPECT_EQ(Entries(dir), (std::vector<std::string>{"rasters", "rasters.tif"}));
}

}  // namespace
}  // namespace rockcal::reports
