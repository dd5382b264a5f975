// A small rough slope built in code, for the studies' tests
// (stability_test.cc, convergence_test.cc).
#ifndef ROCKCAL_TESTS_CALIBRATE_SMALL_SLOPE_H_
#define ROCKCAL_TESTS_CALIBRATE_SMALL_SLOPE_H_

#include <cmath>

#include "rockcal/core/material.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/scene.h"

namespace rockcal::calibrate::fixtures {

// A small rough slope: 35 degrees down to x = 16 m, then a flat runout to
// x = 30 m, 20 m across, 2 m grid. Hard rock on the slope, soft soil below.
// The rocks (1-1.8 m) are larger than the holes the roughest variant
// (R = s/2) leaves between virtual spheres (SmallRocksOnTheRoughestSlope
// covers smaller ones), and start away from the lateral edges.
inline core::Scene SmallSlope(double size_min = 1.0, double size_max = 1.6) {
  core::Scene scene;
  scene.name = "small slope";
  auto& g = scene.grid;
  g.spacing = 2.0;
  g.nx = 16;
  g.ny = 11;
  const double slope = std::tan(35.0 * 3.14159265358979323846 / 180.0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x(i);
      g.z.push_back(x < 16.0 ? (16.0 - x) * slope : 0.0);
      g.material.push_back(x < 14.0 ? 0 : 1);
    }
  core::Material rock;
  rock.id = "rock";
  rock.hardness = 0.6;
  rock.roughness_m = 0.2;
  core::Material soil;
  soil.id = "soil";
  soil.hardness = 0.2;
  soil.roughness_m = 0.3;
  scene.materials = {rock, soil};
  core::RockGroup spheres;
  spheres.count = 2;
  spheres.shape = core::Shape::kSphere;
  spheres.size_min = size_min;
  spheres.size_max = size_max;
  spheres.unit_weight = 26e3;
  spheres.release.zone = {{1, 9}, {3, 9}, {3, 11}, {1, 11}};
  core::RockGroup cubes = spheres;
  cubes.shape = core::Shape::kCube;
  cubes.size_min = size_min + 0.2;
  cubes.size_max = size_max + 0.2;
  scene.groups = {spheres, cubes};
  scene.partitions = {{"P-slope", core::Partition::Kind::kX, 10.0}};
  scene.options.max_time = 30.0;
  return scene;
}

}  // namespace rockcal::calibrate::fixtures

#endif  // ROCKCAL_TESTS_CALIBRATE_SMALL_SLOPE_H_
