#include "rockcal/sites/surface.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "gis_files.h"
#include "rockcal/sites/text_reader.h"
#include "test_files.h"

namespace rockcal::sites {
namespace surface_test {

using ::testing::ElementsAre;
using ::testing::EndsWith;
using testing::ErrorOf;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::TempDir;

constexpr double kPi = 3.14159265358979323846;

// The plane every source below describes, in the site frame.
double Plane(double x, double y) { return 0.3 * x - 0.1 * y + 50.0; }

Surface Read(const std::string& json, const TempDir& dir,
             const std::vector<std::string>& materials = {"a", "b"}) {
  const nlohmann::json j = nlohmann::json::parse(json);
  const JsonNode node(&j, dir.path() + "/site.json", "$.surface");
  return ReadSurface(node, Units::kSI, dir.path(), materials);
}

std::string ReadError(const std::string& json, const TempDir& dir) {
  return ErrorOf([&] { Read(json, dir); });
}

void ExpectPlane(const core::HeightGrid& g, const char* source) {
  ASSERT_EQ(g.nx, 21) << source;
  ASSERT_EQ(g.ny, 11) << source;
  EXPECT_NEAR(g.x0, 0.0, 1e-9) << source;
  EXPECT_NEAR(g.y0, 0.0, 1e-9) << source;
  EXPECT_DOUBLE_EQ(g.spacing, 2.0) << source;
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      EXPECT_NEAR(g.z[g.index(i, j)], Plane(g.x(i), g.y(j)), 1e-9)
          << source << " node " << i << "," << j;
    }
  }
}

// The plane sampled every 2/3 m over [0, 40] x [0, 20].
std::vector<Eigen::Vector3d> Lattice() {
  std::vector<Eigen::Vector3d> p;
  for (int b = 0; b <= 30; ++b) {
    for (int a = 0; a <= 60; ++a) {
      const double x = a * 2.0 / 3.0, y = b * 2.0 / 3.0;
      p.emplace_back(x, y, Plane(x, y));
    }
  }
  return p;
}

TEST(ReadSurface, LidarWithOffsetAndSpinLandsOnTheGrid) {
  TempDir dir;
  // Written in a frame turned by -30 deg and shifted by the offset, so that
  // subtracting the offset and spinning 30 deg restores the site frame.
  const double a = -30.0 * kPi / 180.0;
  std::ostringstream s;
  s.precision(17);
  s << "CRSP LIDAR export\nunits: m\nX Y Z R G B\n";
  for (const Eigen::Vector3d& p : Lattice()) {
    s << 1000.0 + std::cos(a) * p.x() - std::sin(a) * p.y() << " "
      << 5000.0 + std::sin(a) * p.x() + std::cos(a) * p.y() << " " << p.z() + 10.0
      << " 120 130 140\n";
  }
  dir.Write("scan.txt", s.str());
  const Surface surf = Read(R"({"resolution": 2, "sphere_spacing": 2, "lidar": {"file": "scan.txt",
      "offset": [1000, 5000, 10], "spin_deg": 30}})",
                            dir);
  EXPECT_EQ(surf.source, "lidar");
  EXPECT_FALSE(surf.materials_from_source);
  EXPECT_THAT(surf.files, ElementsAre(EndsWith("/scan.txt")));  // once: a resume names it once
  ExpectPlane(surf.grid, "lidar");
}

TEST(ReadSurface, LidarAutoOffsetKeepsElevation) {
  TempDir dir;
  dir.Write("scan.txt", "X Y Z\n1000 2000 7\n1010 2000 7\n1000 2010 7\n1010 2010 7\n");
  const Surface surf = Read(
      R"({"resolution": 5, "sphere_spacing": 5, "lidar": {"file": "scan.txt", "offset": "auto"}})",
      dir);
  EXPECT_EQ(surf.grid.x0, 0.0);
  EXPECT_EQ(surf.grid.y0, 0.0);
  EXPECT_EQ(surf.grid.nx, 3);
  EXPECT_DOUBLE_EQ(surf.grid.z[4], 7.0);
}

