// The cost of a forest (issue #52): the throughput bench's slope
// (slope_scene.h) bare and with stems drawn over the whole plan at 300, 600
// and 1000 stems per hectare (DBH normal, mean 30 cm, sd 10 cm, at least
// 5 cm; 20 m tall), at one thread. Prints the median of several runs:
// contact rock-steps per second (the engine's cost per step, the figure the
// goal is set on: under 20 % below bare at 600 stems/ha), steps, flights,
// strikes, wall seconds per rock and the share of rocks stopped.
//   forest_bench [rocks=100] [runs=5]
#include <cstdio>
#include <cstdlib>
#include <random>

#include "slope_scene.h"
#include "timing.h"

namespace {

// The slope with stems at `per_ha` stems per hectare over its whole plan.
rockcal::core::Scene ForestScene(int rocks, double per_ha) {
  using namespace rockcal;
  core::Scene scene = bench::SlopeScene(rocks);
  const double x1 = (scene.grid.nx - 1) * scene.grid.spacing;
  const double y1 = (scene.grid.ny - 1) * scene.grid.spacing;
  std::mt19937_64 gen(52);
  std::poisson_distribution<int> count(per_ha * 1e-4 * x1 * y1);
  std::uniform_real_distribution<double> ux(0.0, x1), uy(0.0, y1);
  std::normal_distribution<double> dbh(0.30, 0.10);
  for (int k = count(gen); k > 0; --k) {
    const double x = ux(gen), y = uy(gen);
    double d = dbh(gen);
    while (d < 0.05) d = dbh(gen);
    scene.forest.Add(x, y, d, 20.0, core::SpeciesClass::kConifer);
  }
  scene.options.record.tree_strikes = per_ha > 0;
  return scene;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace rockcal;
  const int rocks = argc > 1 ? std::atoi(argv[1]) : 100;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  if (rocks < 1 || runs < 1) {
    std::fprintf(stderr, "usage: forest_bench [rocks=100] [runs=5] (both >= 1)\n");
    return 2;
  }
  std::printf("forest_bench: rough 35-degree slope, %d sphere rocks, 1 thread, median of %d runs\n",
              rocks, runs);
  std::printf("%-10s %7s %10s %12s %8s %8s %14s %10s %8s %9s\n", "stems/ha", "stems", "wall_s",
              "steps", "flights", "strikes", "rock_steps/s", "s/rock", "stopped", "vs_bare");
  double bare = 0.0;
  for (double per_ha : {0.0, 300.0, 600.0, 1000.0}) {
    const core::Scene scene = ForestScene(rocks, per_ha);
    const core::Terrain terrain = core::BuildTerrain(scene);
    const bench::TimedRuns timed = bench::TimeSimulation(scene, terrain, 1, runs);
    const core::SimulationResult& r = timed.result;
    long strikes = 0;
    for (const core::RockRecord& rec : r.rocks) strikes += static_cast<long>(rec.strikes.size());
    const double rate = r.figures.steps / timed.median_wall;
    if (per_ha == 0.0) bare = rate;
    std::printf("%-10.0f %7zu %10.3f %12ld %8ld %8ld %14.4g %10.4f %8d %8.1f%%\n", per_ha,
                scene.forest.stems.size(), timed.median_wall, r.figures.steps, r.figures.flights,
                strikes, rate, timed.median_wall / rocks, r.count(core::Outcome::kStopped),
                100.0 * (bare / rate - 1.0));
  }
  return 0;
}
