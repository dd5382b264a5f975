// Throughput of the engine: rocks down a rough 35-degree slope (~100 m long,
// 6 m virtual spheres on a 3.66 m grid, e = 0.5) with a flat runout, at one
// thread and at all threads. Prints medians of several runs.
//   throughput_bench [rocks=200] [runs=5]
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "rockcal/core/simulate.h"

namespace {

using namespace rockcal::core;

Scene SlopeScene(int rocks) {
  const double s = 12 * kFoot, theta = 35.0 * M_PI / 180.0;
  Scene scene;
  scene.name = "rough 35-degree slope";
  scene.grid.spacing = s;
  scene.grid.nx = 40;  // 143 m: ~100 m of slope and a runout
  scene.grid.ny = 12;
  for (int j = 0; j < scene.grid.ny; ++j)
    for (int i = 0; i < scene.grid.nx; ++i) {
      const double x = i * s;
      scene.grid.z.push_back(x < 100.0 ? (100.0 - x) * std::tan(theta) : 0.0);
      scene.grid.material.push_back(0);
    }
  Material m;
  m.id = "slope";
  m.hardness = 0.5;
  m.roughness_m = 6 * kFoot;  // r = 6 ft
  scene.materials = {m};
  RockGroup g;
  g.count = rocks;
  g.shape = Shape::kSphere;
  g.size_min = 0.6;
  g.size_max = 1.2;  // 0.3-0.6 m radius
  g.unit_weight = 26e3;
  g.release.zone = {{4, 15}, {12, 15}, {12, 26}, {4, 26}};
  scene.groups = {g};
  scene.options.max_time = 60.0;
  return scene;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int rocks = argc > 1 ? std::atoi(argv[1]) : 200;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  Scene scene = SlopeScene(rocks);
  const Terrain terrain = BuildTerrain(scene);
  std::printf("throughput_bench: %s, %d sphere rocks, median of %d runs\n", scene.name.c_str(), rocks,
              runs);
  std::printf("%-8s %10s %12s %8s %14s %10s\n", "threads", "wall_s", "steps", "flights",
              "rock_steps/s", "rocks/s");
  double one = 0.0;
  for (int threads : {1, omp_get_max_threads()}) {
    scene.options.threads = threads;
    std::vector<double> wall;
    SimulationResult last;
    for (int r = 0; r < runs; ++r) {
      last = Simulate(scene, terrain);
      wall.push_back(last.wall_seconds);
    }
    const double w = Median(wall);
    if (threads == 1) one = w;
    std::printf("%-8d %10.3f %12ld %8ld %14.3g %10.1f\n", threads, w, last.steps, last.flights,
                last.steps / w, rocks / w);
    if (threads > 1) std::printf("speed-up at %d threads: %.2fx\n", threads, one / w);
    if (threads == omp_get_max_threads() && threads == 1) break;
  }
  return 0;
}