TEST(ReadSurface, EsriGridStlAndPointsGiveTheSameTerrain) {
  TempDir dir;
  std::ostringstream asc;
  asc.precision(17);
  asc << "ncols 21\nnrows 11\nxllcorner -1\nyllcorner -1\ncellsize 2\n";
  for (int j = 10; j >= 0; --j) {
    for (int i = 0; i <= 20; ++i) asc << (i ? " " : "") << Plane(2.0 * i, 2.0 * j);
    asc << "\n";
  }
  dir.Write("plane.asc", asc.str());
  const Surface from_grid = Read(R"({"grid_file": "plane.asc", "sphere_spacing": 2})", dir);
  ExpectPlane(from_grid.grid, "grid_file");  // its own cell size
  // Each data file is listed once (Site::inputs, the resume fingerprint).
  EXPECT_THAT(from_grid.files, ElementsAre(EndsWith("/plane.asc")));

  // STL in a Y-up frame: vertices written as (x, elevation, y).
  std::ostringstream stl;
  stl.precision(17);
  stl << "solid plane\n";
  const double corners[4][2] = {{0, 0}, {40, 0}, {40, 20}, {0, 20}};
  const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& t : tris) {
    stl << "facet normal 0 1 0\nouter loop\n";
    for (int k : t) {
      const double x = corners[k][0], y = corners[k][1];
      stl << "vertex " << x << " " << Plane(x, y) << " " << y << "\n";
    }
    stl << "endloop\nendfacet\n";
  }
  stl << "endsolid plane\n";
  dir.Write("zones/plane.stl", stl.str());
  const Surface from_stl = Read(R"({"resolution": 2, "sphere_spacing": 2, "stl": {"axes": "xzy",
      "files": [{"file": "zones/plane.stl", "material": "b"}]}})",
                                dir);
  ExpectPlane(from_stl.grid, "stl");
  EXPECT_THAT(from_stl.files, ElementsAre(EndsWith("/zones/plane.stl")));
  EXPECT_TRUE(from_stl.materials_from_source);
  EXPECT_EQ(from_stl.grid.material[7], 1);

  std::ostringstream pts;
  pts.precision(17);
  pts << "x,y,z\n";
  for (const Eigen::Vector3d& p : Lattice()) pts << p.x() << "," << p.y() << "," << p.z() << "\n";
  dir.Write("plane.csv", pts.str());
  const Surface from_points =
      Read(R"({"resolution": 2, "sphere_spacing": 2, "points_file": "plane.csv"})", dir);
  ExpectPlane(from_points.grid, "points_file");
  EXPECT_THAT(from_points.files, ElementsAre(EndsWith("/plane.csv")));

  ExpectPlane(
      Read(
          R"({"resolution": 2, "sphere_spacing": 2, "points": [[0, 0, 50], [40, 0, 62], [40, 20, 60],
      [0, 20, 48]]})",
          dir)
          .grid,
      "points");
}

// The plane over [0, 40] x [0, 20] as a GeoTIFF of 21 x 11 cells of 2 m
// centred on the nodes of ExpectPlane (and the same values as an ESRI grid).
void WritePlaneRasters(const TempDir& dir, const std::string& crs = "") {
  testing::RasterSpec spec;
  spec.nx = 21;
  spec.ny = 11;
  spec.geotransform = {-1, 2, 0, 21, 0, -2};
  spec.type = GDT_Float64;
  spec.crs = crs;
  std::ostringstream asc;
  asc.precision(17);
  asc << "ncols 21\nnrows 11\nxllcorner -1\nyllcorner -1\ncellsize 2\n";
  for (int j = 10; j >= 0; --j) {
    for (int i = 0; i <= 20; ++i) {
      spec.values.push_back(Plane(2.0 * i, 2.0 * j));
      asc << (i ? " " : "") << Plane(2.0 * i, 2.0 * j);
    }
    asc << "\n";
  }
  testing::WriteRaster(dir.path() + "/plane.tif", spec);
  dir.Write("plane.asc", asc.str());
}

