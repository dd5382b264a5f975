#include "rockcal/sites/gridding.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace rockcal::sites {
namespace gridding_test {

using ::testing::HasSubstr;

double Plane(double x, double y) { return 0.35 * x - 0.2 * y + 40.0; }

// Deterministic uniform numbers in [0, 1).
class Lcg {
 public:
  double Next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) / 9007199254740992.0;
  }

 private:
  std::uint64_t state_ = 12345;
};

int CountHoles(const core::HeightGrid& g) {
  int n = 0;
  for (double z : g.z) n += std::isnan(z);
  return n;
}

core::HeightGrid Grid(const std::vector<Eigen::Vector3d>& pts, double spacing,
                      GriddingReport* rep = nullptr,
                      double max_edge = std::numeric_limits<double>::infinity()) {
  GriddingOptions options;
  options.spacing = spacing;
  options.max_edge = max_edge;
  core::HeightGrid g;
  std::string error;
  EXPECT_TRUE(GridPoints(pts, options, &g, rep, &error)) << error;
  return g;
}

std::string GridError(const std::vector<Eigen::Vector3d>& pts) {
  GriddingOptions options;
  core::HeightGrid g;
  std::string error;
  EXPECT_FALSE(GridPoints(pts, options, &g, nullptr, &error));
  return error;
}

TEST(NodeCount, FloorPlusOneWithRoundingSlack) {
  EXPECT_EQ(NodeCount(10.0, 2.0), 6);
  EXPECT_EQ(NodeCount(11.9, 2.0), 6);
  EXPECT_EQ(NodeCount(3 * 0.1, 0.1), 4);  // 0.30000000000000004 / 0.1
  EXPECT_EQ(NodeCount(0.0, 1.0), 1);
}

TEST(GridPoints, ScatteredPlaneIsExactAtEveryNode) {
  Lcg rng;
  std::vector<Eigen::Vector3d> pts;
  // The four corners make the hull the whole bounding box.
  for (double x : {0.0, 60.0})
    for (double y : {0.0, 30.0}) pts.emplace_back(x, y, Plane(x, y));
  for (int k = 0; k < 4000; ++k) {
    const double x = 60.0 * rng.Next(), y = 30.0 * rng.Next();
    pts.emplace_back(x, y, Plane(x, y));
  }
  GriddingReport rep;
  const core::HeightGrid g = Grid(pts, 3.0, &rep);
  ASSERT_EQ(g.nx, 21);
  ASSERT_EQ(g.ny, 11);
  EXPECT_EQ(rep.points, 4004);
  EXPECT_EQ(rep.nodes, g.nx * g.ny);
  EXPECT_EQ(rep.outside_hull + rep.long_edge, 0);
  EXPECT_GT(rep.triangles, 7000);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      EXPECT_NEAR(g.z[g.index(i, j)], Plane(g.x(i), g.y(j)), 1e-9) << "node " << i << "," << j;
}

TEST(GridPoints, FourCornersOfAPlaneFillTheWholeGrid) {
  // A plane given by its four corners, as a small site file gives it.
  std::vector<Eigen::Vector3d> pts;
  for (double x : {0.0, 400.0})
    for (double y : {0.0, 200.0}) pts.emplace_back(x, y, 300.0 - 0.7 * x);
  GriddingReport rep;
  const core::HeightGrid g = Grid(pts, 12.0, &rep);
  EXPECT_EQ(g.nx, 34);
  EXPECT_EQ(g.ny, 17);
  EXPECT_EQ(rep.triangles, 2);
  EXPECT_EQ(CountHoles(g), 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      EXPECT_NEAR(g.z[g.index(i, j)], 300.0 - 0.7 * g.x(i), 1e-9) << "node " << i << "," << j;
}

TEST(GridPoints, LinearInsideEachTriangle) {
  // Delaunay: (0,0) (10,0) (0,10), and (10,0) (12,12) (0,10) (the fourth
  // point lies outside the first triangle's circumcircle).
  const std::vector<Eigen::Vector3d> pts = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {12, 12, 10}};
  GriddingReport rep;
  const core::HeightGrid g = Grid(pts, 2.0, &rep);
  EXPECT_EQ(rep.triangles, 2);
  EXPECT_NEAR(g.z[g.index(1, 1)], 0.0, 1e-12);         // (2, 2): first triangle
  EXPECT_NEAR(g.z[g.index(4, 4)], 30.0 / 7.0, 1e-12);  // (8, 8): s = 3/7 of the way to (12, 12)
  EXPECT_NEAR(g.z[g.index(6, 6)], 10.0, 1e-12);        // the corner itself
  EXPECT_TRUE(std::isnan(g.z[g.index(6, 0)]));         // (12, 0): outside the hull
  EXPECT_TRUE(std::isnan(g.z[g.index(0, 6)]));
}

TEST(GridPoints, OnlyTheOutsideOfTheHullIsAHole) {
  // Data on the triangle x + y <= 40 of a 40 x 40 box.
  std::vector<Eigen::Vector3d> pts;
  for (int j = 0; j <= 80; ++j)
    for (int i = 0; i <= 80 - j; ++i) pts.emplace_back(0.5 * i, 0.5 * j, Plane(0.5 * i, 0.5 * j));
  GriddingReport rep;
  const core::HeightGrid g = Grid(pts, 2.0, &rep);
  int outside = 0;
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x(i), y = g.y(j), z = g.z[g.index(i, j)];
      if (x + y > 40 + 1e-9) {
        EXPECT_TRUE(std::isnan(z)) << "node beyond the data " << x << "," << y << " z " << z;
        ++outside;
      } else {
        EXPECT_NEAR(z, Plane(x, y), 1e-9) << x << "," << y;
      }
    }
  }
  EXPECT_EQ(rep.outside_hull, outside);
  EXPECT_EQ(rep.nodes + rep.outside_hull, g.nx * g.ny);
}

