// The forest twin in full (#52, bench/README.md "Forest twin"): scars at
// stems and stop points simulated through a stand at hidden runout hardness
// and roughness (tests/calibrate/forest_twin_fixture.h), calibrated at
// several seeds with the forest and with it left out (--no-forest); prints
// each calibration's error in % of the ranges and the means.
//
//   forest_twin [--rocks 400] [--evals 80] [--seeds 3] [--obs-rocks 480]
//               [--scarred 12] [--threads 2]
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "../tests/calibrate/forest_twin_fixture.h"
#include "timing.h"

namespace {
using namespace rockcal::calibrate::testing;
using rockcal::bench::Arg;
}  // namespace

int main(int argc, char** argv) {
  const int rocks = static_cast<int>(Arg(argc, argv, "rocks", 400));
  const int evals = static_cast<int>(Arg(argc, argv, "evals", 80));
  const int seeds = static_cast<int>(Arg(argc, argv, "seeds", 3));
  const int obs_rocks = static_cast<int>(Arg(argc, argv, "obs-rocks", 480));
  const int scarred = static_cast<int>(Arg(argc, argv, "scarred", 12));
  const int threads = static_cast<int>(Arg(argc, argv, "threads", 2));
  if (rocks < 10 || evals < 10 || seeds < 1 || obs_rocks < 10 || scarred < 1) {
    std::fprintf(stderr, "forest_twin: --rocks, --obs-rocks >= 10, --evals >= 10, --seeds >= 1\n");
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  const ForestTwin twin = MakeForestTwin("forest_twin_bench", obs_rocks, scarred);
  std::printf("hidden run (%d rocks): %d stems struck, %d scarred (%d scars), %d stopped\n",
              obs_rocks, twin.stems_struck, scarred, twin.scars, twin.stopped);
  std::printf("seed,forest,hardness,roughness,hardness_error_pct,roughness_error_pct\n");
  double sum[2][2] = {{0, 0}, {0, 0}};
  for (int s = 0; s < seeds; ++s) {
    for (int f = 0; f < 2; ++f) {
      const std::vector<double> x = CalibrateForestTwin(f == 0 ? twin.site : twin.bare,
                                                        twin.observations, rocks, evals,
                                                        static_cast<std::uint64_t>(2 + s), threads);
      std::printf("%d,%s,%.4f,%.4f,%+.1f,%+.1f\n", 2 + s, f == 0 ? "yes" : "no", x[0], x[1],
                  100 * ForestRangeError(x, 0), 100 * ForestRangeError(x, 1));
      std::fflush(stdout);
      for (int k = 0; k < 2; ++k) sum[f][k] += ForestRangeError(x, k);
    }
  }
  for (int f = 0; f < 2; ++f)
    std::printf("mean error, %s: hardness %+.1f %%, roughness %+.1f %% of the ranges\n",
                f == 0 ? "with the forest" : "--no-forest", 100 * sum[f][0] / seeds,
                100 * sum[f][1] / seeds);
  std::printf("%.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  std::filesystem::remove_all(twin.dir);
  return 0;
}
