#include "rockcal/sites/surface.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::ElementsAre;
using ::testing::EndsWith;
using ::testing::HasSubstr;
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
  const Surface surf = Read(R"({"resolution": 2, "lidar": {"file": "scan.txt",
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
  const Surface surf =
      Read(R"({"resolution": 5, "lidar": {"file": "scan.txt", "offset": "auto"}})", dir);
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
  const Surface from_grid = Read(R"({"grid_file": "plane.asc"})", dir);
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
  const Surface from_stl = Read(R"({"resolution": 2, "stl": {"axes": "xzy",
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
  const Surface from_points = Read(R"({"resolution": 2, "points_file": "plane.csv"})", dir);
  ExpectPlane(from_points.grid, "points_file");
  EXPECT_THAT(from_points.files, ElementsAre(EndsWith("/plane.csv")));

  ExpectPlane(Read(R"({"resolution": 2, "points": [[0, 0, 50], [40, 0, 62], [40, 20, 60],
      [0, 20, 48]]})",
                   dir)
                  .grid,
              "points");
}

TEST(ReadSurface, UsUnitsConvertCoordinatesAndResolution) {
  TempDir dir;
  const nlohmann::json j = nlohmann::json::parse(
      R"({"resolution": 10, "points": [[0, 0, 100], [100, 0, 100], [0, 50, 100], [100, 50, 100]]})");
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
                               "points_file, lidar, grid_file, stl), found points, grid_file"));
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

// Issue 14: /dev/zero as a points file read for ever.
TEST(ReadSurface, AFileOfOneEndlessLineFailsFast) {
  TempDir dir;
  EXPECT_THAT(ReadError(R"({"points_file": "/dev/zero"})", dir),
              HasSubstr("/dev/zero:1: line 1 longer than 1048576 bytes"));
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

}  // namespace
}  // namespace rockcal::sites