TEST(ReadSurface, RasterTakesTheEsriGridsWayOntoTheGrid) {
  TempDir dir;
  WritePlaneRasters(dir);
  const Surface tif = Read(R"({"raster": "plane.tif", "sphere_spacing": 2})", dir);
  EXPECT_EQ(tif.source, "raster");
  EXPECT_TRUE(tif.gis);
  EXPECT_TRUE(tif.crs_wkt.empty());
  EXPECT_THAT(tif.files, ElementsAre(EndsWith("/plane.tif")));
  ExpectPlane(tif.grid, "raster");  // its own cell size: the cell centres are the nodes
  EXPECT_THAT(tif.notes[0], HasSubstr("(GTiff, band 1), 21 x 11 cells of 2 m (cell centres are "
                                      "the grid nodes)"));
  EXPECT_TRUE(tif.resampled.empty());
  // Resampled: the same bilinear rule as the ESRI grid, to the last bit.
  const Surface a = Read(
      R"({"resolution": 3, "sphere_spacing": 3, "raster": {"file": "plane.tif", "band": 1}})", dir);
  const Surface b =
      Read(R"({"resolution": 3, "sphere_spacing": 3, "grid_file": "plane.asc"})", dir);
  EXPECT_FALSE(b.gis);
  ASSERT_EQ(a.grid.nx, 14);
  ASSERT_EQ(a.grid.nx, b.grid.nx);
  ASSERT_EQ(a.grid.ny, b.grid.ny);
  EXPECT_EQ(a.grid.x0, b.grid.x0);
  EXPECT_EQ(a.grid.z, b.grid.z);
  EXPECT_NEAR(a.grid.z[a.grid.index(5, 3)], Plane(15, 9), 1e-9);
  EXPECT_THAT(a.resampled, ElementsAre("surface: 21 x 11 cells of 2 m resampled bilinearly to "
                                       "the resolution 3 m (resolution): 14 x 7 nodes"));
  EXPECT_EQ(a.notes[1], a.resampled[0]);
}

// Issue 55: a DEM with no sphere_spacing keeps its own grid (its cells, or
// its resolution when given) rather than the 12 ft of scattered points; any
// resampling is said with units and node counts.
TEST(ReadSurface, ADemKeepsItsOwnGridUnlessSphereSpacingIsGiven) {
  TempDir dir;
  WritePlaneRasters(dir);
  for (const char* json : {R"({"raster": "plane.tif"})", R"({"grid_file": "plane.asc"})"}) {
    const Surface s = Read(json, dir);
    ExpectPlane(s.grid, json);
    EXPECT_TRUE(s.resampled.empty()) << json;
  }
  // A resolution of its own: the spheres sit on that grid, resampled once.
  const Surface coarse = Read(R"({"raster": "plane.tif", "resolution": 4})", dir);
  EXPECT_DOUBLE_EQ(coarse.grid.spacing, 4.0);
  EXPECT_EQ(coarse.grid.nx, 11);
  EXPECT_EQ(coarse.grid.ny, 6);
  EXPECT_THAT(coarse.resampled, ElementsAre("surface: 21 x 11 cells of 2 m resampled bilinearly "
                                            "to the resolution 4 m (resolution): 11 x 6 nodes"));
  // A sphere spacing given: the DEM's grid resampled onto it.
  const Surface spheres = Read(R"({"grid_file": "plane.asc", "sphere_spacing": 4})", dir);
  EXPECT_DOUBLE_EQ(spheres.grid.spacing, 4.0);
  EXPECT_THAT(spheres.resampled,
              ElementsAre("surface: the grid of 2 m (21 x 11 nodes) resampled bilinearly to the "
                          "virtual spheres' spacing 4 m (11 x 6 nodes; sphere_spacing)"));
  // Scattered points keep CRSP's 12 ft, and say so.
  const Surface points = Read(
      R"({"resolution": 2, "points": [[0, 0, 50], [40, 0, 62], [40, 20, 60], [0, 20, 48]]})", dir);
  EXPECT_DOUBLE_EQ(points.grid.spacing, kDefaultSphereSpacingM);
  EXPECT_THAT(points.resampled,
              ElementsAre("surface: the grid of 2 m (21 x 11 nodes) resampled bilinearly to the "
                          "virtual spheres' spacing 3.6576 m (11 x 6 nodes; the default 12 ft of "
                          "scattered points and STL)"));
  // In a "us" site the notes are in feet.
  const nlohmann::json j = nlohmann::json::parse(R"({"grid_file": "plane.asc", "sphere_spacing": 4})");
  const Surface us = ReadSurface(JsonNode(&j, dir.path() + "/site.json", "$.surface"), Units::kUS,
                                 dir.path(), {"a"});
  EXPECT_DOUBLE_EQ(us.grid.spacing, 4 * 0.3048);
  EXPECT_THAT(us.resampled, ElementsAre(HasSubstr("the grid of 2 ft (21 x 11 nodes) resampled "
                                                  "bilinearly to the virtual spheres' spacing 4 ft")));
}

