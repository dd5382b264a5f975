// The virtual-sphere surface of the terrain, through its public queries.
#include "rockcal/core/terrain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "rockcal/core/material.h"
#include "rockcal/core/scene.h"
#include "scene_fixtures.h"

namespace rockcal::core {
namespace {

// How deep a small probe sphere sinks between the virtual spheres of two
// neighbouring nodes along the fall line of a uniform plane of angle
// `degrees` (down +x) with roughness R on a grid of spacing s: the depth of
// the probe's lowest point below the plane, measured normal to it, where the
// probe just touches the terrain (Terrain::Gap = 0) on the plane's normal
// through the midpoint of the two nodes.
double FallLineSag(double degrees, double roughness, double s, double probe) {
  const double theta = degrees * M_PI / 180.0;
  const HeightGrid grid =
      testing::GridScene(11, 5, s, [&](double x, double) { return (10 * s - x) * std::tan(theta); },
                         Material())
          .grid;
  const Terrain terrain(grid, {roughness}, probe);
  // Nodes (5, 2) and (6, 2), far from the edges (whose normals are one-sided).
  const Eigen::Vector3d mid(5.5 * s, 2 * s, 4.5 * s * std::tan(theta));
  const Eigen::Vector3d up(std::sin(theta), 0.0, std::cos(theta));
  // Gap along the normal rises with the height h of the probe's centre over
  // the plane: bisect for the touching height (a spacing below the plane the
  // probe is deep in the spheres).
  double lo = -s, hi = probe + roughness;
  EXPECT_LT(terrain.Gap(mid + lo * up, probe, 0.0), 0.0);
  EXPECT_GT(terrain.Gap(mid + hi * up, probe, 0.0), 0.0);
  for (int k = 0; k < 100; ++k) {
    const double h = 0.5 * (lo + hi);
    (terrain.Gap(mid + h * up, probe, 0.0) < 0.0 ? lo : hi) = h;
  }
  return probe - 0.5 * (lo + hi);
}

// Issue 13, finding 2: roughness R is the sag a rock feels between
// neighbouring virtual spheres along the surface, whatever the slope. (It
// was the sag on level ground only: the nodes of a slope of angle theta are
// s / cos(theta) apart along its fall line, and with R = 1 ft on a 12 ft
// grid the sag there grew to 1.35 ft at 30 degrees and 4.4 ft at 60.)
TEST(Terrain, RoughnessIsTheSagAlongTheFallLineAtAnySlope) {
  const double s = 12 * kFoot, roughness = 1 * kFoot;
  // A probe of 0.01 ft stops 0.0006 ft short of the cusp between the spheres.
  const double probe = 0.01 * kFoot;
  for (double degrees : {0.0, 30.0, 45.0, 60.0}) {
    const double sag = FallLineSag(degrees, roughness, s, probe);
    EXPECT_NEAR(sag / roughness, 1.0, 0.02)
        << degrees << " degrees: sag " << sag / kFoot << " ft, R = " << roughness / kFoot << " ft";
  }
}

// A 60-degree face 20 m high below a level plateau (x <= 10 m) and above a
// level toe, on a 1 m grid.
Terrain CrestTerrain(double roughness) {
  const double tan60 = std::tan(60.0 * M_PI / 180.0);
  const HeightGrid grid =
      testing::GridScene(
          41, 5, 1.0, [&](double x, double) { return std::clamp(20.0 - (x - 10.0) * tan60, 0.0, 20.0); },
          Material())
          .grid;
  return Terrain(grid, {roughness}, 0.2);
}

// The larger spheres of a steep face must not stand up behind its crest: a
// sphere of the face 5 m below the crest, sized for the sag along the face
// (radius 5.05 m against 1.3 m on level ground), would rise 0.8 m above the
// plateau, 2 m and more behind the crest. A sphere grows past its
// level-ground size only while it holds no other node, and the plateau
// stays as it is with level-ground spheres.
TEST(Terrain, SlopeSpheresDoNotStandUpBehindACrest) {
  const Terrain terrain = CrestTerrain(0.1);
  const HeightGrid& grid = terrain.grid();
  const double face_r = terrain.sphere_radius(grid.index(15, 2));
  EXPECT_NEAR(face_r, VirtualSphereRadius(0.1, 2.0), 1e-9) << "the middle of the face";
  double highest = -1e9, at = 0.0;
  for (double x = 1.0; x <= 8.0; x += 0.01) {
    double z = 0.0;
    ASSERT_TRUE(terrain.GroundHeight(x, 2.0, &z));
    if (z > highest) {
      highest = z;
      at = x;
    }
  }
  EXPECT_LE(highest, 20.0 + 1e-9) << "the spheres stand " << highest - 20.0
                                  << " m above the plateau at x = " << at << " m";
}

// The ground a rock rolls on (heights at partitions, trees and map cells) is
// the top of the highest virtual sphere over the point. With a small
// roughness the spheres are large (R = 0.02 m on a 1 m grid: r = 6.3 m on
// level ground), and past a crest the plateau's spheres overhang the face
// for several cells: a search of the nodes one ring around the point's cell
// missed them, and read the ground on the face up to metres too low.
TEST(Terrain, GroundHeightIsTheTopOfTheHighestSphereOverThePoint) {
  const Terrain terrain = CrestTerrain(0.02);
  const HeightGrid& grid = terrain.grid();
  int checked = 0;
  for (double x = 5.05; x < 25.0; x += 0.13)
    for (double y = 1.05; y < 3.0; y += 0.31) {
      double top = terrain.FloorHeight(x, y);
      for (int n = 0; n < grid.nx * grid.ny; ++n) {
        const Eigen::Vector3d& c = terrain.sphere_centre(n);
        const double r = terrain.sphere_radius(n);
        const double h2 = r * r - (x - c.x()) * (x - c.x()) - (y - c.y()) * (y - c.y());
        if (h2 > 0.0) top = std::max(top, c.z() + std::sqrt(h2));
      }
      double z = 0.0;
      ASSERT_TRUE(terrain.GroundHeight(x, y, &z));
      EXPECT_NEAR(z, top, 1e-9) << "at (" << x << ", " << y << ")";
      ++checked;
    }
  EXPECT_GT(checked, 500);
}


// Issue 36's finding: a point exactly on the grid's far edge, at a spacing
// whose reciprocal rounds (34 * 2.4575 * (1 / 2.4575) > 34), was off the grid.
// Points on either edge are on it; a point a millionth of a cell beyond is not.
TEST(Terrain, PointsOnTheGridsEdgesAreOnTheGrid) {
  int far_edges = 0;
  for (double s : {0.1, 0.3, 2.4575, 12 * kFoot}) {
    for (int n : {2, 8, 13, 35, 60}) {
      const HeightGrid grid =
          testing::GridScene(n, 3, s, [](double, double) { return 0.0; }, Material()).grid;
      const Terrain terrain(grid, {0.0}, 0.1);
      const double edge = (n - 1) * s;
      EXPECT_EQ(terrain.CellOf(edge, 0.0), n - 2) << "x = (n - 1) s, n " << n << ", s " << s;
      EXPECT_EQ(terrain.CellOf(0.0, 2 * s), n - 1) << "y on the far edge, n " << n << ", s " << s;
      EXPECT_EQ(terrain.CellOf(edge + 1e-6 * s, 0.0), -1) << "beyond x, n " << n << ", s " << s;
      EXPECT_EQ(terrain.CellOf(-1e-6 * s, 0.0), -1) << "before x, n " << n << ", s " << s;
      ++far_edges;
    }
  }
  EXPECT_EQ(far_edges, 4 * 5);
}

}  // namespace
}  // namespace rockcal::core
