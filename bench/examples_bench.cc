// Wall time of the three example sites (tutorial, profile2d, authume) as the
// command line runs them (the site's own rocks, seed and options), at 1 and at
// 2 threads. Prints medians of several runs.
//   examples_bench [runs=5] [sites_dir=sites/examples]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "rockcal/sites/site.h"
#include "timing.h"

int main(int argc, char** argv) {
  using namespace rockcal;
  const int runs = argc > 1 ? std::atoi(argv[1]) : 5;
  std::string dir = argc > 2 ? argv[2] : "sites/examples";
  if (runs < 1) {
    std::fprintf(stderr, "usage: examples_bench [runs=5] [sites_dir=sites/examples]\n");
    return 2;
  }
  // Run from anywhere: without an explicit folder, fall back to the source tree's.
  if (argc <= 2 && !std::filesystem::is_directory(dir)) dir = ROCKCAL_SOURCE_DIR "/sites/examples";

  std::printf("examples_bench: example sites from %s, median of %d runs at 1 and 2 threads\n",
              dir.c_str(), runs);
  std::printf("%-10s %6s %8s %10s %12s %9s %14s %18s %9s\n", "site", "rocks", "threads", "wall_s",
              "steps", "flights", "rock_steps/s", "fixed_dt_equiv/s", "speed-up");
  for (const char* name : {"tutorial", "profile2d", "authume"}) {
    const std::string path = dir + "/" + name + "/site.json";
    sites::Site site;
    try {
      site = sites::LoadSite(path);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "examples_bench: %s\n", e.what());
      return 2;
    }
    const core::Scene& scene = site.scene;
    const core::Terrain terrain = core::BuildTerrain(scene);
    double one = 0.0;
    for (int threads : {1, 2}) {
      const bench::TimedRuns timed = bench::TimeSimulation(scene, terrain, threads, runs);
      const double w = timed.median_wall;
      const core::SimulationResult& r = timed.result;
      if (threads == 1) one = w;
      char speedup[32] = "";
      if (threads > 1) std::snprintf(speedup, sizeof speedup, "%.2fx", one / w);
      std::printf("%-10s %6zu %8d %10.3f %12ld %9ld %14.3g %18.3g %9s\n", name, r.rocks.size(),
                  threads, w, r.steps, r.flights, r.steps / w, bench::FixedStepRockSteps(r) / w,
                  speedup);
    }
    std::fflush(stdout);
  }
  std::printf(
      "rock_steps/s: contact steps per wall second (free flights are advanced exactly, not in "
      "steps);\nfixed_dt_equiv/s: the rock-steps a fixed-step engine would take for the same "
      "simulated rock time, per wall second.\n");
  return 0;
}
