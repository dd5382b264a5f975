// Small scenes built in code for the core tests.
#ifndef ROCKCAL_TESTS_CORE_SCENE_FIXTURES_H_
#define ROCKCAL_TESTS_CORE_SCENE_FIXTURES_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>

#include "rockcal/core/scene.h"

namespace rockcal::core::testing {

// A grid of nx x ny nodes at `spacing` with elevation f(x, y), one material.
inline Scene GridScene(int nx, int ny, double spacing, const std::function<double(double, double)>& f,
                       const Material& material) {
  Scene scene;
  scene.name = "test";
  scene.grid.x0 = 0.0;
  scene.grid.y0 = 0.0;
  scene.grid.spacing = spacing;
  scene.grid.nx = nx;
  scene.grid.ny = ny;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      scene.grid.z.push_back(f(i * spacing, j * spacing));
      scene.grid.material.push_back(0);
    }
  scene.materials = {material};
  scene.options.max_time = 5.0;
  return scene;
}

// A smooth material with explicit restitution and friction and no rolling
// resistance (the pure CRSP-3D contact law) unless `rolling` is given.
inline Material SmoothMaterial(double restitution, double contact_time, double friction,
                               double rolling = 0.0) {
  Material m;
  m.rolling_resistance = rolling;
  m.id = "m";
  m.hardness = restitution;
  m.roughness_m = 0.0;
  m.contact_time_s = contact_time;
  m.friction = friction;
  return m;
}

// One rock group of `count` rocks released at a point.
inline RockGroup PointGroup(Shape shape, double size, double x, double y, double height,
                            int count = 1) {
  RockGroup g;
  g.count = count;
  g.shape = shape;
  g.size_min = g.size_max = size;
  g.unit_weight = 26.0e3;
  g.release.point = Eigen::Vector2d(x, y);
  g.release.height = height;
  return g;
}

// Level ground, 21 x 21 nodes 1 m apart, one material.
inline Scene FlatScene(const Material& m) {
  return GridScene(21, 21, 1.0, [](double, double) { return 0.0; }, m);
}

// The centre's first apex after the first bounce of a sampled trajectory: the
// highest point after the velocity first turns upward.
template <typename Trajectory>
double FirstApex(const Trajectory& tr) {
  std::size_t k = 0;
  while (k < tr.size() && tr[k].v.z() <= 0.0) ++k;
  double apex = -1e9;
  for (; k < tr.size() && tr[k].v.z() >= -1e-9; ++k) apex = std::max(apex, tr[k].x.z());
  return apex;
}

}  // namespace rockcal::core::testing

#endif  // ROCKCAL_TESTS_CORE_SCENE_FIXTURES_H_