TEST(ReadSurface, RasterNodataIsAHole) {
  TempDir dir;
  testing::RasterSpec spec;
  spec.nx = 4;
  spec.ny = 3;
  spec.geotransform = {0, 1, 0, 3, 0, -1};
  spec.values = {1, 2, 3, -1, 5, 6, 7, 8, 9, 10, 11, 12};
  spec.nodata = -1;
  testing::WriteRaster(dir.path() + "/dem.tif", spec);
  const Surface s = Read(R"({"raster": "dem.tif", "sphere_spacing": 1})", dir);
  EXPECT_TRUE(std::isnan(s.grid.z[s.grid.index(3, 2)]));
  EXPECT_DOUBLE_EQ(s.grid.z[s.grid.index(0, 0)], 9.0);
}

TEST(ReadSurface, CrsFromTheRasterOrTheCrsKey) {
  TempDir dir;
  WritePlaneRasters(dir, "EPSG:2154");
  const std::string site = dir.path() + "/site.json: ";
  Surface s = Read(R"({"raster": "plane.tif"})", dir);
  EXPECT_THAT(s.crs_wkt, HasSubstr("Lambert-93"));
  EXPECT_THAT(s.notes.back(), HasSubstr("crs: RGF93 v1 / Lambert-93 (EPSG:2154)"));
  s = Read(R"({"crs": "EPSG:2154", "raster": "plane.tif"})", dir);
  EXPECT_THAT(s.crs_wkt, HasSubstr("Lambert-93"));
  EXPECT_THAT(ReadError(R"({"crs": "EPSG:32631", "raster": "plane.tif"})", dir),
              HasSubstr(site + "$.surface.crs: the raster '" + dir.path() +
                        "/plane.tif' has the CRS RGF93 v1 / Lambert-93 (EPSG:2154), not the one "
                        "named here (WGS 84 / UTM zone 31N (EPSG:32631)); expected the same CRS"));
  // Any source may name its CRS.
  s = Read(
      R"({"crs": "EPSG:32631", "resolution": 2, "sphere_spacing": 2, "points": [[0, 0, 50], [40, 0, 62],
      [40, 20, 60], [0, 20, 48]]})",
      dir);
  EXPECT_THAT(s.crs_wkt, HasSubstr("UTM zone 31N"));
  EXPECT_FALSE(s.gis);
  EXPECT_THAT(ReadError(R"({"crs": "EPSG:99999999", "points": [[0,0,0],[9,0,0],[0,9,0]]})", dir),
              HasSubstr(site + "$.surface.crs: not a coordinate reference system GDAL "
                               "recognises"));
  EXPECT_THAT(ReadError(R"({"crs": "EPSG:4326", "points": [[0,0,0],[9,0,0],[0,9,0]]})", dir),
              HasSubstr(site + "$.surface.crs: the CRS WGS 84 (EPSG:4326) is geographic"));
  // Coordinates are never converted: a CRS in metres needs a site in metres.
  const nlohmann::json j = nlohmann::json::parse(R"({"raster": "plane.tif"})");
  EXPECT_THAT(ErrorOf([&] {
                ReadSurface(JsonNode(&j, "s.json", "$.surface"), Units::kUS, dir.path(), {"a"});
              }),
              HasSubstr(dir.path() + "/plane.tif: the CRS RGF93 v1 / Lambert-93 (EPSG:2154) "
                                     "measures coordinates in metre (1 m), not in the site's "
                                     "unit (ft)"));
  dir.Write("scan.txt", "X Y Z\n0 0 1\n10 0 1\n0 10 1\n");
  EXPECT_THAT(
      ReadError(R"({"crs": "EPSG:2154", "lidar": {"file": "scan.txt", "offset": "auto"}})", dir),
      HasSubstr(site + "$.surface.crs: a LIDAR offset in plan or a spin moves the points "
                       "out of any map frame"));
}

