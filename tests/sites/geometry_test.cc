#include "rockcal/sites/geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace rockcal::sites {
namespace {

core::HeightGrid Flat(int nx, int ny, double spacing) {
  core::HeightGrid g;
  g.x0 = 10;
  g.y0 = 20;
  g.spacing = spacing;
  g.nx = nx;
  g.ny = ny;
  g.z.assign(static_cast<std::size_t>(nx) * ny, 5.0);
  g.material.assign(g.z.size(), 0);
  return g;
}

TEST(Polygon, AreaAndInsideWithBoundary) {
  const Polygon square = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  EXPECT_DOUBLE_EQ(SignedArea(square), 16.0);
  EXPECT_DOUBLE_EQ(SignedArea({{0, 0}, {0, 4}, {4, 4}, {4, 0}}), -16.0);
  EXPECT_TRUE(PointInPolygon(square, {2, 2}));
  EXPECT_TRUE(PointInPolygon(square, {0, 2}));  // on an edge
  EXPECT_TRUE(PointInPolygon(square, {4, 4}));  // a vertex
  EXPECT_FALSE(PointInPolygon(square, {4.001, 2}));
  EXPECT_FALSE(PointInPolygon(square, {-1, -1}));
  const Polygon l_shape = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
  EXPECT_TRUE(PointInPolygon(l_shape, {0.5, 3}));
  EXPECT_FALSE(PointInPolygon(l_shape, {2, 2}));
}

TEST(FindSelfIntersection, SimpleRingsPassCrossingOrFoldedOnesAreNamed) {
  const Polygon square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_FALSE(FindSelfIntersection(square));
  Polygon closed = square;
  closed.push_back(square[0]);  // the first vertex again closes the ring
  EXPECT_FALSE(FindSelfIntersection(closed));
  const Polygon concave = {{0, 0}, {10, 0}, {10, 10}, {5, 2}, {0, 10}};
  EXPECT_FALSE(FindSelfIntersection(concave));
  // A bow tie: edges 0 and 2 cross.
  const Polygon bow = {{0, 0}, {10, 10}, {10, 0}, {0, 10}};
  const auto crossing = FindSelfIntersection(bow);
  ASSERT_TRUE(crossing);
  EXPECT_EQ(*crossing, std::make_pair(0, 2));
  // A vertex touching a far edge, and an edge folding back on its neighbour.
  EXPECT_TRUE(FindSelfIntersection(Polygon{{0, 0}, {10, 0}, {5, 0}, {5, 5}}));
  EXPECT_TRUE(FindSelfIntersection(Polygon{{0, 0}, {10, 0}, {10, 10}, {0, 5}, {10, 5}, {0, 10}}));
}

TEST(OnTerrain, InsideGridAndNoHoleCorner) {
  core::HeightGrid g = Flat(5, 4, 2.0);  // x 10..18, y 20..26
  EXPECT_TRUE(OnTerrain(g, 10, 20));
  EXPECT_TRUE(OnTerrain(g, 18, 26));
  EXPECT_FALSE(OnTerrain(g, 9.99, 22));
  EXPECT_FALSE(OnTerrain(g, 12, 26.01));
  g.z[g.index(2, 1)] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(OnTerrain(g, 13, 21));  // cell (1, 0) has the hole as a corner
  EXPECT_FALSE(OnTerrain(g, 15, 23));  // cell (2, 1) too
  EXPECT_TRUE(OnTerrain(g, 17, 25));
  EXPECT_FALSE(ElevationAt(g, 13, 21).has_value());
  ASSERT_TRUE(ElevationAt(g, 17, 25).has_value());
  EXPECT_DOUBLE_EQ(*ElevationAt(g, 17, 25), 5.0);
}

TEST(ElevationAt, LinearOnTheCellTriangles) {
  core::HeightGrid g = Flat(3, 3, 1.0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) g.z[g.index(i, j)] = 2.0 * i + 3.0 * j;
  EXPECT_DOUBLE_EQ(*ElevationAt(g, 10.25, 21.5), 2.0 * 0.25 + 3.0 * 1.5);
}

TEST(FindOffTerrain, FindsAHoleInsideTheZone) {
  core::HeightGrid g = Flat(11, 11, 1.0);  // x 10..20, y 20..30
  const Polygon zone = {{12, 22}, {18, 22}, {18, 28}, {12, 28}};
  EXPECT_FALSE(FindOffTerrain(g, zone, 0.25).has_value());
  g.z[g.index(5, 5)] = std::numeric_limits<double>::quiet_NaN();  // (15, 25), well inside
  const std::optional<Eigen::Vector2d> off = FindOffTerrain(g, zone, 0.25);
  ASSERT_TRUE(off.has_value());
  EXPECT_NEAR(off->x(), 15, 1.0);
  EXPECT_NEAR(off->y(), 25, 1.0);
  const Polygon beyond = {{18, 22}, {21, 22}, {21, 24}};
  EXPECT_TRUE(FindOffTerrain(Flat(11, 11, 1.0), beyond, 0.25).has_value());
  EXPECT_EQ(NodesInside(g, zone), 49);
}

}  // namespace
}  // namespace rockcal::sites
