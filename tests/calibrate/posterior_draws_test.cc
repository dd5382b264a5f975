#include "rockcal/calibrate/posterior_draws.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../sites/test_files.h"
#include "default_table_fixture.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/core/statistics.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using sites::testing::ErrorOf;
using ::testing::HasSubstr;

// The twin's slope hardness drawn from four samples, and the scene of a
// set: the twin at its values, recording the partitions.
struct Draws {
  sites::Site site = testing::TwinSite(9);
  CalibratedSite parameters;
  std::vector<std::vector<double>> samples = {{0.3}, {0.5}, {0.7}, {0.75}};
  Draws() {
    parameters.file = "twin/parameters.json";
    parameters.samples_file = "twin/posterior.csv";
    parameters.parameters = {testing::P("slope", "slope", "hardness", 0.5, 0.2, 0.8)};
  }
  core::Scene SceneFor(const CalibratedSite& values) const {
    core::Scene scene = site.scene;
    ApplyParameters(values, &scene);
    scene.options.threads = 1;
    RecordingNeeds needs;
    needs.partitions = true;
    scene.options.record = RecordingFor(scene, needs);
    return scene;
  }
  PosteriorRun Run(int draws) const {
    PosteriorDrawOptions options;
    options.draws = draws;
    options.seed = 4;
    return SimulatePosteriorDraws(
        parameters, samples, options,
        [this](const CalibratedSite& values) { return SceneFor(values); }, "draws");
  }
};

// Rock i is simulated with draw i mod D's values, exactly as the whole run
// at those values simulates it; each draw's statistics are its own rocks'
// and each band holds the 5, 50 and 95 % quantiles of the draws' values.
TEST(SimulatePosteriorDraws, RockIWithDrawIModDAndTheBandsOverTheDraws) {
  const Draws d;
  const PosteriorRun run = d.Run(3);
  ASSERT_EQ(run.draws.size(), 3u);
  EXPECT_EQ(run.samples, 4);
  ASSERT_EQ(run.pooled.rocks.size(), 9u);
  for (std::size_t k = 0; k < 3; ++k) {
    const PosteriorDraw& draw = run.draws[k];
    EXPECT_EQ(draw.values, d.samples[static_cast<std::size_t>(draw.sample)]);
    EXPECT_EQ(draw.rocks, 3);
    CalibratedSite values = d.parameters;
    values.parameters[0].value = draw.values[0];
    const core::Scene scene = d.SceneFor(values);
    const core::SimulationResult whole = core::Simulate(scene, core::BuildTerrain(scene));
    for (std::size_t i = k; i < 9; i += 3) {
      EXPECT_EQ(run.pooled.rocks[i].rock, static_cast<int>(i));
      EXPECT_EQ(run.pooled.rocks[i].stop, whole.rocks[i].stop) << "rock " << i << ", draw " << k;
    }
  }
  auto band = [&](const std::string& where, const std::string& quantity) {
    for (const DrawBand& b : run.bands)
      if (b.where == where && b.quantity == quantity) return b;
    ADD_FAILURE() << "no band " << where << " " << quantity;
    return DrawBand{};
  };
  auto expect_quantiles = [](const DrawBand& b, std::vector<double> v) {
    EXPECT_EQ(b.p05, core::QuantileOf(&v, 0.05)) << b.where << " " << b.quantity;
    EXPECT_EQ(b.median, core::QuantileOf(&v, 0.5)) << b.where << " " << b.quantity;
    EXPECT_EQ(b.p95, core::QuantileOf(&v, 0.95)) << b.where << " " << b.quantity;
  };
  std::vector<double> runout, passed;
  for (const PosteriorDraw& draw : run.draws) {
    runout.push_back(draw.stats.runout_x.p50);
    passed.push_back(static_cast<double>(draw.stats.partitions[1].passed) / draw.rocks);
  }
  expect_quantiles(band("runout", "x_m.p50"), runout);
  expect_quantiles(band("Q", "passed_fraction"), passed);
  EXPECT_EQ(band("Q", "energy_kj.max").unit, "kJ");
  EXPECT_TRUE(run.raster_bands.empty()) << "no passages recorded, no map bands";
}

TEST(SimulatePosteriorDraws, MoreDrawsThanRocksOrSamplesAreNamed) {
  Draws d;
  EXPECT_THAT(ErrorOf([&] { d.Run(5); }),
              HasSubstr("draws: 5 draws from 4 posterior samples (twin/posterior.csv)"));
  d.site = testing::TwinSite(2);
  EXPECT_THAT(ErrorOf([&] { d.Run(3); }), HasSubstr("draws: 3 draws for 2 rocks"));
  EXPECT_THAT(ErrorOf([&] { d.Run(0); }), HasSubstr("draws = 0: must be in [1, 10000]"));
}

}  // namespace
}  // namespace rockcal::calibrate
