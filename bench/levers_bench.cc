// Before/after of each lever of "leave out what the scene does not need" on
// the benchmark slope (slope_scene.h, X partition at 60 m): the production
// path, the production path with one lever off, and the reference path with
// every lever off. For each: median wall seconds at one thread, contact steps
// and flights, and the runout and bounce-height quantiles against the
// reference path's, with Monte Carlo standard errors (a lever that moves a
// quantile by more than two combined errors costs accuracy).
//   levers_bench [rocks=1000] [runs=3]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "rockcal/core/simulate.h"
#include "slope_scene.h"
#include "timing.h"

namespace {

using namespace rockcal;

struct Config {
  const char* name;
  void (*apply)(core::SimulationOptions*);
};

}  // namespace

int main(int argc, char** argv) {
  const int rocks = argc > 1 ? std::atoi(argv[1]) : 1000;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 3;
  if (rocks < 10 || runs < 1) {
    std::fprintf(stderr, "usage: levers_bench [rocks >= 10] [runs >= 1]\n");
    return 2;
  }
  core::Scene scene = bench::SlopeScene(rocks);
  scene.partitions = {{"X60", core::Partition::Kind::kX, 60.0}};
  const core::Terrain terrain = core::BuildTerrain(scene);
  const std::vector<Config> configs = {
      {"production (all levers)", [](core::SimulationOptions*) {}},
      {"gentle step off", [](core::SimulationOptions* o) { o->gentle_steps_per_contact = 0; }},
      {"exact flight off", [](core::SimulationOptions* o) { o->exact_flight = false; }},
      {"reference (all off)", [](core::SimulationOptions* o) { o->reference_path = true; }},
  };
  std::printf("levers_bench: %s, %d sphere rocks, 1 thread, median of %d runs\n",
              scene.name.c_str(), rocks, runs);
  std::printf("%-26s %8s %8s %11s %10s %9s\n", "path", "wall_s", "vs ref", "steps", "flights",
              "stopped");
  std::vector<bench::Samples> samples;
  std::vector<double> walls;
  for (const Config& c : configs) {
    core::Scene s = scene;
    c.apply(&s.options);
    const bench::TimedRuns t = bench::TimeSimulation(s, terrain, 1, runs);
    samples.push_back(bench::Collect(t.result));
    walls.push_back(t.median_wall);
    std::printf("%-26s %8.3f %8s %11ld %10ld %9d\n", c.name, t.median_wall, "",
                t.result.figures.steps, t.result.figures.flights,
                t.result.count(core::Outcome::kStopped));
  }
  std::printf("speed-up against the reference path:");
  for (std::size_t k = 0; k + 1 < configs.size(); ++k)
    std::printf(" %s %.2fx%s", configs[k].name, walls.back() / walls[k],
                k + 2 < configs.size() ? "," : "\n");
  std::printf("\nquantiles against the reference path (+- order-statistic standard error;\n"
              "ok: within two combined errors)\n");
  std::vector<std::string> names;
  for (const Config& c : configs) names.push_back(c.name);
  bench::PrintQuantileCheck(names, samples, "X60");
  return 0;
}
