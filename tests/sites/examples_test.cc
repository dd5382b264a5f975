// The example sites under sites/examples/ load, and the Authume site agrees
// with its field data (release square and stop points on the terrain).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "rockcal/sites/geometry.h"
#include "rockcal/sites/site.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

std::vector<int> NodesPerMaterial(const core::Scene& s) {
  std::vector<int> n(s.materials.size(), 0);
  for (std::size_t k = 0; k < s.grid.z.size(); ++k)
    if (!std::isnan(s.grid.z[k])) ++n[static_cast<std::size_t>(s.grid.material[k])];
  return n;
}

TEST(Examples, TutorialLoads) {
  const Site site = LoadSite(testing::ExampleSite("tutorial"));
  const core::Scene& s = site.scene;
  EXPECT_EQ(site.units, Units::kUS);
  EXPECT_DOUBLE_EQ(s.grid.spacing, 3.6576);
  EXPECT_EQ(s.materials.size(), 3u);
  for (int n : NodesPerMaterial(s)) EXPECT_GT(n, 0);
  EXPECT_EQ(s.partitions.size(), 2u);
  ASSERT_EQ(s.groups.size(), 2u);
  EXPECT_EQ(s.total_rocks(), 100);
  EXPECT_NE(s.groups[0].shape, s.groups[1].shape);
  // Calibration bounds on the hardness and roughness of two materials.
  EXPECT_EQ(site.calibrate.size(), 4u);
  // From 300 ft (320 ft at the upper corners, the valley's sides) down to
  // about 20 ft; no holes.
  double zmin = 1e9, zmax = -1e9;
  for (double z : s.grid.z) {
    ASSERT_FALSE(std::isnan(z));
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  EXPECT_NEAR(zmax, 320 * 0.3048, 1.0);
  EXPECT_NEAR(zmin, 20 * 0.3048, 3.0);
  const std::optional<double> top = ElevationAt(s.grid, 0.0, 100 * 0.3048);
  ASSERT_TRUE(top.has_value());
  EXPECT_NEAR(*top, 300 * 0.3048, 0.5);
}

// The forest twin (sites/examples/forest_twin/README.md): the tutorial's
// terrain with a stand of 157 stems drawn from the seed, the soil's two
// values calibrated.
TEST(Examples, ForestTwinLoadsWithItsStand) {
  const Site site = LoadSite(testing::ExampleSite("forest_twin"));
  EXPECT_EQ(site.scene.forest.stems.size(), 157u);
  EXPECT_EQ(site.drawn_stems_first, 0u);
  ASSERT_EQ(site.calibrate.size(), 2u);
  EXPECT_EQ(site.calibrate[0].material, "soil");
}

TEST(Examples, Profile2dIsOneCellWide) {
  const Site site = LoadSite(testing::ExampleSite("profile2d"));
  const core::Scene& s = site.scene;
  EXPECT_EQ(site.units, Units::kSI);
  EXPECT_EQ(s.grid.ny, 2);
  EXPECT_GE(s.grid.nx, 100);
  EXPECT_EQ(s.partitions.size(), 1u);
  EXPECT_EQ(s.partitions[0].kind, core::Partition::Kind::kX);
  ASSERT_EQ(s.groups.size(), 1u);
  EXPECT_TRUE(s.groups[0].release.zone.empty());  // a release point
  for (int n : NodesPerMaterial(s)) EXPECT_GT(n, 0);
}

TEST(Examples, AuthumeMatchesItsFieldData) {
  const Site site = LoadSite(testing::ExampleSite("authume"));
  const core::Scene& s = site.scene;
  EXPECT_EQ(site.units, Units::kSI);
  EXPECT_LT(s.grid.nx * s.grid.ny, 50000);
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].id, "gray");
  EXPECT_EQ(s.materials[1].id, "red");
  EXPECT_EQ(s.materials[2].id, "blue");
  const std::vector<int> nodes = NodesPerMaterial(s);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    EXPECT_GT(nodes[k], 100) << "material " << s.materials[k].id;
  EXPECT_GE(s.total_rocks(), 41);
  for (const core::RockGroup& g : s.groups) {
    ASSERT_EQ(g.release.zone.size(), 4u);
    EXPECT_FALSE(FindOffTerrain(s.grid, g.release.zone, s.grid.spacing / 8).has_value());
  }
  // Terrain elevations of the quarry: about 153 m to 214 m.
  const std::optional<double> top = ElevationAt(s.grid, 0.3, 370.4);
  ASSERT_TRUE(top.has_value());
  EXPECT_GT(*top, 200.0);
  // Every observed stop point (Xstop, Zstop of the Y-up file) lies on the grid.
  std::ifstream in(std::string(ROCKCAL_SOURCE_DIR) +
                   "/sites/examples/authume/data/endpoints_P1.txt");
  ASSERT_TRUE(in);
  std::string line;
  std::vector<core::Block> measured;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    double x, y, z, mass, l1, l2, l3;
    if (!(row >> x >> y >> z >> mass >> l1 >> l2 >> l3)) continue;
    measured.push_back({core::Shape::kBox, Eigen::Vector3d(l1, l2, l3), mass});
    EXPECT_TRUE(OnTerrain(s.grid, x, z)) << "stop point " << x << ", " << z;
  }
  ASSERT_EQ(measured.size(), 41u);
  // The rocks are the 41 measured blocks, as boxes of their measured sides
  // and masses, dropped from the surveyed elevation (the survey's offset from
  // the terrain taken off: README.md).
  ASSERT_EQ(s.groups.size(), 1u);
  const core::RockGroup& g = s.groups[0];
  ASSERT_EQ(g.inventory.size(), measured.size());
  EXPECT_EQ(g.count, 41);
  for (std::size_t k = 0; k < measured.size(); ++k) {
    EXPECT_EQ(g.inventory[k].mass, measured[k].mass) << "block " << k;
    EXPECT_EQ(g.inventory[k].sides, measured[k].sides) << "block " << k;
    EXPECT_EQ(g.inventory[k].shape, core::Shape::kBox);
  }
  ASSERT_TRUE(g.release.elevation.has_value());
  EXPECT_NEAR(*g.release.elevation, 211.75 - 2.55, 0.01);
}

}  // namespace
}  // namespace rockcal::sites
