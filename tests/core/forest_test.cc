// Trunks in the engine (docs/physics.md, "Trees"): strikes against exact
// answers of the contact law, on the production path (core::Simulate).
#include "rockcal/core/forest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "rockcal/core/simulate.h"
#include "scene_fixtures.h"

namespace rockcal::core {
namespace forest_test {

using testing::FlatScene;
using testing::GridScene;
using testing::PointGroup;
using testing::SmoothMaterial;

constexpr double kPi = 3.14159265358979323846;

TEST(StemCapacity, DorrenBergerCurveAndSpeciesFactor) {
  // 38.7 * 30^2.31 J and 38.7 * 10^2.31 J.
  EXPECT_NEAR(StemCapacity(0.30, SpeciesClass::kConifer), 99968.01, 0.1);
  EXPECT_NEAR(StemCapacity(0.10, SpeciesClass::kConifer), 7901.526, 0.01);
  EXPECT_NEAR(
      StemCapacity(0.10, SpeciesClass::kBroadleaf) / StemCapacity(0.10, SpeciesClass::kConifer),
      kBroadleafFractureFactor, 1e-12);
  EXPECT_NEAR(StemCapacity(0.10, SpeciesClass::kConifer, 2.0), 2.0 * 7901.526, 0.02);
}

TEST(Forest, IsValidNamesTheStemAndTheRule) {
  Forest f;
  f.Add(1.0, 2.0, 0.3, 20.0, SpeciesClass::kConifer);
  std::string error;
  EXPECT_TRUE(f.IsValid(&error)) << error;
  f.stems[0].dbh = -0.1;
  EXPECT_FALSE(f.IsValid(&error));
  EXPECT_NE(error.find("forest.stems[0].dbh = -0.1"), std::string::npos) << error;
}

// A sphere of diameter 1 m flying level at `speed` along +x at 5 m above a
// flat, smooth plane (41 x 21 m), towards one stem at (20, 10 + offset) of
// diameter dbh; its path sampled every millisecond.
struct Strike {
  Scene scene;
  SimulationResult result;
  double mass = 0.0;
};
Strike FlyIntoStem(double speed, double dbh, double offset, double friction,
                   double capacity_factor = 1.0, int threads = 1) {
  Strike s;
  s.scene = GridScene(
      41, 21, 1.0, [](double, double) { return 0.0; }, SmoothMaterial(0.5, 0.005, 0.5));
  RockGroup g = PointGroup(Shape::kSphere, 1.0, 19.0, 10.0 + offset, 5.0);
  g.release.velocity = Eigen::Vector3d(speed, 0.0, 0.0);
  s.scene.groups = {g};
  s.scene.forest.capacity_factor = capacity_factor;
  s.scene.forest.contact.friction = friction;
  s.scene.forest.Add(20.0, 10.0, dbh, 30.0, SpeciesClass::kConifer);
  s.scene.options.max_time = 1.0;
  s.scene.options.threads = threads;
  s.scene.options.record.trajectories = 1;
  s.scene.options.record.sample_seconds = 0.001;
  s.scene.options.record.tree_strikes = true;
  s.result = Simulate(s.scene);
  s.mass = s.result.rocks[0].mass;
  return s;
}

// The sample at time t (the first at or after it).
const TrajectorySample& At(const RockRecord& r, double t) {
  for (const TrajectorySample& p : r.trajectory)
    if (p.t >= t - 1e-12) return p;
  return r.trajectory.back();
}

double MechanicalEnergy(const Strike& s, const TrajectorySample& p) {
  const double inertia = 0.1 * s.mass * 1.0;  // (2/5) m r^2, r = 0.5 m
  return 0.5 * s.mass * p.v.squaredNorm() + 0.5 * inertia * p.w.squaredNorm() +
         s.mass * s.scene.gravity * p.x.z();
}

TEST(Forest, HeadOnStrikeBelowCapacityReboundsWithTheTrunksRestitution) {
  // 2 m/s: 2.8 kJ against 100 kJ for a 30 cm stem. No friction on the bark:
  // the level motion alone meets the trunk, and it comes back at e times
  // its speed; the trunk keeps the rest of that motion's energy.
  const Strike s = FlyIntoStem(2.0, 0.30, 0.0, 0.0);
  const RockRecord& r = s.result.rocks[0];
  ASSERT_EQ(r.strikes.size(), 1u);
  const double e = s.scene.forest.contact.restitution;
  const TrajectorySample& after = At(r, 0.5);  // the strike is over by 0.1 s
  EXPECT_NEAR(after.v.x() / (-e * 2.0), 1.0, 0.01) << "vx after " << after.v.x();
  EXPECT_NEAR(after.v.y(), 0.0, 1e-9);
  const double lost = 0.5 * s.mass * 4.0 * (1.0 - e * e);
  EXPECT_NEAR(r.strikes[0].absorbed / lost, 1.0, 0.02)
      << "absorbed " << r.strikes[0].absorbed << " J, expected " << lost;
  EXPECT_FALSE(r.strikes[0].broken);
  EXPECT_EQ(r.strikes[0].tree, 0);
  // Falling for 0.35 m / 2 m/s when it meets the trunk.
  EXPECT_NEAR(r.strikes[0].speed, std::hypot(2.0, s.scene.gravity * 0.175), 0.02);
}

TEST(Forest, StrikeAboveCapacityPassesWithItsEnergyLessTheCapacity) {
  // 10 m/s: 69 kJ against 7.9, 20 and 40 kJ for stems of 10, 15 and 20 cm
  // (the last breaks late in the strike); with friction on the bark, so the
  // energy includes the spin the strike gives.
  for (double dbh : {0.10, 0.15, 0.20}) {
    SCOPED_TRACE("dbh " + std::to_string(dbh));
    const Strike s = FlyIntoStem(10.0, dbh, 0.0, 0.5);
    const RockRecord& r = s.result.rocks[0];
    ASSERT_GE(r.strikes.size(), 1u);
    EXPECT_TRUE(r.strikes[0].broken);
    const double capacity = s.scene.forest.stems[0].capacity;
    EXPECT_NEAR(r.strikes[0].absorbed, capacity, 1e-9 * capacity);
    const double before = MechanicalEnergy(s, At(r, 0.0));
    const double after = MechanicalEnergy(s, At(r, 0.4));  // past the stem, before landing
    EXPECT_NEAR((before - after) / capacity, 1.0, 0.01)
        << "lost " << before - after << " J, capacity " << capacity << " J";
    EXPECT_GT(At(r, 0.4).x.x(), 20.5);  // through the stem's place
    EXPECT_EQ(r.strikes.size(), 1u);    // broken for this rock: not struck again
    EXPECT_LT(r.max_relative_energy_gain, 1e-3) << "energy gain";
  }
}

TEST(Forest, EccentricStrikesDeflectToTheSideOfTheOffsetSymmetrically) {
  for (double offset : {0.2, 0.45}) {
    const Strike left = FlyIntoStem(3.0, 0.30, offset, 0.5);
    const Strike right = FlyIntoStem(3.0, 0.30, -offset, 0.5);
    const TrajectorySample& a = At(left.result.rocks[0], 0.5);
    const TrajectorySample& b = At(right.result.rocks[0], 0.5);
    EXPECT_GT(a.v.y(), 0.05) << "offset " << offset;
    EXPECT_LT(b.v.y(), -0.05) << "offset " << offset;
    EXPECT_NEAR(a.v.y(), -b.v.y(), 1e-6 * std::abs(a.v.y())) << "offset " << offset;
    EXPECT_NEAR(a.v.x(), b.v.x(), 1e-6 * std::abs(a.v.x())) << "offset " << offset;
  }
  // Further off centre, less of the motion meets the trunk: less energy taken.
  const Strike near = FlyIntoStem(3.0, 0.30, 0.2, 0.0);
  const Strike far = FlyIntoStem(3.0, 0.30, 0.55, 0.0);
  EXPECT_GT(near.result.rocks[0].strikes[0].absorbed, far.result.rocks[0].strikes[0].absorbed);
}

TEST(Forest, MissesAStemItFliesOver) {
  Strike s;
  s.scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5));
  RockGroup g = PointGroup(Shape::kSphere, 1.0, 3.0, 10.0, 5.0);
  g.release.velocity = Eigen::Vector3d(5.0, 0.0, 0.0);
  s.scene.groups = {g};
  s.scene.forest.Add(5.0, 10.0, 0.3, 2.0, SpeciesClass::kConifer);  // 2 m tall, under the rock
  s.scene.options.record.tree_strikes = true;
  s.result = Simulate(s.scene);
  EXPECT_TRUE(s.result.rocks[0].strikes.empty());
}

