// The maps of a simulation (core/rasters.h): what each cell of the site grid
// records, checked on a flight whose heights and energies are exact.
#include "rockcal/core/rasters.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rockcal/core/simulate.h"
#include "scene_fixtures.h"

namespace rockcal::core {
namespace {

using testing::GridScene;
using testing::PointGroup;
using testing::SmoothMaterial;

constexpr double kG = kStandardGravity;

// A sphere thrown horizontally over flat ground from (2, 10): until it lands,
// its centre at plan x is at z0 - g t^2 / 2 with t = (x - 2) / u, and its
// kinetic energy is m (u^2 + (g t)^2) / 2.
struct Throw {
  double radius = 0.2, drop = 3.0, u = 6.0;
  double z0() const { return drop + radius; }
  double Time(double x) const { return (x - 2.0) / u; }
  double Height(double x) const { return z0() - 0.5 * kG * Time(x) * Time(x); }
  double Speed(double x) const { return std::sqrt(u * u + kG * kG * Time(x) * Time(x)); }
  double Energy(double mass, double x) const {
    return 0.5 * mass * (u * u + kG * kG * Time(x) * Time(x));
  }
};

TEST(Rasters, AFlightRecordsEveryCellBelowItWithItsHeightAndEnergy) {
  const Throw th;
  Scene scene = GridScene(21, 21, 1.0, [](double, double) { return 0.0; },
                          SmoothMaterial(0.3, 0.005, 0.5));
  scene.groups = {PointGroup(Shape::kSphere, 2 * th.radius, 2.0, 10.0, th.drop)};
  scene.groups[0].release.velocity = Eigen::Vector3d(th.u, 0.0, 0.0);
  scene.options.record.passages = true;
  const SimulationResult result = Simulate(scene);
  const RockRecord& r = result.rocks[0];
  const RasterSet maps = ComputeRasters(scene, result);
  ASSERT_EQ(maps.nx, 21);
  ASSERT_EQ(maps.ny, 21);
  const RasterBand* passages = maps.Find("passages");
  const RasterBand* h_max = maps.Find("height_max");
  const RasterBand* e_max = maps.Find("energy_max");
  const RasterBand* e_p95 = maps.Find("energy_p95");
  const RasterBand* v_max = maps.Find("speed_max");
  const RasterBand* v_p95 = maps.Find("speed_p95");
  ASSERT_TRUE(passages && h_max && e_max && e_p95 && v_max && v_p95);
  EXPECT_EQ(v_max->unit, "m/s");
  // The first landing: where the centre comes down to its radius.
  const double land_x = 2.0 + th.u * std::sqrt(2.0 * th.drop / kG);
  ASSERT_GT(land_x, 6.5);
  // Cells 3..6 of row 10 (x in [i - 0.5, i + 0.5]) lie wholly under the first
  // flight, every one visited (a flight is sampled every quarter cell at
  // most). The rebound (e = 0.3) stays far lower and slower, so each cell's
  // largest values are the first flight's at its upslope side, sampled
  // within a quarter cell of it.
  for (int i = 3; i <= 6; ++i) {
    const std::size_t k = static_cast<std::size_t>(10 * maps.nx + i);
    EXPECT_EQ(passages->values[k], 1.0) << "cell " << i;
    const double x_in = i - 0.5, x_in_quarter = i - 0.25;
    EXPECT_LE(h_max->values[k], th.Height(x_in) + 1e-9) << "cell " << i;
    EXPECT_GE(h_max->values[k], th.Height(x_in_quarter) - 1e-9) << "cell " << i;
    // Energy grows along the fall: largest at the downslope side.
    const double x_out = i + 0.5, x_out_quarter = i + 0.25;
    EXPECT_LE(e_max->values[k] * 1000.0, th.Energy(r.mass, x_out) * (1 + 1e-9))
        << "cell " << i;
    EXPECT_GE(e_max->values[k] * 1000.0, th.Energy(r.mass, x_out_quarter) * (1 - 1e-9))
        << "cell " << i;
    EXPECT_EQ(e_p95->values[k], e_max->values[k]) << "one rock: its value is every quantile";
    // Issue 55: the speed, largest at the downslope side like the energy.
    EXPECT_LE(v_max->values[k], th.Speed(x_out) * (1 + 1e-9)) << "cell " << i;
    EXPECT_GE(v_max->values[k], th.Speed(x_out_quarter) * (1 - 1e-9)) << "cell " << i;
    EXPECT_EQ(v_p95->values[k], v_max->values[k]) << "cell " << i;
  }
  // Nothing beside the path.
  EXPECT_EQ(passages->values[static_cast<std::size_t>(11 * maps.nx + 4)], 0.0);
  EXPECT_TRUE(std::isnan(h_max->values[static_cast<std::size_t>(11 * maps.nx + 4)]));
  EXPECT_TRUE(std::isnan(v_max->values[static_cast<std::size_t>(11 * maps.nx + 4)]));
}

// A slope with a hole, several rocks: the counts agree with the records.
TEST(Rasters, CountRocksStopsAndLeaveHolesEmpty) {
  const double tan30 = std::tan(30.0 * M_PI / 180.0);
  Material m = SmoothMaterial(0.3, 0.005, 0.6);
  m.roughness_m = 0.5;  // rough enough that some rocks stop, and some leave
  Scene scene = GridScene(
      30, 10, 2.0, [&](double x, double) { return x < 30.0 ? (30.0 - x) * tan30 : 0.0; }, m);
  const std::size_t hole = static_cast<std::size_t>(scene.grid.index(25, 1));
  scene.grid.z[hole] = std::nan("");
  scene.groups = {PointGroup(Shape::kSphere, 0.6, 4.0, 9.0, 0.5, 12)};
  scene.groups[0].release.zone = {{3, 7}, {6, 7}, {6, 11}, {3, 11}};
  scene.options.max_time = 20.0;
  scene.options.record.passages = true;
  const SimulationResult result = Simulate(scene);
  const RasterSet maps = ComputeRasters(scene, result);
  const auto& g = scene.grid;
  auto cell_of = [&](const Eigen::Vector3d& x) {
    return static_cast<int>(std::lround((x.y() - g.y0) / g.spacing)) * g.nx +
           static_cast<int>(std::lround((x.x() - g.x0) / g.spacing));
  };
  std::vector<double> count(g.z.size(), 0.0);
  int stopped = 0;
  for (const RockRecord& r : result.rocks) {
    ASSERT_FALSE(r.cells.empty());
    for (std::size_t k = 1; k < r.cells.size(); ++k)
      EXPECT_LT(r.cells[k - 1].cell, r.cells[k].cell) << "one visit per cell, by cell";
    auto has = [&](int c) {
      return std::any_of(r.cells.begin(), r.cells.end(),
                         [c](const CellVisit& v) { return v.cell == c; });
    };
    EXPECT_TRUE(has(cell_of(r.start))) << "rock " << r.rock << " starts over its cell";
    if (r.outcome == Outcome::kStopped) {
      ++stopped;
      EXPECT_TRUE(has(cell_of(r.stop))) << "rock " << r.rock << " stops over its cell";
    }
    for (const CellVisit& v : r.cells) {
      count[static_cast<std::size_t>(v.cell)] += 1.0;
      EXPECT_GE(v.energy, 0.0);
    }
  }
  ASSERT_GT(stopped, 0);
  const RasterBand* passages = maps.Find("passages");
  const RasterBand* reach = maps.Find("reach_probability");
  const RasterBand* stops = maps.Find("stop_density");
  ASSERT_TRUE(passages && reach && stops);
  double stop_sum = 0.0, most = 0.0;
  for (std::size_t k = 0; k < count.size(); ++k) {
    if (k == hole) {
      for (const RasterBand& b : maps.bands) EXPECT_TRUE(std::isnan(b.values[k])) << b.name;
      continue;
    }
    EXPECT_EQ(passages->values[k], count[k]) << "cell " << k;
    EXPECT_DOUBLE_EQ(reach->values[k], count[k] / 12.0) << "cell " << k;
    stop_sum += stops->values[k] * g.spacing * g.spacing;
    most = std::max(most, count[k]);
  }
  EXPECT_NEAR(stop_sum, stopped, 1e-9);
  EXPECT_GT(most, 1.0);
  scene.options.record.passages = false;
  const SimulationResult bare = Simulate(scene);
  for (const RockRecord& r : bare.rocks) EXPECT_TRUE(r.cells.empty()) << "not recorded unless asked";
  EXPECT_THROW(ComputeRasters(scene, bare), std::logic_error);
}

}  // namespace
}  // namespace rockcal::core