TEST(GridPoints, MaxEdgeKeepsWideGapsAsHoles) {
  std::vector<Eigen::Vector3d> pts;
  for (int j = 0; j <= 150; ++j) {
    for (int i = 0; i <= 150; ++i) {
      const double x = 0.4 * i, y = 0.4 * j;  // 60 m x 60 m
      const bool small_gap = std::hypot(x - 15, y - 15) < 2.6;
      const bool large_gap = std::hypot(x - 40, y - 40) < 12;
      if (!small_gap && !large_gap) pts.emplace_back(x, y, Plane(x, y));
    }
  }
  // Without a limit the hull is convex: every node is interpolated, exactly.
  GriddingReport all;
  core::HeightGrid g = Grid(pts, 2.0, &all);
  EXPECT_EQ(CountHoles(g), 0);
  EXPECT_NEAR(g.z[g.index(20, 20)], Plane(40, 40), 1e-9);
  // With max_edge 6 m the 5.2 m gap is bridged, the 24 m one is not.
  GriddingReport rep;
  g = Grid(pts, 2.0, &rep, 6.0);
  ASSERT_EQ(g.nx, 31);
  EXPECT_NEAR(g.z[g.index(7, 7)], Plane(14, 14), 1e-9);
  EXPECT_NEAR(g.z[g.index(8, 7)], Plane(16, 14), 1e-9);
  EXPECT_TRUE(std::isnan(g.z[g.index(20, 20)]));
  EXPECT_TRUE(std::isnan(g.z[g.index(22, 20)]));
  EXPECT_GT(rep.long_edge, 50);
  EXPECT_EQ(rep.outside_hull, 0);
  EXPECT_EQ(CountHoles(g), rep.long_edge);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.z[g.index(i, j)];
      if (!std::isnan(z)) {
        EXPECT_NEAR(z, Plane(g.x(i), g.y(j)), 1e-9) << i << "," << j;
      }
      // Nodes more than 6 m inside the large gap are holes.
      if (std::hypot(g.x(i) - 40, g.y(j) - 40) < 6) {
        EXPECT_TRUE(std::isnan(z)) << i << "," << j;
      }
    }
  }
}

TEST(GridPoints, PointsAtTheSamePlanPositionAreAveraged) {
  std::vector<Eigen::Vector3d> pts = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}};
  pts.emplace_back(10, 10, 4);  // the same corner twice more: mean (0 + 4 + 8) / 3 = 4
  pts.emplace_back(10, 10, 8);
  pts.emplace_back(0, 0, 0);  // and a plain duplicate
  GriddingReport rep;
  const core::HeightGrid g = Grid(pts, 5.0, &rep);
  EXPECT_EQ(rep.points, 7);
  EXPECT_EQ(rep.merged, 3);
  EXPECT_NEAR(g.z[g.index(2, 2)], 4.0, 1e-12);
  EXPECT_NEAR(g.z[g.index(0, 0)], 0.0, 1e-12);
  EXPECT_EQ(CountHoles(g), 0);
}

TEST(GridPoints, TooFewOrCollinearPointsAreErrors) {
  EXPECT_THAT(GridError({{0, 0, 1}, {5, 5, 2}, {0, 0, 3}}),
              HasSubstr("2 distinct plan position(s) among the surface points; expected at "
                        "least 3 points not on one line"));
  EXPECT_THAT(GridError({{0, 0, 1}, {5, 5, 2}, {10, 10, 3}, {2.5, 2.5, 0}}),
              HasSubstr("the 4 distinct surface points lie on one line in plan"));
  EXPECT_THAT(GridError({{0, 0, 1}, {5, 0, 2}, {10, 0, 3}}), HasSubstr("lie on one line"));
}

TEST(GriddingOptions, IsValidNamesTheField) {
  GriddingOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error));
  o.spacing = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("GriddingOptions::spacing = 0"));
  o.spacing = 1;
  o.max_edge = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("GriddingOptions::max_edge = -1"));
}

TEST(GridPoints, FarFromTheOriginAsNearIt) {
  // Map coordinates (e.g. Lambert-93) must not cost precision.
  Lcg rng;
  std::vector<Eigen::Vector3d> pts;
  const double x0 = 900000.0, y0 = 6500000.0;
  for (double x : {0.0, 50.0})
    for (double y : {0.0, 50.0}) pts.emplace_back(x0 + x, y0 + y, Plane(x, y));
  for (int k = 0; k < 500; ++k) {
    const double x = 50.0 * rng.Next(), y = 50.0 * rng.Next();
    pts.emplace_back(x0 + x, y0 + y, Plane(x, y));
  }
  const core::HeightGrid g = Grid(pts, 1.0);
  EXPECT_EQ(CountHoles(g), 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      EXPECT_NEAR(g.z[g.index(i, j)], Plane(g.x(i) - x0, g.y(j) - y0), 1e-7) << i << "," << j;
}

}  // namespace gridding_test
}  // namespace rockcal::sites
