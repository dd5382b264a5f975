#include "rockcal/core/polygon.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rockcal/core/numbers.h"

namespace rockcal::core {
namespace {

using Polygon = std::vector<Eigen::Vector2d>;

TEST(PointInPolygon, InsideOutsideAndOnTheBoundary) {
  const Polygon square = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  EXPECT_TRUE(PointInPolygon(square, {2, 2}));
  EXPECT_TRUE(PointInPolygon(square, {0, 2}));  // on an edge
  EXPECT_TRUE(PointInPolygon(square, {4, 4}));  // a vertex
  EXPECT_FALSE(PointInPolygon(square, {4.001, 2}));
  EXPECT_FALSE(PointInPolygon(square, {-1, -1}));
}

TEST(PointInPolygon, ConcaveAndSelfIntersecting) {
  const Polygon l_shape = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
  EXPECT_TRUE(PointInPolygon(l_shape, {0.5, 3}));
  EXPECT_FALSE(PointInPolygon(l_shape, {2, 2}));
  // A bow tie: each lobe is covered once, so both are inside (even-odd rule).
  const Polygon bow_tie = {{0, 0}, {4, 4}, {4, 0}, {0, 4}};
  EXPECT_TRUE(PointInPolygon(bow_tie, {0.5, 2}));
  EXPECT_TRUE(PointInPolygon(bow_tie, {3.5, 2}));
  EXPECT_FALSE(PointInPolygon(bow_tie, {2, 0.5}));
}

TEST(PointInPolygon, FewerThanThreeVerticesHoldNothing) {
  EXPECT_FALSE(PointInPolygon({}, {0, 0}));
  EXPECT_FALSE(PointInPolygon({{0, 0}, {1, 1}}, {0.5, 0.5}));
}

TEST(DiscPolygon, ItsVerticesLieOnTheCircleAroundTheCentreCounterClockwise) {
  const Eigen::Vector2d centre(33.4, 236.67);
  const Polygon disc = DiscPolygon(centre, 0.5);
  ASSERT_EQ(disc.size(), static_cast<std::size_t>(kDiscVertices));
  double area = 0.0;
  for (std::size_t k = 0; k < disc.size(); ++k) {
    EXPECT_NEAR((disc[k] - centre).norm(), 0.5, 1e-12) << k;
    const Eigen::Vector2d& a = disc[k];
    const Eigen::Vector2d& b = disc[(k + 1) % disc.size()];
    area += 0.5 * (a.x() * b.y() - b.x() * a.y());
  }
  EXPECT_NEAR(disc[0].x(), centre.x() + 0.5, 1e-12);
  EXPECT_NEAR(disc[0].y(), centre.y(), 1e-12);
  // Counter-clockwise (a positive signed area), the regular 24-gon's:
  // (n / 2) r^2 sin(2 pi / n).
  EXPECT_NEAR(area, 12.0 * 0.25 * std::sin(2.0 * kPi / 24.0), 1e-9);
  EXPECT_TRUE(PointInPolygon(disc, centre));
  EXPECT_TRUE(PointInPolygon(disc, centre + Eigen::Vector2d(0.0, 0.49)));
  EXPECT_FALSE(PointInPolygon(disc, centre + Eigen::Vector2d(0.36, 0.36)));
}

}  // namespace
}  // namespace rockcal::core
