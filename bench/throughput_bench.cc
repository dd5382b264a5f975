// Throughput of the engine: rocks down a rough 35-degree slope (100 m long,
// 6 m virtual spheres on a 12 ft grid, e = 0.5) onto a long runout (the scene
// of slope_scene.h), at one thread and at all threads. Prints medians of
// several runs.
//   throughput_bench [rocks=200] [runs=5]
#include <omp.h>

#include <cstdio>
#include <cstdlib>

#include "slope_scene.h"
#include "timing.h"

int main(int argc, char** argv) {
  using namespace rockcal;
  const int rocks = argc > 1 ? std::atoi(argv[1]) : 200;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  if (rocks < 1 || runs < 1) {
    std::fprintf(stderr, "usage: throughput_bench [rocks=200] [runs=5] (both >= 1)\n");
    return 2;
  }
  const core::Scene scene = bench::SlopeScene(rocks);
  const core::Terrain terrain = core::BuildTerrain(scene);
  std::printf("throughput_bench: %s, %d sphere rocks, median of %d runs\n", scene.name.c_str(),
              rocks, runs);
  std::printf("%-8s %10s %12s %8s %14s %10s\n", "threads", "wall_s", "steps", "flights",
              "rock_steps/s", "rocks/s");
  double one = 0.0;
  for (int threads : {1, omp_get_max_threads()}) {
    const bench::TimedRuns timed = bench::TimeSimulation(scene, terrain, threads, runs);
    const double w = timed.median_wall;
    const core::SimulationResult& last = timed.result;
    if (threads == 1) one = w;
    std::printf("%-8d %10.3f %12ld %8ld %14.3g %10.1f\n", threads, w, last.figures.steps,
                last.figures.flights, last.figures.steps / w, rocks / w);
    if (threads > 1) std::printf("speed-up at %d threads: %.2fx\n", threads, one / w);
    if (threads == omp_get_max_threads() && threads == 1) break;
  }
  return 0;
}
