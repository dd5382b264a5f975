#include "rockcal/sites/stl.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

std::string Facet(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  std::ostringstream s;
  s.precision(17);
  s << "  facet normal 0 0 1\n    outer loop\n";
  for (const Eigen::Vector3d* v : {&a, &b, &c})
    s << "      vertex " << v->x() << " " << v->y() << " " << v->z() << "\n";
  s << "    endloop\n  endfacet\n";
  return s.str();
}

TEST(ReadStl, AsciiWithAxisMappingAndScale) {
  TempDir dir;
  const std::string path = dir.Write(
      "a.stl", "solid terrain\n" + Facet({0, 5, 1}, {2, 6, 1}, {0, 7, 3}) + "endsolid terrain\n");
  const std::vector<Triangle> xyz = ReadStl(path, StlAxes::kXYZ, 1.0);
  ASSERT_EQ(xyz.size(), 1u);
  EXPECT_EQ(xyz[0].b, Eigen::Vector3d(2, 6, 1));
  // Y-up file: (x, y, z) -> (x, z, y); then feet to metres.
  const std::vector<Triangle> xzy = ReadStl(path, StlAxes::kXZY, 0.5);
  EXPECT_EQ(xzy[0].b, Eigen::Vector3d(1, 0.5, 3));
  StlAxes axes;
  EXPECT_TRUE(StringToStlAxes("xzy", &axes));
  EXPECT_EQ(axes, StlAxes::kXZY);
  EXPECT_FALSE(StringToStlAxes("yxz", &axes));
}

TEST(ReadStl, ErrorsNameFileAndLine) {
  TempDir dir;
  struct Case {
    std::string text;
    const char* expected;
  };
  const std::string ok = Facet({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  for (const Case& c : {
           Case{"solid x\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n"
                "      vertex 1 zero 0\n",
                ":5: expected a vertex coordinate (a finite number), found 'zero'"},
           Case{"solid x\n" + ok +
                    "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n"
                    "    endloop\n",
                ":12: expected 'vertex', found 'endloop'"},
           Case{"solid x\n" + ok, ":8: file ends inside a solid"},
           Case{"hello\n", ":1: expected 'solid', found 'hello'"},
           Case{"solid x\nendsolid x\n", ": no triangles"},
       }) {
    const std::string path = dir.Write("bad.stl", c.text);
    EXPECT_THAT(ErrorOf([&] { ReadStl(path, StlAxes::kXYZ, 1.0); }), HasSubstr(path + c.expected))
        << c.text;
  }
}

TEST(ReadStl, BinaryIsRejectedClearly) {
  TempDir dir;
  std::string data(84 + 50, '\0');
  data[80] = 1;  // one triangle
  const std::string path = dir.Write("bin.stl", data);
  EXPECT_THAT(ErrorOf([&] { ReadStl(path, StlAxes::kXYZ, 1.0); }),
              HasSubstr(path + ": binary STL is not supported"));
}

TEST(SampleTriangles, PlaneIsExactAndOutsideIsAHole) {
  auto plane = [](double x, double y) { return 2.0 - 0.5 * x + 0.125 * y; };
  auto p = [&](double x, double y) { return Eigen::Vector3d(x, y, plane(x, y)); };
  TriangleSet set;
  // A right triangle in plan, half of the 10 x 10 square.
  set.triangles.push_back({p(0, 0), p(10, 0), p(0, 10)});
  const core::HeightGrid g = SampleTriangles({set}, 1.0);
  EXPECT_EQ(g.nx, 11);
  EXPECT_EQ(g.ny, 11);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.z[g.index(i, j)];
      if (i + j <= 10) {
        EXPECT_NEAR(z, plane(i, j), 1e-12) << i << "," << j;  // edges included
      } else {
        EXPECT_TRUE(std::isnan(z)) << i << "," << j;
      }
    }
  }
}

TEST(SampleTriangles, HighestTriangleWinsAndSetsTheMaterial) {
  // A vertical step at x = 5: low ground (set 0) up to x = 5, high ground
  // (set 1) from x = 5, a vertical wall between them (no plan area).
  TriangleSet low, high, wall;
  low.material = 0;
  high.material = 1;
  wall.material = 2;
  low.triangles = {{{0, 0, 0}, {5, 0, 0}, {5, 4, 0}}, {{0, 0, 0}, {5, 4, 0}, {0, 4, 0}}};
  high.triangles = {{{5, 0, 3}, {9, 0, 3}, {9, 4, 3}}, {{5, 0, 3}, {9, 4, 3}, {5, 4, 3}}};
  wall.triangles = {{{5, 0, 0}, {5, 4, 0}, {5, 4, 3}}};
  const core::HeightGrid g = SampleTriangles({low, wall, high}, 1.0);
  ASSERT_EQ(g.nx, 10);
  EXPECT_EQ(g.z[g.index(4, 2)], 0.0);
  EXPECT_EQ(g.material[g.index(4, 2)], 0);
  EXPECT_EQ(g.z[g.index(5, 2)], 3.0);  // on the wall: the top
  EXPECT_EQ(g.material[g.index(5, 2)], 1);
  EXPECT_EQ(g.z[g.index(8, 1)], 3.0);
}

}  // namespace
}  // namespace rockcal::sites
