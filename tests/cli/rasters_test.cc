// rockcal simulate/calibrate --rasters (issue 16): rasters.tif and
// rasters/<band>.asc on the grid of the DEM the site was read from, with its
// CRS, read back with GDAL as a GIS reads them; the passages checked against
// the partition crossings of rocks.csv on a scene where they must agree.
#include <gdal.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../reports/raster_check.h"
#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using rockcal::testing::EpsgWkt;
using rockcal::testing::OpenRaster;
using rockcal::testing::ReadRaster;
using rockcal::testing::SameCrs;
using testing::Example;
using testing::FreshDir;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

constexpr double kNodata = -9999.0;

// The DEM: 44 x 14 cells of 1 m in RGF93 / Lambert-93 (EPSG:2154), north-west
// corner at (700000, 6600014); a plane falling 30 degrees to the east; a
// border one cell wide of nodata all round.
constexpr int kCols = 44, kRows = 14;
constexpr double kWest = 700000.0, kNorth = 6600014.0;

// The x (y) of the centre of DEM column c (row r, 0 = north).
double ColumnX(int c) { return kWest + c + 0.5; }
double RowY(int r) { return kNorth - r - 0.5; }

void WriteDem(const std::string& path) {
  GDALAllRegister();
  GDALDriverH gtiff = GDALGetDriverByName("GTiff");
  ASSERT_NE(gtiff, nullptr);
  const sites::gdal::Dataset dataset(
      GDALCreate(gtiff, path.c_str(), kCols, kRows, 1, GDT_Float32, nullptr));
  ASSERT_TRUE(dataset);
  const auto ds = static_cast<GDALDatasetH>(dataset.get());
  double transform[6] = {kWest, 1.0, 0.0, kNorth, 0.0, -1.0};
  GDALSetGeoTransform(ds, transform);
  GDALSetProjection(ds, EpsgWkt(2154).c_str());
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  GDALSetRasterNoDataValue(band, kNodata);
  std::vector<float> z(static_cast<std::size_t>(kCols) * kRows);
  const double fall = std::tan(std::acos(-1.0) / 6.0);  // 30 degrees
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) {
      const bool border = r == 0 || c == 0 || r == kRows - 1 || c == kCols - 1;
      z[static_cast<std::size_t>(r) * kCols + c] =
          border ? static_cast<float>(kNodata) : static_cast<float>(100.0 - fall * (c + 0.5));
    }
  ASSERT_EQ(
      GDALRasterIO(band, GF_Write, 0, 0, kCols, kRows, z.data(), kCols, kRows, GDT_Float32, 0, 0),
      CE_None);
}

// Spheres released at rest at the centres of DEM cells, on a smooth plane
// (roughness 0): each rolls straight down the slope (east) along the middle
// of its row of cells. The partition X20 is the plane through the centres of
// column 20. Two rocks start at row 9 and three at row 6, upslope of it; two
// at row 3 start downslope of it and never reach it.
constexpr int kColumn = 20;
// With `forest`, stems of 30 cm stand on the middle of rows 9 and 6 (in the
// rocks' way, columns 12 and 16) and of row 3 at column 12 (upslope of the
// rocks released there: never struck).
constexpr int kStems[3][2] = {{12, 9}, {16, 6}, {12, 3}};
std::string SiteJson(bool forest = false) {
  nlohmann::json rocks = nlohmann::json::array();
  for (const auto& [count, c, r] :
       std::vector<std::array<int, 3>>{{2, 4, 9}, {3, 4, 6}, {2, 30, 3}})
    rocks.push_back({{"count", count},
                     {"shape", "sphere"},
                     {"size", 0.5},
                     {"unit_weight", 26},
                     {"release", {{"point", nlohmann::json::array({ColumnX(c), RowY(r)})}}}});
  const nlohmann::json site = {
      {"name", "GIS plane"},
      {"units", "si"},
      {"surface", {{"raster", "dem.tif"}, {"sphere_spacing", 1}}},
      {"materials", nlohmann::json::array({{{"id", "rock"}, {"hardness", 0.5}, {"roughness", 0}}})},
      {"partitions", nlohmann::json::array({{{"id", "X20"}, {"x", ColumnX(kColumn)}}})},
      {"rocks", rocks},
      {"simulation", {{"seed", 1}, {"max_time", 20}}}};
  if (!forest) return site.dump(2);
  nlohmann::json with = site;
  for (const auto& [c, r] : kStems)
    with["forest"]["trees"].push_back({{"x", ColumnX(c)}, {"y", RowY(r)}, {"dbh_cm", 30}});
  return with.dump(2);
}

