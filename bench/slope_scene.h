// The benchmark slope shared by throughput_bench and liggghts_compare: the
// CRSP-like scene of issue #7, sphere rocks down a rough 35-degree slope.
//   - a plane 35-degree slope from x = 0 (z = 70 m) to its toe at x = 100 m,
//     then a flat runout to the end of the grid (x = 362 m), where most rocks
//     stop;
//   - a 100 x 24 node grid at 12 ft (3.66 m), 362 m by 84 m in plan;
//   - one material: hardness 0.5 (e = 0.5), contact time 5 ms (default), and
//     the roughness R = 0.43 m that gives virtual spheres of radius 6 m on
//     the slope, whose nodes are d = s / cos(35 deg) = 4.47 m apart along
//     the fall line (r = (R^2 + (d/2)^2) / (2R); R is the sag along the
//     fall line at any slope angle), and of 4.1 m on the flat runout: a
//     closed sphere surface, no holes. (Before roughness was taken along
//     the fall line, R = 0.29 m gave 6 m spheres on the slope and the
//     runout alike.)
//   - sphere rocks of diameter 0.6-1.2 m (radius 0.3-0.6 m), 26 kN/m^3,
//     released at rest near the top (x 4-12 m, y 37-48 m, the middle).
#ifndef ROCKCAL_BENCH_SLOPE_SCENE_H_
#define ROCKCAL_BENCH_SLOPE_SCENE_H_

#include <cmath>

#include "rockcal/core/scene.h"

namespace rockcal::bench {

constexpr double kSlopeDegrees = 35.0;
constexpr double kSlopeToeX = 100.0;   // m, where the slope meets the flat runout
constexpr double kSphereRadius = 6.0;  // m, the virtual spheres

// Ground elevation of the benchmark slope at x [m] (the analytic profile; the
// terrain's triangulated surface equals it wherever nodes bracket x on one side
// of the toe).
inline double SlopeGround(double x) {
  const double tan_theta = std::tan(kSlopeDegrees * M_PI / 180.0);
  return x < kSlopeToeX ? (kSlopeToeX - x) * tan_theta : 0.0;
}

// The scene with `rocks` sphere rocks and default simulation options (seed 1,
// 60 s limit, t_c / 50 steps); no partitions. `spacing` [m] other than 12 ft
// keeps the 6 m spheres on the slope and the plan extent (362 m x 84 m).
inline core::Scene SlopeScene(int rocks, double spacing = 12 * core::kFoot) {
  const double s = spacing;
  core::Scene scene;
  scene.name = "rough 35-degree slope";
  scene.grid.spacing = s;
  scene.grid.nx = static_cast<int>(std::floor(362.2 / s + 1e-9)) + 1;  // 100 at 12 ft: 362 m
  scene.grid.ny = static_cast<int>(std::floor(84.2 / s + 1e-9)) + 1;   // 24 at 12 ft: 84 m
  for (int j = 0; j < scene.grid.ny; ++j)
    for (int i = 0; i < scene.grid.nx; ++i) {
      scene.grid.z.push_back(SlopeGround(i * s));
      scene.grid.material.push_back(0);
    }
  core::Material m;
  m.id = "slope";
  m.hardness = 0.5;
  const double fall = s / std::cos(kSlopeDegrees * M_PI / 180.0);  // node distance along the slope
  m.roughness_m = kSphereRadius - std::sqrt(kSphereRadius * kSphereRadius - 0.25 * fall * fall);
  scene.materials = {m};
  core::RockGroup g;
  g.count = rocks;
  g.shape = core::Shape::kSphere;
  g.size_min = 0.6;
  g.size_max = 1.2;  // 0.3-0.6 m radius
  g.unit_weight = 26e3;
  g.release.zone = {{4, 37}, {12, 37}, {12, 48}, {4, 48}};
  scene.groups = {g};
  scene.options.max_time = 60.0;
  return scene;
}

// The same slope with tumbling blocks instead of rolling spheres: half
// cubes (8 elements), half cylinders (2 elements), 0.6-1.2 m, and an X
// partition at 60 m on the slope. The scene of issue #15's throughput.
inline core::Scene TumblingScene(int rocks) {
  core::Scene scene = SlopeScene(rocks);
  scene.name = "tumbling cubes and cylinders on the rough 35-degree slope";
  core::RockGroup cubes = scene.groups.front();
  cubes.shape = core::Shape::kCube;
  cubes.count = rocks / 2;
  core::RockGroup cylinders = cubes;
  cylinders.shape = core::Shape::kCylinder;
  cylinders.count = rocks - cubes.count;
  scene.groups = {cubes, cylinders};
  scene.partitions = {{"X60", core::Partition::Kind::kX, 60.0}};
  return scene;
}

}  // namespace rockcal::bench

#endif  // ROCKCAL_BENCH_SLOPE_SCENE_H_