TEST(ReadSurface, MaxEdgeAndTriangulationNotes) {
  TempDir dir;
  const Surface s = Read(
      R"({"resolution": 1, "sphere_spacing": 1, "max_edge": 6.5, "points": [[0, 0, 0], [4, 0, 0],
      [0, 4, 0], [4, 4, 0], [10, 0, 0], [10, 4, 0], [4, 4, 0]]})",
      dir);
  // x 0-4: edges of 4 m and diagonals of 5.7 m; x 4-10: diagonals of 7.2 m, holes.
  EXPECT_FALSE(std::isnan(s.grid.z[s.grid.index(2, 2)]));
  EXPECT_TRUE(std::isnan(s.grid.z[s.grid.index(7, 2)]));
  EXPECT_THAT(s.notes[1], HasSubstr("triangulation: 7 points, 1 point(s) at a plan position "
                                    "already taken merged (elevations averaged), 4 Delaunay "
                                    "triangles; "));
  EXPECT_THAT(s.notes[1], HasSubstr("0 holes outside the convex hull, "));
  EXPECT_THAT(s.notes[1], HasSubstr("holes in triangles with an edge longer than 6.5 (max_edge)"));
  WritePlaneRasters(dir);
  EXPECT_THAT(ReadError(R"({"max_edge": 5, "raster": "plane.tif"})", dir),
              HasSubstr("$.surface.max_edge: 'max_edge' applies to triangulated points"));
  EXPECT_THAT(ReadError(R"({"points": [[0, 0, 0], [10, 10, 0], [20, 20, 0]]})", dir),
              HasSubstr("$.surface.points: the 3 distinct surface points lie on one line in plan"));
}

TEST(ReadSurface, UsUnitsConvertCoordinatesAndResolution) {
  TempDir dir;
  const nlohmann::json j = nlohmann::json::parse(
      R"({"resolution": 10, "sphere_spacing": 10, "points": [[0, 0, 100], [100, 0, 100], [0, 50, 100], [100, 50, 100]]})");
  const Surface surf =
      ReadSurface(JsonNode(&j, "s.json", "$.surface"), Units::kUS, dir.path(), {"a"});
  EXPECT_DOUBLE_EQ(surf.grid.spacing, 3.048);
  EXPECT_EQ(surf.grid.nx, 11);
  EXPECT_EQ(surf.grid.ny, 6);
  EXPECT_DOUBLE_EQ(surf.grid.z[0], 30.48);
}

TEST(ReadSurface, DefaultResolutionIsTwelveFeet) {
  TempDir dir;
  const Surface surf = Read(R"({"points": [[0, 0, 1], [40, 0, 1], [0, 40, 1]]})", dir);
  EXPECT_DOUBLE_EQ(surf.grid.spacing, 3.6576);
}

