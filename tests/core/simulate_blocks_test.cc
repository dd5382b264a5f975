// SimulateRocks and JoinRockBlocks: a run split into blocks of rocks (as the
// ranks of an MPI job simulate it) joins into exactly the whole run; and
// SimulateEveryNthRock takes the whole run's rocks. RunFigures: a run's
// figures are its rocks' summed.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "rockcal/core/simulate.h"
#include "scene_fixtures.h"

namespace rockcal::core {
namespace {

// A 30 degree slope with a partition, two groups (spheres and cubes) and
// everything recorded: crossings, cells and the first rocks' paths.
Scene SlopeScene() {
  Material m = testing::SmoothMaterial(0.4, 0.005, 0.5, 0.1);
  m.roughness_m = 0.3;
  Scene scene = testing::GridScene(
      31, 9, 1.0, [](double x, double) { return std::max(0.0, 15.0 - 0.58 * x); }, m);
  scene.partitions.push_back({"P", Partition::Kind::kX, 12.0});
  RockGroup spheres = testing::PointGroup(Shape::kSphere, 0.5, 3.0, 4.0, 0.5, 5);
  spheres.size_min = 0.3;
  spheres.size_max = 0.8;
  spheres.release.zone = {{2, 2}, {5, 2}, {5, 6}, {2, 6}};
  RockGroup cubes = testing::PointGroup(Shape::kCube, 0.6, 3.0, 4.0, 0.2, 4);
  cubes.release.zone = spheres.release.zone;
  scene.groups = {spheres, cubes};
  scene.options.max_time = 6.0;
  scene.options.seed = 7;
  scene.options.record.passages = true;
  scene.options.record.trajectories = 3;
  return scene;
}

void ExpectSameRecord(const RockRecord& a, const RockRecord& b) {
  EXPECT_EQ(a.rock, b.rock);
  EXPECT_EQ(a.group, b.group);
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.stop, b.stop) << "rock " << a.rock;
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.flights, b.flights);
  ASSERT_EQ(a.crossings.size(), b.crossings.size());
  for (std::size_t p = 0; p < a.crossings.size(); ++p) {
    EXPECT_EQ(a.crossings[p].crossed, b.crossings[p].crossed);
    EXPECT_EQ(a.crossings[p].energy, b.crossings[p].energy);
  }
  ASSERT_EQ(a.cells.size(), b.cells.size());
  for (std::size_t c = 0; c < a.cells.size(); ++c) EXPECT_EQ(a.cells[c].energy, b.cells[c].energy);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  for (std::size_t s = 0; s < a.trajectory.size(); ++s)
    EXPECT_EQ(a.trajectory[s].x, b.trajectory[s].x);
}

