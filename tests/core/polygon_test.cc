#include "rockcal/core/polygon.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace rockcal::core