TEST(ReadSurface, ErrorsNameFileAndJsonPath) {
  TempDir dir;
  const std::string site = dir.path() + "/site.json: ";
  EXPECT_THAT(ReadError(R"({"points": [[0,0,0],[1,0,0],[0,1,0]], "grid_file": "g.asc"})", dir),
              HasSubstr(site + "$.surface: expected exactly one surface source (one of points, "
                               "points_file, lidar, grid_file, raster, stl), found points, "
                               "grid_file"));
  EXPECT_THAT(ReadError(R"({"resolution": 2})", dir), HasSubstr("found none"));
  EXPECT_THAT(ReadError(R"({"pointz": []})", dir),
              HasSubstr(site + "$.surface.pointz: unknown key 'pointz'"));
  EXPECT_THAT(ReadError(R"({"points": [[0, 0, 0], [1, 1, 1]]})", dir),
              HasSubstr(site + "$.surface.points: expected an array of at least 3 entries"));
  EXPECT_THAT(ReadError(R"({"points": [[0, 0, 0], [1, 1], [0, 1, 0]]})", dir),
              HasSubstr(site + "$.surface.points[1]: expected an array of 3 numbers"));
  EXPECT_THAT(ReadError(R"({"resolution": 0, "points": [[0,0,0],[9,0,0],[0,9,0]]})", dir),
              HasSubstr(site + "$.surface.resolution: expected a number > 0"));
  EXPECT_THAT(ReadError(R"({"resolution": 20, "points": [[0,0,0],[9,0,0],[0,9,0]]})", dir),
              HasSubstr(site + "$.surface.resolution: the surface data span 9 x 9"));
  EXPECT_THAT(ReadError(R"({"resolution": 0.0001, "points": [[0,0,0],[9,0,0],[0,9,0]]})", dir),
              HasSubstr("is too large"));
  EXPECT_THAT(ReadError(R"({"sphere_spacing": -1, "points": [[0,0,0],[9,0,0],[0,9,0]]})", dir),
              HasSubstr(site + "$.surface.sphere_spacing: expected a number > 0"));
  EXPECT_THAT(
      ReadError(R"({"resolution": 1, "sphere_spacing": 20, "points": [[0,0,0],[9,0,0],[0,9,0]]})",
                dir),
      HasSubstr(site + "$.surface.sphere_spacing: the surface data span 9 x 9"));
  EXPECT_THAT(
      ReadError(
          R"({"resolution": 1, "sphere_spacing": 0.0001, "points": [[0,0,0],[9,0,0],[0,9,0]]})",
          dir),
      HasSubstr(site + "$.surface.sphere_spacing: a grid of"));
  dir.Write("x.txt", "");
  EXPECT_THAT(ReadError(R"({"lidar": {"file": "x.txt", "offset": "automatic"}})", dir),
              HasSubstr(site + "$.surface.lidar.offset: expected \"auto\" or [x, y, z]"));
  EXPECT_THAT(ReadError(R"({"lidar": {"file": "x.txt", "spin": 3}})", dir),
              HasSubstr(site + "$.surface.lidar.spin: unknown key 'spin'"));
  EXPECT_THAT(ReadError(R"({"stl": {"files": [{"file": "x.stl", "material": "rock"}]}})", dir),
              HasSubstr(site + "$.surface.stl.files[0].material: unknown material 'rock' "
                               "(materials: a, b)"));
  EXPECT_THAT(ReadError(R"({"stl": {"axes": "yxz", "files": []}})", dir),
              HasSubstr(site + "$.surface.stl.axes: unknown axes (allowed: xyz, xzy)"));
  EXPECT_THAT(ReadError(R"({"points_file": "missing.csv"})", dir),
              HasSubstr(site + "$.surface.points_file: cannot open file '" + dir.path() +
                        "/missing.csv': No such file or directory"));
  // Issue 14: an empty name said "cannot open file" without file or path.
  EXPECT_THAT(ReadError(R"({"points_file": ""})", dir),
              HasSubstr(site + "$.surface.points_file: expected a file name"));
  EXPECT_THAT(ReadError(R"({"grid_file": "."})", dir),
              HasSubstr(site + "$.surface.grid_file: '" + dir.path() + "/.' is a folder"));
}

