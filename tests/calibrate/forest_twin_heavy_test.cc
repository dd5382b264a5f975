// The forest twin (#52; tests/calibrate/forest_twin_fixture.h): scars at
// stems and stop points simulated through a stand at hidden runout hardness
// and roughness, calibrated with the forest and with it left out (calibrate
// --no-forest). Labelled "heavy": it needs the optimised build. The full
// twin, with more rocks and seeds, is bench/forest_twin.cc (bench/README.md,
// "Forest twin").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "forest_twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using namespace testing;

// The bench at 400 and 800 rocks and 80 evaluations finds the calibration
// with the forest unbiased (both values within 1.1 % of their ranges on
// average over 6-8 seeds) but a single calibration's hardness scattered by
// about 4 % (sd) about it. At this cost (two calibrations of 40 evaluations
// of 100 rocks) one calibration is not within 5 % at every seed; the test
// checks a looser recovery, 15 %, and the direction of the --no-forest bias:
// the bare ground takes the stand's braking, so its calibrated runout is
// softer (lower hardness) or rougher than the forest's, and further from the
// hidden values.
constexpr int kRocks = 100, kEvals = 40, kHiddenRocks = 240, kScarred = 12;

TEST(Calibration, ForestTwinRecoversTheHiddenValuesLooselyAndNoForestIsBiased) {
  const ForestTwin twin = MakeForestTwin("forest_twin_heavy", kHiddenRocks, kScarred);
  std::printf("hidden run: %d stems struck, %d scars on %d stems, %d of %d stopped\n",
              twin.stems_struck, twin.scars, kScarred, twin.stopped, kHiddenRocks);
  const std::vector<double> forest =
      CalibrateForestTwin(twin.site, twin.observations, kRocks, kEvals, 2);
  const std::vector<double> bare =
      CalibrateForestTwin(twin.bare, twin.observations, kRocks, kEvals, 2);
  double forest_error = 0, bare_error = 0;
  for (int k = 0; k < 2; ++k) {
    std::printf("%s: hidden %g; with the forest %.3f (%+.1f %% of the range), --no-forest %.3f "
                "(%+.1f %%)\n",
                k == 0 ? "runout.hardness" : "runout.roughness", kForestHidden[k], forest[k],
                100 * ForestRangeError(forest, k), bare[k], 100 * ForestRangeError(bare, k));
    EXPECT_LT(std::abs(ForestRangeError(forest, k)), 0.15) << k;
    forest_error += std::abs(ForestRangeError(forest, k));
    bare_error += std::abs(ForestRangeError(bare, k));
  }
  // Bare: softer or rougher ground, further from the hidden values.
  EXPECT_TRUE(bare[0] < forest[0] || bare[1] > forest[1]);
  EXPECT_GT(bare_error, forest_error + 0.15) << "summed |error| over both parameters";
  std::filesystem::remove_all(twin.dir);
}

}  // namespace
}  // namespace rockcal::calibrate
