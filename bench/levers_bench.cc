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

struct Samples {
  std::vector<double> runout, heights;
};

Samples Collect(const core::SimulationResult& r) {
  Samples s;
  for (const core::RockRecord& rock : r.rocks) {
    if (rock.outcome == core::Outcome::kStopped) s.runout.push_back(rock.stop.x());
    if (!rock.crossings.empty() && rock.crossings[0].crossed)
      s.heights.push_back(rock.crossings[0].height);
  }
  return s;
}

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
  std::vector<Samples> samples;
  std::vector<double> walls;
  for (const Config& c : configs) {
    core::Scene s = scene;
    c.apply(&s.options);
    const bench::TimedRuns t = bench::TimeSimulation(s, terrain, 1, runs);
    samples.push_back(Collect(t.result));
    walls.push_back(t.median_wall);
    std::printf("%-26s %8.3f %8s %11ld %10ld %9d\n", c.name, t.median_wall, "", t.result.steps,
                t.result.flights, t.result.count(core::Outcome::kStopped));
  }
  std::printf("speed-up against the reference path:");
  for (std::size_t k = 0; k + 1 < configs.size(); ++k)
    std::printf(" %s %.2fx%s", configs[k].name, walls.back() / walls[k],
                k + 2 < configs.size() ? "," : "\n");
  std::printf("\nquantiles against the reference path (+- order-statistic standard error;\n"
              "ok: within two combined errors)\n");
  std::printf("%-26s", "quantity");
  for (const Config& c : configs) std::printf(" %22s", c.name);
  std::printf("\n");
  auto row = [&](const char* label, std::vector<double> Samples::*field, double p) {
    std::printf("%-26s", label);
    const bench::QuantileEstimate ref = bench::EstimateQuantile(samples.back().*field, p);
    for (const Samples& s : samples) {
      const bench::QuantileEstimate q = bench::EstimateQuantile(s.*field, p);
      const bool ok = q.valid && ref.valid &&
                      std::abs(q.value - ref.value) <= 2.0 * std::hypot(q.se, ref.se);
      std::printf(" %9.2f +- %5.2f %-3s", q.value, q.se, &s == &samples.back() ? "" : ok ? "ok" : "NO");
    }
    std::printf("\n");
  };
  row("runout x p10 [m]", &Samples::runout, 0.1);
  row("runout x p50 [m]", &Samples::runout, 0.5);
  row("runout x p90 [m]", &Samples::runout, 0.9);
  row("height at X60 p50 [m]", &Samples::heights, 0.5);
  row("height at X60 p90 [m]", &Samples::heights, 0.9);
  row("height at X60 p95 [m]", &Samples::heights, 0.95);
  return 0;
}