// Issue 56: a grid or GeoTIFF cell of 1e30 ran ("elevation 0 to 3.152e+29
// m") where a points file refused it; xllcenter 1e300 and an STL vertex at
// 6e300 were "less than one grid spacing", a points file's z = 1e30 and an
// inline point at 1e300 were blamed on $.surface.resolution. Every source
// takes one range, +-1e7 m, and the error names the value, the file and
// where in it.
TEST(ReadSurface, EveryTerrainSourceTakesOneRangeNamingTheValue) {
  TempDir dir;
  const std::string site = dir.path() + "/site.json: ";
  const std::string grid_head = "ncols 3\nnrows 3\nxllcenter 0\nyllcenter 0\ncellsize 5\n";
  const std::string asc = dir.Write("big.asc", grid_head + "1 2 3\n4 1e30 6\n7 8 9\n");
  std::string error = ReadError(R"({"grid_file": "big.asc", "sphere_spacing": 5})", dir);
  EXPECT_THAT(error, HasSubstr(asc + ": the elevation of row 2 (counted from the north), column 2 "
                                     "is 1e+30, out of range; expected coordinates and elevations "
                                     "within +-10000000 (file units)"));
  dir.Write("far.asc",
            "ncols 3\nnrows 3\nxllcenter 1e300\nyllcenter 0\ncellsize 5\n1 2 3\n4 5 6\n7 8 9\n");
  error = ReadError(R"({"grid_file": "far.asc", "sphere_spacing": 5})", dir);
  EXPECT_THAT(error, HasSubstr("far.asc: the x of the lower-left cell's centre is 1e+300, out of "
                               "range"));
  EXPECT_THAT(error, Not(HasSubstr("grid spacing")));

  testing::RasterSpec spec;
  spec.nx = 3;
  spec.ny = 3;
  spec.geotransform = {0, 5, 0, 15, 0, -5};
  spec.values = {1, 2, 3, 4, 5, 6, 7, 8, -1e30};
  testing::WriteRaster(dir.path() + "/big.tif", spec);
  error = ReadError(R"({"raster": "big.tif", "sphere_spacing": 5})", dir);
  EXPECT_THAT(error, HasSubstr("/big.tif: the elevation of row 3 (counted from the north), "
                               "column 3 is -1.000000015e+30, out of range"));

  // A vertex far away, Z up.
  dir.Write("far.stl",
            "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 6e300 0 0\n"
            "vertex 0 10 0\nendloop\nendfacet\nendsolid s\n");
  error = ReadError(
      R"({"resolution": 2, "sphere_spacing": 2, "stl": {"files": [{"file": "far.stl",
          "material": "a"}]}})",
      dir);
  EXPECT_THAT(error, HasSubstr("/far.stl: the x of a vertex of triangle 1 is 6e+300, out of "
                               "range"));

  dir.Write("high.csv", "0 0 0\n10 0 0\n0 10 1e30\n");
  error = ReadError(R"({"resolution": 2, "sphere_spacing": 2, "points_file": "high.csv"})", dir);
  EXPECT_THAT(error, HasSubstr(site + "$.surface.points_file: surface point 3 of '" + dir.path() +
                               "/high.csv' (0, 10, 1e+30) is out of range"));
  EXPECT_THAT(error, Not(HasSubstr("resolution")));
  error = ReadError(
      R"({"resolution": 2, "sphere_spacing": 2, "points": [[0,0,0],[1e300,0,0],[0,9,0]]})", dir);
  EXPECT_THAT(error, HasSubstr(site + "$.surface.points: surface point 2 (1e+300, 0, 0) is out "
                                      "of range"));
  // At the limit: accepted.
  dir.Write("edge.asc", grid_head + "1 2 3\n4 1e7 6\n7 8 9\n");
  EXPECT_NO_THROW(Read(R"({"grid_file": "edge.asc", "sphere_spacing": 5})", dir));
}

// Issue 14: /dev/zero as a points file read for ever. Issue 40: a device is
// refused before it is opened; a regular file of one endless line still
// fails at its first line.
TEST(ReadSurface, AFileOfOneEndlessLineFailsFast) {
  TempDir dir;
  EXPECT_THAT(ReadError(R"({"points_file": "/dev/zero"})", dir),
              HasSubstr("/dev/zero: is a character device, expected a regular file"));
  const std::string line = dir.Write("line.csv", std::string(kMaxLineBytes + 10, '1'));
  EXPECT_THAT(ReadError(R"({"points_file": "line.csv"})", dir),
              HasSubstr(line + ":1: line 1 longer than 1048576 bytes"));
}

TEST(ReadSurface, DataFileErrorsNameTheDataFileAndLine) {
  TempDir dir;
  const std::string path = dir.Write("scan.txt", "X Y Z\n0 0 0\n5 0 0\n0 5 x\n");
  EXPECT_THAT(ReadError(R"({"lidar": {"file": "scan.txt"}})", dir),
              HasSubstr(path + ":4: value 3 'x' is not a finite number"));
}

TEST(ResolvePath, RelativeToTheSiteFolder) {
  EXPECT_EQ(ResolvePath("/a/b", "c.csv"), "/a/b/c.csv");
  EXPECT_EQ(ResolvePath("/a/b", "/d/c.csv"), "/d/c.csv");
  EXPECT_EQ(ResolvePath("", "c.csv"), "c.csv");
}

}  // namespace surface_test
}  // namespace rockcal::sites
