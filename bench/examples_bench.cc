// Throughput of the real scenes: the example sites (tutorial, profile2d,
// authume) as the command line runs them (the site's own seed and options,
// `rocks` rocks as `--rocks` sets them) and the tumbling blocks of
// slope_scene.h, at 1 and at 2 threads (`runs` pairs of runs, medians): rocks
// per second, contact steps and flights, the 2-thread speed-up and the
// schedule's balance. Then the accuracy check of each: the
// runout and bounce-height quantiles of `check_rocks` rocks against the
// reference path's (SimulationOptions::reference_path: every lever off, at
// the scene's N_c or at reference_nc steps per contact), "ok" within two
// combined Monte Carlo errors, and the whole runout and height
// distributions by the Kolmogorov-Smirnov test, for the production path and
// for a longer gentle step (t_c/10 within the whole critical step): error
// against run time. check_rocks 0 skips it. reference "fine" checks against the
// production path itself with every step at t_c / reference_nc (default
// 800; gentle step and rest shortcut off, flights exact) instead: on
// Authume the reference path at N_c = 50 and 200 is still moving (runout
// p10 25.17, 25.45 m) where this one has settled (25.92, 25.86 m at N_c =
// 200, 800), see bench/README.md.
//   examples_bench [runs=3] [rocks=1000] [check_rocks=2000] [sites_dir=sites/examples]
//                  [reference_nc=0 (the scene's)] [reference=path|fine]
//                  [long_gentle_nc=10] [long_gentle_safety=1]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "rockcal/sites/site.h"
#include "slope_scene.h"
#include "timing.h"

