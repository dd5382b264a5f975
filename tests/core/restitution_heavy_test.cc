// Restitution of blocks landing flat, on the production path: many small
// steps of clusters of up to 32 elements, so it runs in the optimised build
// with the other numerical experiments (label "heavy").
#include <gtest/gtest.h>

#include <cmath>

#include "rockcal/core/simulate.h"
#include "scene_fixtures.h"

namespace rockcal::core {
namespace {

using testing::FirstApex;
using testing::FlatScene;
using testing::PointGroup;
using testing::SmoothMaterial;

// Issue 13, finding 4: a cluster dropped flat on one face lands on all the
// elements of that face at once (a cube: 4 of its 8; a box of sides
// 1 : 0.85 : 0.5: 16 of its 32). Like a sphere, it should rebound with the
// material's restitution e, whatever the number of its elements that touch:
// the contacts share the rock's law. (Before they did not: each took the
// whole stiffness and damping, and a cube rebounded at 0.052, 0.266 and
// 0.639 for e = 0.2, 0.5 and 0.8.) Returns the apex ratio (of the block's
// bottom face) of the first rebound.
double FlatBlockApexRatio(double e, Shape shape, const Eigen::Vector3d& box) {
  Scene scene = FlatScene(SmoothMaterial(e, 0.005, 0.5));
  const double size = 0.8, drop = 20.0;
  scene.groups = {PointGroup(shape, size, 10.0, 10.0, drop)};
  scene.groups[0].box = box;
  scene.groups[0].release.orientation = Eigen::Quaterniond::Identity();
  scene.options.max_time = 4.5;
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = 1e-4;
  const SimulationResult result = Simulate(scene);
  const auto& tr = result.rocks[0].trajectory;
  const double apex = FirstApex(tr);
  // Identity orientation: faces along the axes, the bottom face half the
  // shortest side below the centre.
  const double half = 0.5 * size * box.minCoeff() / box.maxCoeff();
  EXPECT_NEAR(tr[0].x.z() - half, drop, 1e-9);
  return (apex - half) / (tr[0].x.z() - half);
}

TEST(Simulate, FlatBlocksReboundWithTheRestitution) {
  for (double e : {0.2, 0.5, 0.8}) {
    const double cube = FlatBlockApexRatio(e, Shape::kCube, Eigen::Vector3d::Ones());
    EXPECT_NEAR(std::sqrt(cube) / e, 1.0, 0.02) << "cube, e = " << e
                                                << " rebound/impact speed = " << std::sqrt(cube);
    const double box = FlatBlockApexRatio(e, Shape::kBox, Eigen::Vector3d(1.0, 0.85, 0.5));
    EXPECT_NEAR(std::sqrt(box) / e, 1.0, 0.02) << "box, e = " << e
                                               << " rebound/impact speed = " << std::sqrt(box);
  }
}

}  // namespace
}  // namespace rockcal::core