TEST(SimulateRocks, BlocksJoinIntoTheWholeRunAndEveryNthRockIsTheWholeRunsRock) {
  const Scene scene = SlopeScene();
  const Terrain terrain = BuildTerrain(scene);
  const SimulationResult whole = Simulate(scene, terrain);
  ASSERT_EQ(whole.rocks.size(), 9u);
  // Uneven blocks, one empty, one across the two groups.
  std::vector<SimulationResult> blocks;
  for (const auto& [first, last] : {std::pair{0, 2}, {2, 2}, {2, 7}, {7, 9}})
    blocks.push_back(SimulateRocks(scene, terrain, first, last));
  EXPECT_TRUE(blocks[1].rocks.empty());
  const SimulationResult joined = JoinRockBlocks(blocks);
  ASSERT_EQ(joined.rocks.size(), whole.rocks.size());
  for (std::size_t k = 0; k < whole.rocks.size(); ++k)
    ExpectSameRecord(whole.rocks[k], joined.rocks[k]);
  EXPECT_EQ(joined.figures.rocks, whole.figures.rocks);
  EXPECT_EQ(joined.figures.steps, whole.figures.steps);
  EXPECT_EQ(joined.figures.flights, whole.figures.flights);
  EXPECT_EQ(joined.figures.gentle_steps, whole.figures.gentle_steps);
  EXPECT_EQ(joined.figures.retried_steps, whole.figures.retried_steps);
  EXPECT_EQ(joined.figures.dt_min, whole.figures.dt_min);
  EXPECT_EQ(joined.figures.dt_max, whole.figures.dt_max);
  EXPECT_EQ(joined.figures.dt_shrunk, whole.figures.dt_shrunk);
  EXPECT_EQ(joined.figures.max_relative_energy_gain, whole.figures.max_relative_energy_gain);
  EXPECT_EQ(joined.figures.max_penetration, whole.figures.max_penetration);
  EXPECT_EQ(joined.figures.non_finite, whole.figures.non_finite);
  EXPECT_EQ(joined.figures.tunneled, whole.figures.tunneled);

  // SimulateEveryNthRock: stride 4 takes rocks {1, 5} (both groups: the
  // spheres are 0-4, the cubes 5-8), exactly as in the whole run.
  const SimulationResult every = SimulateEveryNthRock(scene, terrain, 1, 4);
  ASSERT_EQ(every.rocks.size(), 2u);
  for (std::size_t k = 0; k < every.rocks.size(); ++k)
    ExpectSameRecord(whole.rocks[1 + 4 * k], every.rocks[k]);
  EXPECT_THROW(SimulateEveryNthRock(scene, terrain, 4, 4), std::invalid_argument);
  EXPECT_EQ(joined.cells_recorded, whole.cells_recorded);
}

TEST(SimulateRocks, RejectsARangeOutsideTheScene) {
  const Scene scene = SlopeScene();
  const Terrain terrain = BuildTerrain(scene);
  EXPECT_THROW(SimulateRocks(scene, terrain, 3, 2), std::invalid_argument);
  EXPECT_THROW(SimulateRocks(scene, terrain, 0, 10), std::invalid_argument);
  EXPECT_THROW(SimulateRocks(scene, terrain, -1, 2), std::invalid_argument);
}

// Two rocks by hand: the second took a shorter, shrunk step, tunneled and
// ended non-finite (its energy gain is left out of the largest).
TEST(RunFigures, ARunsFiguresAreItsRocksSummed) {
  RockRecord a;
  a.steps = 10, a.flights = 2, a.gentle_steps = 4, a.retried_steps = 1;
  a.dt = 2e-4;
  a.max_relative_energy_gain = 1e-5;
  a.max_penetration = 0.1;
  RockRecord b = a;
  b.steps = 5;
  b.dt = 1e-4;
  b.max_relative_energy_gain = std::nan("");
  b.max_penetration = 0.3;
  b.tunneled = true;
  RunFigures f;
  f += RunFigures::OfRock(a, false);
  f += RunFigures::OfRock(b, true);
  EXPECT_EQ(f.rocks, 2);
  EXPECT_EQ(f.steps, 15);
  EXPECT_EQ(f.flights, 4);
  EXPECT_EQ(f.gentle_steps, 8);
  EXPECT_EQ(f.retried_steps, 2);
  EXPECT_EQ(f.dt_min, 1e-4);
  EXPECT_EQ(f.dt_max, 2e-4);
  EXPECT_EQ(f.dt_shrunk, 1);
  EXPECT_EQ(f.max_relative_energy_gain, 1e-5);
  EXPECT_EQ(f.max_penetration, 0.3);
  EXPECT_EQ(f.non_finite, 1);
  EXPECT_EQ(f.tunneled, 1);
  // No rocks add nothing, on either side (the steps' range is not widened to 0).
  RunFigures g = f;
  g += RunFigures{};
  RunFigures h;
  h += f;
  for (const RunFigures& x : {g, h}) {
    EXPECT_EQ(x.rocks, 2);
    EXPECT_EQ(x.steps, 15);
    EXPECT_EQ(x.dt_min, 1e-4);
    EXPECT_EQ(x.dt_max, 2e-4);
  }
}

}  // namespace
}  // namespace rockcal::core