namespace {

using namespace rockcal;

struct Named {
  std::string name;
  core::Scene scene;
};

// The first partition's id, for the height rows; empty without one.
std::string FirstPartition(const core::Scene& scene) {
  return scene.partitions.empty() ? std::string() : scene.partitions.front().id;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::atoi(argv[1]) : 3;
  const int rocks = argc > 2 ? std::atoi(argv[2]) : 1000;
  const int check_rocks = argc > 3 ? std::atoi(argv[3]) : 2000;
  std::string dir = argc > 4 ? argv[4] : "sites/examples";
  const int nc = argc > 5 ? std::atoi(argv[5]) : 0;
  const std::string kind = argc > 6 ? argv[6] : "path";
  const bool fine = kind == "fine";
  const int long_nc = argc > 7 ? std::atoi(argv[7]) : 10;
  const double long_safety = argc > 8 ? std::atof(argv[8]) : 1.0;
  const int reference_nc = nc == 0 && fine ? 800 : nc;
  if (runs < 1 || rocks < 1 || check_rocks < 0 || (nc != 0 && nc < 4) ||
      (kind != "path" && !fine) || long_nc < 1 || !(long_safety > 0.0)) {
    std::fprintf(stderr,
                 "usage: examples_bench [runs=3] [rocks=1000] [check_rocks=2000] "
                 "[sites_dir=sites/examples] [reference_nc=0 (the scene's; 800 for fine) or >= 4] "
                 "[reference=path|fine] [long_gentle_nc=10] [long_gentle_safety=1]\n");
    return 2;
  }
  // Run from anywhere: without an explicit folder, fall back to the source tree's.
  if (argc <= 4 && !std::filesystem::is_directory(dir)) dir = ROCKCAL_SOURCE_DIR "/sites/examples";

  std::vector<Named> scenes;
  for (const char* name : {"tutorial", "profile2d", "authume"}) {
    const std::string path = dir + "/" + name + "/site.json";
    try {
      scenes.push_back({name, sites::LoadSite(path).scene});
    } catch (const std::exception& e) {
      std::fprintf(stderr, "examples_bench: %s\n", e.what());
      return 2;
    }
  }
  scenes.push_back({"tumbling", bench::TumblingScene(rocks)});

  std::printf(
      "examples_bench: %d rocks a scene, %d pairs of runs (1 thread, then 2 threads): medians\n",
      rocks, runs);
  std::printf("%-10s %6s %8s %9s %9s %12s %9s %11s %8s %8s\n", "scene", "rocks", "threads",
              "wall_s", "rocks/s", "steps", "flights", "identical", "speed-up", "balance");
  for (Named& n : scenes) {
    n.scene.SetTotalRocks(rocks);
    const core::Terrain terrain = core::BuildTerrain(n.scene);
    const bench::ScalingRuns timed = bench::TimeScaling(n.scene, terrain, runs);
    const core::SimulationResult& first = timed.one.result;
    const core::SimulationResult& second = timed.two.result;
    bool equal = first.rocks.size() == second.rocks.size();
    for (std::size_t k = 0; equal && k < second.rocks.size(); ++k)
      equal = first.rocks[k].stop == second.rocks[k].stop &&
              first.rocks[k].time == second.rocks[k].time;
    for (int threads : {1, 2}) {
      const bench::TimedRuns& t = threads == 1 ? timed.one : timed.two;
      const double w = t.median_wall;
      char speedup[32] = "", same[8] = "", balance[16] = "";
      if (threads == 2) {
        std::snprintf(speedup, sizeof speedup, "%.2fx", timed.speedup);
        std::snprintf(same, sizeof same, "%s", equal ? "yes" : "NO");
        std::snprintf(balance, sizeof balance, "%.3f", timed.balance);
      }
      std::printf("%-10s %6zu %8d %9.3f %9.1f %12ld %9ld %11s %8s %8s\n", n.name.c_str(),
                  t.result.rocks.size(), threads, w, static_cast<double>(t.result.rocks.size()) / w,
                  t.result.figures.steps, t.result.figures.flights, same, speedup, balance);
    }
    std::fflush(stdout);
  }
  std::printf(
      "wall_s: the simulation alone (SimulationResult::wall_seconds, not building the terrain);\n"
      "identical: the 2-thread run's rocks stop where and when the 1-thread run's do;\n"
      "speed-up: the median of the pairs' ratios; balance: the share of the 2-thread run in\n"
      "which both threads were inside rocks (busy_seconds / (2 wall_s)): what the schedule loses\n"
      "is 1 - balance, the rest of a speed-up below 2x is the machine (both threads slower).\n");
  if (check_rocks == 0) return 0;

  std::printf(
      "\naccuracy: %d rocks a scene at 2 threads against %s%s\n"
      "(+- order-statistic standard error; ok: within two combined errors); long gentle:\n"
      "gentle_steps_per_contact %d, gentle_safety %g\n",
      check_rocks, fine ? "the production path's fine steps" : "the reference path",
      reference_nc > 0 ? (" at N_c = " + std::to_string(reference_nc)).c_str() : "", long_nc,
      long_safety);
  int failed = 0, differing = 0;
  for (Named& n : scenes) {
    n.scene.SetTotalRocks(check_rocks);
    n.scene.options.threads = 2;
    const core::Terrain terrain = core::BuildTerrain(n.scene);
    const core::SimulationResult production = core::Simulate(n.scene, terrain);
    core::Scene gentle = n.scene;
    gentle.options.gentle_steps_per_contact = long_nc;
    gentle.options.gentle_safety = long_safety;
    const core::SimulationResult longer = core::Simulate(gentle, terrain);
    core::Scene reference = n.scene;
    if (fine) {
      reference.options.gentle_steps_per_contact = 0;
      reference.options.rest_window = 0.0;
    } else {
      reference.options.reference_path = true;
    }
    if (reference_nc > 0) reference.options.steps_per_contact = reference_nc;
    const core::SimulationResult ref = core::Simulate(reference, terrain);
    std::printf("\n%s: stopped %d, %d and %d\n", n.name.c_str(),
                production.count(core::Outcome::kStopped), longer.count(core::Outcome::kStopped),
                ref.count(core::Outcome::kStopped));
    std::vector<int> fails, differ;
    failed += bench::PrintQuantileCheck(
        {"production", "long gentle", "reference"},
        {bench::Collect(production), bench::Collect(longer), bench::Collect(ref)},
        FirstPartition(n.scene), &fails, &differ);
    differing += differ[0] + differ[1];
    std::printf("%-26s %9.1f s %2d NO      %9.1f s %2d NO      %9.1f s\n", "wall, outside 2 errors",
                production.wall_seconds, fails[0], longer.wall_seconds, fails[1], ref.wall_seconds);
    std::printf("%-26s %12d differ %15d differ\n", "whole distributions (KS)", differ[0],
                differ[1]);
    std::fflush(stdout);
  }
  std::printf("\n%d quantiles outside two combined errors of the reference (both paths)\n", failed);
  std::printf("%d whole distributions differ from the reference's (KS p < %.2f, both paths)\n",
              differing, bench::kKsLevel);
  return 0;
}