// A folder with dem.tif and site.json; returns the site file.
std::string WriteGisSite(const std::string& name, bool forest = false) {
  const std::string dir = FreshDir(name);
  fs::create_directories(dir);
  WriteDem(dir + "/dem.tif");
  std::ofstream(dir + "/site.json") << SiteJson(forest);
  return dir + "/site.json";
}

// The values of column `column` of rocks.csv, by row.
std::vector<std::string> CsvColumn(const std::string& csv, const std::string& column) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) header.push_back(f);
  }
  const auto at = std::find(header.begin(), header.end(), column);
  EXPECT_NE(at, header.end()) << column << " not in " << line;
  std::vector<std::string> out;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
    while (fields.size() < header.size()) fields.push_back("");  // empty trailing fields
    out.push_back(fields[static_cast<std::size_t>(at - header.begin())]);
  }
  return out;
}

const rockcal::testing::ReadBand* Band(const ReadRaster& r, const std::string& name) {
  for (const auto& b : r.bands)
    if (b.description.rfind(name + ":", 0) == 0) return &b;
  return nullptr;
}

TEST(Rasters, SimulateWritesTheMapsOnTheDemGridWithItsCrs) {
  const std::string site = WriteGisSite("site");
  const std::string out = FreshDir("out");
  const RunResult run = Rockcal("simulate " + site + " --rasters --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("rasters.tif, rasters/*.asc"));

  const ReadRaster dem = OpenRaster(fs::path(site).parent_path().string() + "/dem.tif");
  const ReadRaster tif = OpenRaster(out + "/rasters.tif");
  ASSERT_TRUE(tif.opened);
  EXPECT_EQ(tif.nx, kCols);
  EXPECT_EQ(tif.ny, kRows);
  ASSERT_TRUE(tif.has_transform);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(tif.transform[k], dem.transform[k], 1e-6) << k;
  EXPECT_FALSE(dem.wkt.empty());
  EXPECT_TRUE(SameCrs(tif.wkt, dem.wkt)) << tif.wkt;
  EXPECT_EQ(tif.compression, "DEFLATE");
  const std::vector<std::string> names = {"passages",   "reach_probability", "stop_density",
                                          "energy_max", "energy_p95",        "height_max",
                                          "height_p95", "speed_max",         "speed_p95"};
  ASSERT_EQ(tif.bands.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(tif.bands[k].description.rfind(names[k] + ": ", 0), 0u) << tif.bands[k].description;
    EXPECT_EQ(tif.bands[k].type, GDT_Float32);
    EXPECT_TRUE(tif.bands[k].has_nodata);
    EXPECT_EQ(tif.bands[k].nodata, kNodata);
  }
  EXPECT_THAT(Band(tif, "energy_max")->description, HasSubstr("[kJ]"));
  EXPECT_THAT(Band(tif, "height_max")->description, HasSubstr("[m]"));
  EXPECT_THAT(Band(tif, "speed_p95")->description, HasSubstr("[m/s]"));
  EXPECT_THAT(Band(tif, "reach_probability")->description, HasSubstr("[1]"));

  // Where the DEM has no data, neither have the maps.
  const auto& passages = Band(tif, "passages")->values;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) {
      const bool border = r == 0 || c == 0 || r == kRows - 1 || c == kCols - 1;
      EXPECT_EQ(passages[static_cast<std::size_t>(r * kCols + c)] == kNodata, border)
          << "row " << r << " column " << c;
    }
  // The column of cells the partition runs through: the rocks that crossed
  // it, each in the cell of its row.
  const std::vector<std::string> crossed = CsvColumn(ReadFile(out + "/rocks.csv"), "X20.height_m");
  ASSERT_EQ(crossed.size(), 7u);
  int crossings = 0;
  for (const std::string& v : crossed) crossings += v.empty() ? 0 : 1;
  EXPECT_EQ(crossings, 5);
  double column_sum = 0.0;
  for (int r = 1; r + 1 < kRows; ++r) {
    const double n = passages[static_cast<std::size_t>(r * kCols + kColumn)];
    column_sum += n;
    EXPECT_EQ(n, r == 9 ? 2.0 : r == 6 ? 3.0 : 0.0) << "row " << r;
  }
  EXPECT_EQ(column_sum, crossings);
  const auto& reach = Band(tif, "reach_probability")->values;
  EXPECT_NEAR(reach[static_cast<std::size_t>(6 * kCols + kColumn)], 3.0 / 7.0, 1e-7);
  EXPECT_EQ(tif.metadata.at("ROCKS_RELEASED"), "7");
}

TEST(Rasters, AsciiGridsMatchTheGeoTiff) {
  const std::string site = WriteGisSite("site");
  const std::string out = FreshDir("out");
  const RunResult run = Rockcal("simulate " + site + " --rasters --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  const ReadRaster tif = OpenRaster(out + "/rasters.tif");
  ASSERT_EQ(tif.bands.size(), 9u);
  for (const auto& band : tif.bands) {
    const std::string name = band.description.substr(0, band.description.find(':'));
    const std::string path = out + "/rasters/" + name + ".asc";
    std::istringstream header(ReadFile(path));
    const std::vector<std::pair<std::string, double>> want = {
        {"ncols", kCols},     {"nrows", kRows},
        {"xllcorner", kWest}, {"yllcorner", kNorth - kRows},
        {"cellsize", 1},      {"NODATA_value", kNodata}};
    for (const auto& [want_key, want_value] : want) {
      std::string key;
      double value = 0.0;
      header >> key >> value;
      EXPECT_EQ(key, want_key) << path;
      EXPECT_EQ(value, want_value) << path << " " << key;
    }
    EXPECT_TRUE(fs::exists(out + "/rasters/" + name + ".prj")) << "the CRS is known";
    const ReadRaster asc = OpenRaster(path);
    ASSERT_TRUE(asc.opened) << path;
    EXPECT_TRUE(SameCrs(asc.wkt, tif.wkt)) << path;
    ASSERT_EQ(asc.bands.size(), 1u);
    ASSERT_EQ(asc.bands[0].values.size(), band.values.size());
    for (std::size_t c = 0; c < band.values.size(); ++c)
      ASSERT_NEAR(asc.bands[0].values[c], band.values[c], 1e-6 * std::fabs(band.values[c]))
          << path << " cell " << c;
  }
}

// #52: a site with a forest adds the band "strikes": each stem's strikes
// (tree_impacts.csv's rows for it) in the cell of its axis, 0 in the other
// cells. The bare site above has no such band.
TEST(Rasters, AForestAddsItsStrikesPerCell) {
  const std::string site = WriteGisSite("site", true);
  const std::string out = FreshDir("out");
  const RunResult run = Rockcal("simulate " + site + " --rasters --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  const ReadRaster tif = OpenRaster(out + "/rasters.tif");
  ASSERT_EQ(tif.bands.size(), 10u);
  const rockcal::testing::ReadBand* band = Band(tif, "strikes");
  ASSERT_NE(band, nullptr);
  EXPECT_THAT(band->description, HasSubstr("[strikes]"));
  const std::vector<std::string> trees = CsvColumn(ReadFile(out + "/tree_impacts.csv"), "tree");
  std::vector<double> per_stem(3, 0.0);
  for (const std::string& t : trees) per_stem.at(static_cast<std::size_t>(std::stoi(t))) += 1.0;
  EXPECT_GT(per_stem[0], 0.0) << "the rocks of row 9 roll into the stem";
  EXPECT_GT(per_stem[1], 0.0) << "the rocks of row 6 roll into the stem";
  EXPECT_EQ(per_stem[2], 0.0) << "no rock reaches row 3's stem";
  double total = 0.0;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c) {
      const double v = band->values[static_cast<std::size_t>(r * kCols + c)];
      const bool border = r == 0 || c == 0 || r == kRows - 1 || c == kCols - 1;
      if (border) {
        EXPECT_EQ(v, kNodata) << "row " << r << " column " << c;
        continue;
      }
      double want = 0.0;
      for (int k = 0; k < 3; ++k)
        if (kStems[k][0] == c && kStems[k][1] == r) want = per_stem[static_cast<std::size_t>(k)];
      EXPECT_EQ(v, want) << "row " << r << " column " << c;
      total += v;
    }
  EXPECT_EQ(total, static_cast<double>(trees.size()));
  EXPECT_TRUE(fs::exists(out + "/rasters/strikes.asc"));
}

TEST(Rasters, OnByDefaultForAGisSiteOnlyAndSaidSo) {
  const std::string site = WriteGisSite("site");
  const std::string out = FreshDir("gis");
  RunResult run = Rockcal("simulate " + site + " --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::exists(out + "/rasters.tif"));
  EXPECT_TRUE(fs::exists(out + "/rasters/passages.asc"));
  EXPECT_THAT(run.out, HasSubstr("on by default for a site read from GIS files"));

  const std::string plain = FreshDir("plain");
  run = Rockcal("simulate " + Example("profile2d") + " --rocks 2 --out " + plain);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_FALSE(fs::exists(plain + "/rasters.tif"));
  EXPECT_FALSE(fs::exists(plain + "/rasters"));
  EXPECT_THAT(run.out, Not(HasSubstr("rasters")));
}

// The bundled GIS example (a GeoTIFF DEM and a GeoPackage of zones in
// EPSG:2154): its maps come back on the DEM's own cells, in its CRS, and the
// rocks that stopped are counted on the terrain.
TEST(Rasters, TheGisExampleMapsOnItsDemCells) {
  const std::string out = FreshDir("authume_gis");
  const RunResult run =
      Rockcal("simulate " + Example("authume_gis") + " --rocks 8 --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  const ReadRaster dem =
      OpenRaster(std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/authume_gis/dem.tif");
  const ReadRaster maps = OpenRaster(out + "/rasters.tif");
  ASSERT_TRUE(dem.opened && maps.opened);
  EXPECT_EQ(maps.nx, dem.nx);
  EXPECT_EQ(maps.ny, dem.ny);
  for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(maps.transform[k], dem.transform[k]) << k;
  EXPECT_TRUE(SameCrs(maps.wkt, EpsgWkt(2154)));
  ASSERT_EQ(maps.bands.size(), 9u);
  // Passages, reach and stops: nodata exactly where the DEM has none; the
  // energies and heights also where no rock passed.
  const auto& passages = maps.bands[0].values;
  for (std::size_t b = 0; b < maps.bands.size(); ++b) {
    const auto& band = maps.bands[b];
    for (std::size_t c = 0; c < dem.bands[0].values.size(); ++c) {
      const bool hole = dem.bands[0].values[c] == dem.bands[0].nodata;
      const bool empty = b >= 3 && !hole && passages[c] == 0.0;
      ASSERT_EQ(band.values[c] == band.nodata, hole || empty) << band.description << " cell " << c;
    }
  }
  // stop_density x cell area summed: the rocks that stopped.
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(out + "/summary.json"));
  double stops = 0.0;
  for (double v : maps.bands[2].values)
    if (v != maps.bands[2].nodata) stops += v * dem.transform[1] * -dem.transform[5];
  EXPECT_NEAR(stops, summary["outcomes"]["stopped"].get<double>(), 1e-3);
}

// A "us" site's coordinates are feet, and so is the rasters' grid: an ESRI
// grid of 10 ft cells, south-west corner (1000 ft, 2000 ft), 8 x 6 cells.
TEST(Rasters, UsSiteGridIsInFeet) {
  const std::string dir = FreshDir("site");
  fs::create_directories(dir);
  std::ofstream grid(dir + "/dem.asc");
  grid << "ncols 8\nnrows 6\nxllcorner 1000\nyllcorner 2000\ncellsize 10\nNODATA_value -9999\n";
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 8; ++c) grid << (c == 0 ? "" : " ") << 200 - 5 * c;
    grid << "\n";
  }
  grid.close();
  const nlohmann::json site = {
      {"name", "feet"},
      {"units", "us"},
      {"surface", {{"grid_file", "dem.asc"}, {"resolution", 10}, {"sphere_spacing", 10}}},
      {"materials",
       nlohmann::json::array({{{"id", "rock"}, {"hardness", 0.5}, {"roughness", 0.5}}})},
      {"rocks",
       nlohmann::json::array({{{"count", 1},
                               {"shape", "sphere"},
                               {"size", 1.0},
                               {"unit_weight", 165},
                               {"release", {{"point", nlohmann::json::array({1015, 2035})}}}}})},
      {"simulation", {{"seed", 1}, {"max_time", 5}}}};
  std::ofstream(dir + "/site.json") << site.dump(2);
  const std::string out = FreshDir("out");
  const RunResult run = Rockcal("simulate " + dir + "/site.json --rasters --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  const ReadRaster tif = OpenRaster(out + "/rasters.tif");
  ASSERT_TRUE(tif.has_transform);
  const std::array<double, 6> want = {1000.0, 10.0, 0.0, 2060.0, 0.0, -10.0};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(tif.transform[k], want[k], 1e-6) << k;
  EXPECT_EQ(tif.nx, 8);
  EXPECT_EQ(tif.ny, 6);
  EXPECT_EQ(tif.wkt, "") << "no CRS known";
  EXPECT_FALSE(fs::exists(out + "/rasters/passages.prj"));
}

TEST(Rasters, CalibrateWritesTheMapsOfTheReportSimulation) {
  const std::string out = FreshDir("cal");
  const std::string obs =
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
  const RunResult run = Rockcal("calibrate " + Example("tutorial") + " --observations " + obs +
                                " --rocks 4 --reach 0 --max-evals 2 --rasters --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("rasters.tif, rasters/*.asc"));
  const ReadRaster tif = OpenRaster(out + "/rasters.tif");
  ASSERT_EQ(tif.bands.size(), 9u);
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(out + "/summary.json"));
  EXPECT_EQ(tif.metadata.at("ROCKS_RELEASED"), std::to_string(summary["rocks"].get<int>()));
  // Every rock passed over the cell it started in.
  double most = 0.0;
  for (double v : Band(tif, "passages")->values) most = std::max(most, v);
  EXPECT_GE(most, 1.0);
  EXPECT_TRUE(fs::exists(out + "/rasters/height_p95.asc"));
}

}  // namespace
}  // namespace rockcal::cli
