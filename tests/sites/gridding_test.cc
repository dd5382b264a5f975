#include "rockcal/sites/gridding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace rockcal::sites {
namespace {

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

TEST(NodeCount, FloorPlusOneWithRoundingSlack) {
  EXPECT_EQ(NodeCount(10.0, 2.0), 6);
  EXPECT_EQ(NodeCount(11.9, 2.0), 6);
  EXPECT_EQ(NodeCount(3 * 0.1, 0.1), 4);  // 0.30000000000000004 / 0.1
  EXPECT_EQ(NodeCount(0.0, 1.0), 1);
}

TEST(GridPoints, ScatteredPlaneIsExactAtEveryNode) {
  Lcg rng;
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 4000; ++k) {
    const double x = 60.0 * rng.Next(), y = 30.0 * rng.Next();
    pts.emplace_back(x, y, Plane(x, y));
  }
  GriddingReport rep;
  const core::HeightGrid g = GridPoints(pts, 3.0, &rep);
  ASSERT_GE(g.nx, 20);
  ASSERT_GE(g.ny, 10);
  EXPECT_EQ(rep.from_cell + rep.from_neighbours + rep.cell_mean + rep.holes, g.nx * g.ny);
  EXPECT_EQ(rep.holes, 0);
  EXPECT_EQ(rep.cell_mean, 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      EXPECT_NEAR(g.z[g.index(i, j)], Plane(g.x(i), g.y(j)), 1e-9) << "node " << i << "," << j;
}

TEST(GridPoints, FourCornersOfAPlaneFillTheWholeGrid) {
  // The site-file example of DESIGN.md: a plane given by its four corners.
  std::vector<Eigen::Vector3d> pts;
  for (double x : {0.0, 400.0})
    for (double y : {0.0, 200.0}) pts.emplace_back(x, y, 300.0 - 0.7 * x);
  GriddingReport rep;
  const core::HeightGrid g = GridPoints(pts, 12.0, &rep);
  EXPECT_EQ(g.nx, 34);
  EXPECT_EQ(g.ny, 17);
  EXPECT_EQ(rep.holes, 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      EXPECT_NEAR(g.z[g.index(i, j)], 300.0 - 0.7 * g.x(i), 1e-9) << "node " << i << "," << j;
}

TEST(GridPoints, SmallGapIsFilledLargeGapStaysAHole) {
  std::vector<Eigen::Vector3d> pts;
  const double s = 2.0;
  for (int j = 0; j <= 150; ++j) {
    for (int i = 0; i <= 150; ++i) {
      const double x = 0.4 * i, y = 0.4 * j;  // 60 m x 60 m, 25 points per cell
      const bool small_gap = std::hypot(x - 15, y - 15) < 1.3 * s;
      const bool large_gap = std::hypot(x - 40, y - 40) < 6 * s;
      if (!small_gap && !large_gap) pts.emplace_back(x, y, Plane(x, y));
    }
  }
  GriddingReport rep;
  const core::HeightGrid g = GridPoints(pts, s, &rep);
  ASSERT_EQ(g.nx, 31);
  // The small gap: its nodes have no points of their own but are filled, exactly.
  EXPECT_GT(rep.from_neighbours, 0);
  EXPECT_NEAR(g.z[g.index(7, 7)], Plane(14, 14), 1e-9);
  EXPECT_NEAR(g.z[g.index(8, 7)], Plane(16, 14), 1e-9);
  // The large gap: no data within 2 spacings of its centre.
  EXPECT_TRUE(std::isnan(g.z[g.index(20, 20)]));
  EXPECT_TRUE(std::isnan(g.z[g.index(22, 20)]));
  EXPECT_GT(rep.holes, 0);
  EXPECT_EQ(CountHoles(g), rep.holes);
  // Every node that is not a hole is on the plane.
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.z[g.index(i, j)];
      if (!std::isnan(z)) {
        EXPECT_NEAR(z, Plane(g.x(i), g.y(j)), 1e-9) << i << "," << j;
      }
    }
  }
}

TEST(GridPoints, NeverExtrapolatesPastTheEdgeOfTheData) {
  // Data on the triangle x + y <= 40 of a 40 x 40 box.
  std::vector<Eigen::Vector3d> pts;
  for (int j = 0; j <= 80; ++j)
    for (int i = 0; i <= 80 - j; ++i) pts.emplace_back(0.5 * i, 0.5 * j, Plane(0.5 * i, 0.5 * j));
  const core::HeightGrid g = GridPoints(pts, 2.0);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x(i), y = g.y(j), z = g.z[g.index(i, j)];
      // Beyond the data by more than half a cell in x and y: no own points.
      if (x + y > 42.5) {
        EXPECT_TRUE(std::isnan(z)) << "node beyond the data " << x << "," << y << " z " << z;
      } else if (x + y <= 40) {
        EXPECT_NEAR(z, Plane(x, y), 1e-9) << x << "," << y;
      }
    }
  }
}

TEST(GridPoints, AveragesNoiseInACell) {
  Lcg rng;
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 20000; ++k) {
    const double x = 20.0 * rng.Next(), y = 20.0 * rng.Next();
    pts.emplace_back(x, y, 10.0 + 0.2 * (rng.Next() - 0.5));
  }
  const core::HeightGrid g = GridPoints(pts, 4.0);
  for (int j = 1; j + 1 < g.ny; ++j)
    for (int i = 1; i + 1 < g.nx; ++i) EXPECT_NEAR(g.z[g.index(i, j)], 10.0, 0.02);
}

}  // namespace
}  // namespace rockcal::sites