// Rocks of diameter D rolling along +x on a smooth level plane through stems
// of diameter DBH drawn at density n: the first L metres have no stem within
// (D + DBH) / 2 of a rock's path with probability exp(-n (D + DBH) L).
struct Stand {
  Scene scene;
  double x0 = 2.0, length = 20.0, width = 600.0;
};
Stand RollingStand(int rocks, double density, int threads) {
  Stand st;
  const double nx = 35, ny = st.width / 2 + 1;
  st.scene = GridScene(
      static_cast<int>(nx), static_cast<int>(ny), 2.0, [](double, double) { return 0.0; },
      SmoothMaterial(0.3, 0.005, 0.6));
  RockGroup g = PointGroup(Shape::kSphere, 1.0, 0.0, 0.0, 0.0, rocks);
  g.release.zone = {{st.x0 - 1.0, 5.0},
                    {st.x0 - 0.999, 5.0},
                    {st.x0 - 0.999, st.width - 5.0},
                    {st.x0 - 1.0, st.width - 5.0}};
  const double speed = 6.0;
  g.release.velocity = Eigen::Vector3d(speed, 0.0, 0.0);
  g.release.angular_velocity = Eigen::Vector3d(0.0, speed / 0.5, 0.0);  // rolling
  st.scene.groups = {g};
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> ux(st.x0, st.x0 + st.length + 8.0), uy(0.0, st.width);
  std::poisson_distribution<int> count(density * (st.length + 8.0) * st.width);
  for (int k = count(gen); k > 0; --k) {
    const double x = ux(gen), y = uy(gen);
    st.scene.forest.Add(x, y, 0.3, 20.0, SpeciesClass::kConifer);
  }
  st.scene.options.max_time = 4.5;
  st.scene.options.threads = threads;
  st.scene.options.record.tree_strikes = true;
  return st;
}

TEST(Forest, ShareOfRocksRollingPastStemsUnstruckIsExponential) {
  const double n = 0.03, D = 1.0, dbh = 0.3;  // 300 stems per hectare
  const int rocks = 400;
  Stand st = RollingStand(rocks, n, 0);
  const SimulationResult result = Simulate(st.scene);
  const double reach = 0.5 * (D + dbh);
  int clear = 0, agree = 0;
  for (const RockRecord& r : result.rocks) {
    // Struck within L: its first strike is at a stem standing in the first L.
    const bool struck =
        !r.strikes.empty() &&
        st.scene.forest.stems[static_cast<std::size_t>(r.strikes[0].tree)].x <= st.x0 + st.length;
    clear += !struck;
    // The same from the stand's geometry alone.
    bool in_path = false;
    for (const Stem& s : st.scene.forest.stems)
      in_path = in_path || (s.x <= st.x0 + st.length && std::abs(s.y - r.start.y()) < reach);
    agree += in_path == struck;
  }
  const double share = static_cast<double>(clear) / rocks;
  const double expected = std::exp(-n * (D + dbh) * st.length);
  // Monte Carlo error: the rocks' draws and the stand's (width / (D + DBH)
  // independent strips).
  const double sigma = std::sqrt(expected * (1 - expected) * (1.0 / rocks + (D + dbh) / st.width));
  EXPECT_NEAR(share, expected, 3.0 * sigma) << "share " << share << " expected " << expected;
  EXPECT_GE(agree, rocks - rocks / 100)
      << agree << " of " << rocks << " rocks struck as the geometry says";
}

TEST(Forest, SameResultsAtOneAndTwoThreads) {
  Stand one = RollingStand(40, 0.06, 1);
  Stand two = RollingStand(40, 0.06, 2);
  const SimulationResult a = Simulate(one.scene), b = Simulate(two.scene);
  ASSERT_EQ(a.rocks.size(), b.rocks.size());
  int strikes = 0;
  for (std::size_t k = 0; k < a.rocks.size(); ++k) {
    EXPECT_EQ(a.rocks[k].stop, b.rocks[k].stop) << "rock " << k;
    ASSERT_EQ(a.rocks[k].strikes.size(), b.rocks[k].strikes.size()) << "rock " << k;
    for (std::size_t i = 0; i < a.rocks[k].strikes.size(); ++i) {
      EXPECT_EQ(a.rocks[k].strikes[i].tree, b.rocks[k].strikes[i].tree);
      EXPECT_EQ(a.rocks[k].strikes[i].absorbed, b.rocks[k].strikes[i].absorbed);
    }
    strikes += static_cast<int>(a.rocks[k].strikes.size());
  }
  EXPECT_GT(strikes, 5);
}

TEST(Forest, NoRecordOfStrikesUnlessAsked) {
  Stand st = RollingStand(10, 0.06, 1);
  st.scene.options.record.tree_strikes = false;
  const SimulationResult r = Simulate(st.scene);
  for (const RockRecord& rock : r.rocks) EXPECT_TRUE(rock.strikes.empty());
}

}  // namespace forest_test
}  // namespace rockcal::core
