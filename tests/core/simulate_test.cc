// Physics of the production simulation path against exact answers.
#include "rockcal/core/simulate.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene_fixtures.h"

namespace rockcal::core {
namespace simulate_test {

using testing::FirstApex;
using testing::FlatScene;
using testing::GridScene;
using testing::PointGroup;
using testing::SmoothMaterial;

constexpr double kG = kStandardGravity;
constexpr double kDeg = 180.0 / 3.14159265358979323846;  // degrees in a radian

// Free fall from rest with a horizontal velocity, far above the ground: the
// recorded path is the parabola.
void ExpectParabola(bool exact_flight) {
  Scene scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5));
  scene.groups = {PointGroup(Shape::kSphere, 0.2, 2.0, 10.0, 50.0)};
  scene.groups[0].release.velocity = Eigen::Vector3d(3.0, 0.0, 4.0);
  scene.options.exact_flight = exact_flight;
  scene.options.max_time = 2.0;
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = 0.1;
  const SimulationResult result = Simulate(scene);
  const RockRecord& r = result.rocks[0];
  ASSERT_GE(r.trajectory.size(), 15u);
  const Eigen::Vector3d x0 = r.trajectory[0].x;
  for (const auto& s : r.trajectory) {
    if (s.t > 2.0) break;
    const Eigen::Vector3d x = x0 + Eigen::Vector3d(3.0, 0.0, 4.0) * s.t +
                              0.5 * Eigen::Vector3d(0, 0, -kG) * s.t * s.t;
    const Eigen::Vector3d v = Eigen::Vector3d(3.0, 0.0, 4.0 - kG * s.t);
    EXPECT_NEAR((s.x - x).norm() / x.norm(), 0.0, 1e-9) << "t = " << s.t << " x = " << s.x.transpose();
    EXPECT_NEAR((s.v - v).norm() / v.norm(), 0.0, 1e-9) << "t = " << s.t << " v = " << s.v.transpose();
  }
}

TEST(Simulate, FreeFallExactFlight) { ExpectParabola(true); }

// RecordOptions::trajectory_groups records the paths of every rock of those
// groups (the tracks' misfit), and of no other rock.
TEST(Simulate, RecordsThePathsOfEveryRockOfTheTrajectoryGroups) {
  Scene scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5));
  scene.groups = {PointGroup(Shape::kSphere, 0.2, 2.0, 10.0, 1.0, 2),
                  PointGroup(Shape::kSphere, 0.2, 4.0, 10.0, 1.0, 3)};
  scene.options.max_time = 2.0;
  scene.options.record.trajectory_groups = {1};
  scene.options.record.sample_seconds = 0.1;
  std::string error;
  ASSERT_TRUE(scene.options.IsValid(&error)) << error;
  const SimulationResult result = Simulate(scene);
  for (const RockRecord& r : result.rocks)
    EXPECT_EQ(r.trajectory.empty(), r.group == 0) << "rock " << r.rock << " of group " << r.group
                                                  << ": " << r.trajectory.size() << " samples";
  scene.options.record.trajectory_groups = {1, 0};
  EXPECT_FALSE(scene.options.IsValid(&error));
  EXPECT_NE(error.find("record.trajectory_groups"), std::string::npos) << error;
}
TEST(Simulate, FreeFallSmallSteps) { ExpectParabola(false); }

// Drops a sphere on flat ground; returns apex heights (of the sphere's
// bottom above the ground) of the release and of the first rebound.
std::pair<double, double> BounceApexes(const Material& m, bool rough, bool exact_flight) {
  Scene scene = FlatScene(m);
  if (rough) scene.materials[0].roughness_m = 0.1;
  // From 20 m the impact is fast enough (19.8 m/s) that gravity acting during
  // a 5 ms contact changes the rebound by well under 1 %; from 1 m it lowers
  // an e = 0.2 rebound by about 3 % (physics of the model, not numerical error).
  const double radius = 0.1, drop = 20.0;
  // Over a node (10, 10) so a rough slope offers the top of a virtual sphere.
  scene.groups = {PointGroup(Shape::kSphere, 2 * radius, 10.0, 10.0, drop)};
  scene.options.max_time = 4.5;
  scene.options.exact_flight = exact_flight;
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = 1e-4;
  const SimulationResult result = Simulate(scene);
  const auto& tr = result.rocks[0].trajectory;
  const double apex = FirstApex(tr);
  return {tr[0].x.z() - radius, apex - radius};
}

class BounceTest : public ::testing::TestWithParam<std::tuple<double, double>> {};

// The production path (exact flight to the touching point, then contact steps
// of t_c / 50).
TEST_P(BounceTest, ApexRatioIsRestitutionSquared) {
  const auto [e, tc] = GetParam();
  const auto [h0, h1] = BounceApexes(SmoothMaterial(e, tc, 0.5), false, true);
  const double ratio = h1 / h0;
  EXPECT_NEAR(ratio / (e * e), 1.0, 0.02)
      << "e = " << e << " tc = " << tc << " ratio = " << ratio << " e^2 = " << e * e;
}

INSTANTIATE_TEST_SUITE_P(Restitutions, BounceTest,
                         ::testing::Combine(::testing::Values(0.2, 0.5, 0.8),
                                            ::testing::Values(0.005, 0.0001)));

TEST(Simulate, VirtualSphereTopGivesSameRestitution) {
  for (double e : {0.2, 0.5, 0.8}) {
    const auto [h0, h1] = BounceApexes(SmoothMaterial(e, 0.005, 0.5), true, true);
    EXPECT_NEAR(h1 / h0 / (e * e), 1.0, 0.02) << "e = " << e << " ratio = " << h1 / h0;
  }
}

// A smooth 30-degree incline down +x, 60 m long.
Scene Incline30(const Material& m) {
  const double theta = 30.0 * M_PI / 180.0;
  return GridScene(61, 5, 1.0, [&](double x, double) { return (60.0 - x) * std::tan(theta); }, m);
}

// The downslope acceleration of a sphere released at rest on Incline30, from
// its speed at two times; `vegetation`: the material's undergrowth [Pa].
double InclineAcceleration(double friction, double rolling = 0.0, double vegetation = 0.0) {
  Material m = SmoothMaterial(0.3, 0.005, friction, rolling);
  m.vegetation_pa = vegetation;
  Scene scene = Incline30(m);
  scene.groups = {PointGroup(Shape::kSphere, 0.4, 5.0, 2.0, 0.0)};
  scene.options.max_time = 3.0;
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = 0.5;
  const SimulationResult result = Simulate(scene);
  const auto& tr = result.rocks[0].trajectory;
  auto speed_at = [&](double t) {
    for (const auto& s : tr)
      if (std::abs(s.t - t) < 1e-9) return s.v.norm();
    ADD_FAILURE() << "no sample at t = " << t;
    return 0.0;
  };
  return (speed_at(2.5) - speed_at(1.0)) / 1.5;
}

TEST(Simulate, SphereRollsDownIncline) {
  const double theta = 30.0 * M_PI / 180.0;
  const double expected = 5.0 / 7.0 * kG * std::sin(theta);
  const double a = InclineAcceleration(1.0);
  EXPECT_NEAR(a / expected, 1.0, 0.01) << "a = " << a << " expected " << expected;
}

// With rolling resistance mu_r (torque mu_r a N): a = 5/7 g (sin t - mu_r cos t).
TEST(Simulate, SphereRollsAgainstRollingResistance) {
  const double theta = 30.0 * M_PI / 180.0, mu_r = 0.05;
  const double expected = 5.0 / 7.0 * kG * (std::sin(theta) - mu_r * std::cos(theta));
  const double a = InclineAcceleration(1.0, mu_r);
  EXPECT_NEAR(a / expected, 1.0, 0.01) << "a = " << a << " expected " << expected;
}

TEST(Simulate, SphereSlidesDownIncline) {
  const double theta = 30.0 * M_PI / 180.0;
  const double mu = 0.1;
  const double expected = kG * (std::sin(theta) - mu * std::cos(theta));
  const double a = InclineAcceleration(mu);
  EXPECT_NEAR(a / expected, 1.0, 0.01) << "a = " << a << " expected " << expected;
}

// Undergrowth (Material::vegetation_pa = tau) pushes on the frontal area A
// of a rock touching the ground against its motion: a deceleration tau A / m
// beside gravity and friction. A 0.4 m sphere (A = pi 0.2^2, m = 26 kN/m^3 x
// its volume / g) on the 30-degree incline, tau giving 1 m/s^2.
double VegetationDeceleration(double tau) {
  const double r = 0.2;
  const double mass = 26.0e3 * (4.0 / 3.0 * M_PI * r * r * r) / kG;
  return tau * M_PI * r * r / mass;
}
double VegetationForOneMetrePerSecondSquared() { return 1.0 / VegetationDeceleration(1.0); }

// Sliding (friction 0.1, too little to roll it): a = g (sin t - mu cos t) - tau A / m.
TEST(Simulate, VegetationSlowsASlidingSphereByTauAOverM) {
  const double theta = 30.0 * M_PI / 180.0, mu = 0.1;
  const double tau = VegetationForOneMetrePerSecondSquared();
  const double expected = kG * (std::sin(theta) - mu * std::cos(theta)) - 1.0;
  const double a = InclineAcceleration(mu, 0.0, tau);
  EXPECT_NEAR(a / expected, 1.0, 0.01) << "a = " << a << " expected " << expected;
}

// Rolling (friction 1): the force acts at the centre, so the sphere rolls on
// with a = 5/7 (g sin t - tau A / m).
TEST(Simulate, VegetationSlowsARollingSphereByFiveSeventhsOfTauAOverM) {
  const double theta = 30.0 * M_PI / 180.0;
  const double tau = VegetationForOneMetrePerSecondSquared();
  const double expected = 5.0 / 7.0 * (kG * std::sin(theta) - 1.0);
  const double a = InclineAcceleration(1.0, 0.0, tau);
  EXPECT_NEAR(a / expected, 1.0, 0.01) << "a = " << a << " expected " << expected;
}

// A cube (a 2 x 2 x 2 cluster, frontal area 6 s^2 / 4) sliding on level
// ground at v stops after v^2 / (2 (mu g + tau A / m)); the deceleration
// falls as 1 / s, so the larger cube slides farther in the same undergrowth.
// Measured from 0.3 s on, once the cube released at v0 has settled on its
// face (its first hops touch the ground only part of the time, and
// undergrowth acts on a rock touching the ground).
TEST(Simulate, VegetationStopsASlidingCubeAtTheExactDistance) {
  const double mu = 0.2, v0 = 4.0, tau = 2000.0, settled = 0.3;
  for (const double size : {0.4, 0.8}) {
    for (const double t : {0.0, tau}) {
      Material m = SmoothMaterial(0.3, 0.005, mu, 0.0);
      m.vegetation_pa = t;
      Scene scene = GridScene(41, 11, 1.0, [](double, double) { return 0.0; }, m);
      RockGroup g = PointGroup(Shape::kCube, size, 5.0, 5.0, 0.0);
      g.release.velocity = Eigen::Vector3d(v0, 0.0, 0.0);
      scene.groups = {g};
      scene.options.max_time = 10.0;
      scene.options.record.trajectories = 1;
      scene.options.record.sample_seconds = 0.05;
      const RockRecord r = Simulate(scene).rocks[0];
      ASSERT_EQ(r.outcome, Outcome::kStopped) << "size " << size << " tau " << t;
      const auto from = std::find_if(r.trajectory.begin(), r.trajectory.end(),
                                     [&](const auto& q) { return q.t > settled - 1e-9; });
      ASSERT_NE(from, r.trajectory.end());
      const double v = from->v.norm();
      const double deceleration = mu * kG + t * (1.5 * size * size) / r.mass;
      const double expected = v * v / (2.0 * deceleration);
      EXPECT_NEAR((r.stop.x() - from->x.x()) / expected, 1.0, 0.01)
          << "size " << size << " tau " << t << ": slid " << r.stop.x() - from->x.x()
          << " m from " << v << " m/s, expected " << expected;
    }
  }
}

// A rough 35-degree slope with a flat runout, a few materials and shapes.
Scene RoughSlope(int rocks_per_group) {
  const double theta = 35.0 * M_PI / 180.0;
  Material rock;
  rock.id = "rock";
  rock.hardness = 0.6;
  rock.roughness_m = 0.3;
  Scene scene = GridScene(
      40, 12, 3.0, [&](double x, double) { return x < 80.0 ? (80.0 - x) * std::tan(theta) : 0.0; },
      rock);
  Material soil;
  soil.id = "soil";
  soil.hardness = 0.2;
  soil.roughness_m = 0.6;
  scene.materials.push_back(soil);
  for (int j = 0; j < scene.grid.ny; ++j)
    for (int i = 0; i < scene.grid.nx; ++i)
      if (i * 3.0 > 70.0) scene.grid.material[scene.grid.index(i, j)] = 1;
  RockGroup spheres = PointGroup(Shape::kSphere, 0.5, 6.0, 16.0, 0.0, rocks_per_group);
  spheres.size_min = 0.3;
  spheres.size_max = 0.8;
  spheres.release.zone = {{3, 12}, {9, 12}, {9, 20}, {3, 20}};
  RockGroup cubes = spheres;
  cubes.shape = Shape::kCube;
  RockGroup discs = spheres;
  discs.shape = Shape::kDisc;
  scene.groups = {spheres, cubes, discs};
  scene.options.max_time = 30.0;
  return scene;
}

// A rock at rest ends as the full wait of stop_duration would end it: the
// same outcome, at the same time to within a step, and within the 1 cm a
// still rock (every point below 0.01 m/s) can move in the rest of that
// second; in fewer steps.
TEST(Simulate, ARockAtRestEndsAsTheFullWaitWouldEndIt) {
  Scene scene = RoughSlope(6);
  Scene waiting = scene;
  waiting.options.rest_window = 0.0;
  ASSERT_GT(scene.options.rest_window, 0.0);
  const SimulationResult ended = Simulate(scene), waited = Simulate(waiting);
  // The slope's materials keep the default contact time.
  const double longest_step = Material().contact_time_s / scene.options.gentle_steps_per_contact;
  int stopped = 0;
  for (std::size_t k = 0; k < ended.rocks.size(); ++k) {
    const RockRecord &a = ended.rocks[k], &b = waited.rocks[k];
    ASSERT_EQ(a.outcome, b.outcome) << "rock " << k;
    if (a.outcome != Outcome::kStopped) continue;
    ++stopped;
    EXPECT_NEAR(a.time, b.time, longest_step) << "rock " << k;
    EXPECT_LT((a.stop - b.stop).norm(),
              0.1 * scene.options.stop_speed * scene.options.stop_duration)
        << "rock " << k;
    EXPECT_LE(a.steps, b.steps) << "rock " << k;
  }
  EXPECT_GE(stopped, 6);
  EXPECT_LT(ended.figures.steps, 0.9 * waited.figures.steps);
}

TEST(Simulate, RoughSlopeEndsCleanlyWithoutEnergyGain) {
  const Scene scene = RoughSlope(4);
  const SimulationResult result = Simulate(scene);
  EXPECT_EQ(result.figures.non_finite, 0);
  EXPECT_EQ(result.figures.tunneled, 0);
  for (const auto& r : result.rocks) {
    EXPECT_TRUE(r.stop.allFinite()) << "rock " << r.rock;
    EXPECT_FALSE(r.tunneled) << "rock " << r.rock << " " << ShapeToString(r.shape) << " size " << r.size
                             << " at " << r.stop.transpose();
    EXPECT_LT(r.max_relative_energy_gain, 1e-2)
        << "rock " << r.rock << " shape " << ShapeToString(r.shape);
  }
  EXPECT_EQ(result.count(Outcome::kStopped) + result.count(Outcome::kLeft) +
                result.count(Outcome::kTimeout),
            static_cast<int>(result.rocks.size()));
}

// The stable step is 2 / omega whatever the damping: every dashpot is
// implicit for the rock's spin as for its centre, together with the step's
// other contacts, and compressive only in that solve (JointEndMotion). A
// hardness-0 (most damped) slope keeps every rock's step at t_c / N_c, and
// no sphere, cube or disc gains energy. (With the spin explicit in the
// dashpots, the bound needed its damping term: at 2 / omega the stability
// suite's hardness-0 boxes gained up to half their energy; bench/README.md,
// "The step".)
TEST(Simulate, TheMostDampedSlopeKeepsItsStepAndAddsNoEnergy) {
  Scene scene = RoughSlope(3);
  for (Material& m : scene.materials) m.hardness = 0.0;
  scene.options.max_time = 8.0;
  const SimulationResult result = Simulate(scene);
  EXPECT_EQ(result.figures.dt_shrunk, 0);
  EXPECT_DOUBLE_EQ(result.figures.dt_max,
                   scene.materials[0].contact_time_s / scene.options.steps_per_contact);
  EXPECT_EQ(result.figures.non_finite, 0);
  for (const auto& r : result.rocks)
    EXPECT_LT(r.max_relative_energy_gain, 1e-6)
        << "rock " << r.rock << " shape " << ShapeToString(r.shape) << " size " << r.size;
}

// A sphere coming down a strip one cell wide (profile2d's: a slope, a face,
// an apron) touches the two rows of virtual spheres at once. At hardness 0,
// a contact separating faster than k d / c would pull if its dashpot were
// solved with the other contact's: solved together without it (the force
// is compressive only), no rock gains energy; solved with it, the spheres
// gained up to 0.17 % at t_c / 50.
TEST(Simulate, ASphereBetweenTwoRowsOfVirtualSpheresAddsNoEnergyAtHardnessZero) {
  Material m;
  m.id = "soft";
  m.hardness = 0.0;
  m.roughness_m = 0.4;
  // A 40-degree slope, a 30 m face and a 31-degree apron below it.
  auto ground = [](double x, double) {
    if (x < 15.0) return 72.6 - 0.84 * x;
    if (x < 19.0) return 60.0 - 7.5 * (x - 15.0);
    return 30.0 - 0.61 * (x - 19.0);
  };
  Scene scene = GridScene(61, 2, 1.0, ground, m);
  Material face = m;  // the slope and face above the apron: nearly smooth
  face.id = "face";
  face.roughness_m = 0.05;
  scene.materials.push_back(face);
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 19; ++i) scene.grid.material[scene.grid.index(i, j)] = 1;
  RockGroup spheres = PointGroup(Shape::kSphere, 1.0, 4.0, 0.5, 0.0, 20);
  spheres.size_min = 0.5;
  spheres.size_max = 1.5;
  scene.groups = {spheres};
  scene.options.max_time = 20.0;
  const SimulationResult result = Simulate(scene);
  EXPECT_EQ(result.figures.non_finite, 0);
  for (const auto& r : result.rocks)
    EXPECT_LT(r.max_relative_energy_gain, 1e-6) << "rock " << r.rock << " size " << r.size;
}

// Undergrowth only takes energy: the rough slope's rocks through it never
// gain any, and stop sooner.
TEST(Simulate, VegetationOnARoughSlopeNeverAddsEnergy) {
  Scene scene = RoughSlope(4);
  const SimulationResult bare = Simulate(scene);
  for (Material& m : scene.materials) m.vegetation_pa = 3000.0;
  const SimulationResult result = Simulate(scene);
  EXPECT_EQ(result.figures.non_finite, 0);
  double bare_run = 0.0, run = 0.0;
  for (std::size_t k = 0; k < result.rocks.size(); ++k) {
    const RockRecord& r = result.rocks[k];
    EXPECT_LT(r.max_relative_energy_gain, 1e-2) << "rock " << r.rock << " " << ShapeToString(r.shape);
    run += r.stop.x();
    bare_run += bare.rocks[k].stop.x();
  }
  EXPECT_LT(run, bare_run);
}

// With R > 0.207 s the four virtual spheres around a cell leave a hole at its
// centre; a rock smaller than the hole must be caught, never fall through.
TEST(Simulate, RoughnessHolesDoNotSwallowSmallRocks) {
  Material m;
  m.id = "coarse";
  m.hardness = 0.3;
  m.roughness_m = 0.45;  // s = 1 m: r = 0.5 m, exactly half the spacing
  Scene scene = GridScene(21, 21, 1.0, [](double, double) { return 0.0; }, m);
  RockGroup g = PointGroup(Shape::kSphere, 0.1, 10.5, 10.5, 0.5, 6);
  g.release.zone = {{9.5, 9.5}, {11.5, 9.5}, {11.5, 11.5}, {9.5, 11.5}};
  scene.groups = {g};
  const Terrain terrain = BuildTerrain(scene);
  ASSERT_GT(terrain.sag(), 0.45) << "the test needs holes at cell centres";
  const SimulationResult result = Simulate(scene, terrain);
  for (const auto& r : result.rocks) {
    // Caught (stopped, or still rolling in the cup at the time limit), not gone.
    EXPECT_NE(r.outcome, Outcome::kLeft) << "rock " << r.rock << " at " << r.stop.transpose();
    EXPECT_FALSE(r.tunneled);
    EXPECT_GE(r.stop.z(), terrain.FloorHeight(r.stop.x(), r.stop.y()));
  }
}

TEST(Simulate, TumblingCubeKeepsUnitQuaternion) {
  Scene scene = RoughSlope(1);
  scene.groups = {scene.groups[1]};
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = 0.01;
  const SimulationResult result = Simulate(scene);
  const auto& tr = result.rocks[0].trajectory;
  ASSERT_GT(tr.size(), 10u);
  double max_w = 0.0;
  for (const auto& s : tr) {
    EXPECT_NEAR(s.q.norm(), 1.0, 1e-12) << "t = " << s.t;
    max_w = std::max(max_w, s.w.norm());
  }
  EXPECT_GT(max_w, 1.0) << "the cube should tumble";
}

TEST(Simulate, SameSeedSameRecordsAtOneAndTwoThreads) {
  Scene scene = RoughSlope(4);
  scene.options.threads = 1;
  const SimulationResult one = Simulate(scene);
  scene.options.threads = 2;
  const SimulationResult two = Simulate(scene);
  ASSERT_EQ(one.rocks.size(), two.rocks.size());
  for (std::size_t k = 0; k < one.rocks.size(); ++k) {
    EXPECT_EQ(one.rocks[k].stop, two.rocks[k].stop) << "rock " << k;
    EXPECT_EQ(one.rocks[k].steps, two.rocks[k].steps) << "rock " << k;
    EXPECT_EQ(one.rocks[k].outcome, two.rocks[k].outcome) << "rock " << k;
  }
}

TEST(Simulate, MaterialChangeKeepsEveryRocksDraws) {
  Scene scene = RoughSlope(4);
  const SimulationResult base = Simulate(scene);
  scene.materials[1].hardness = 0.5;
  const SimulationResult changed = Simulate(scene);
  bool any_differs = false;
  for (std::size_t k = 0; k < base.rocks.size(); ++k) {
    EXPECT_EQ(base.rocks[k].size, changed.rocks[k].size) << "rock " << k;
    EXPECT_EQ(base.rocks[k].start, changed.rocks[k].start) << "rock " << k;
    any_differs = any_differs || base.rocks[k].stop != changed.rocks[k].stop;
  }
  EXPECT_TRUE(any_differs) << "the change should move some rock";
}

// Common random numbers need more than fixed draws: a material no rock
// reaches must not touch any rock's path, even when it sets the scene's
// finest contact step (each rock steps by the materials around it).
TEST(Simulate, UnreachedMaterialLeavesEveryRockAlone) {
  Scene scene = RoughSlope(4);
  Material far = scene.materials[0];
  far.id = "far";
  scene.materials.push_back(far);
  // Two nodes at the top corner, 13 m across the slope from the release zone.
  for (int i : {0, 1}) scene.grid.material[scene.grid.index(i, scene.grid.ny - 1)] = 2;
  const SimulationResult base = Simulate(scene);
  scene.materials[2].hardness = 0.0;         // restitution 0.01: overdamped, a shorter stable step
  scene.materials[2].contact_time_s = 5e-4;  // and a 10x shorter contact
  scene.materials[2].roughness_m = 0.9;
  const SimulationResult changed = Simulate(scene);
  for (std::size_t k = 0; k < base.rocks.size(); ++k) {
    ASSERT_GT(base.rocks[k].dt, changed.rocks[k].dt) << "the far material sets the finest step";
    EXPECT_EQ(base.rocks[k].stop, changed.rocks[k].stop) << "rock " << k;
    EXPECT_EQ(base.rocks[k].steps, changed.rocks[k].steps) << "rock " << k;
    EXPECT_EQ(base.rocks[k].flights, changed.rocks[k].flights) << "rock " << k;
    EXPECT_EQ(base.rocks[k].outcome, changed.rocks[k].outcome) << "rock " << k;
  }
}

// A tumbling box leaves a cliff and flies over two partitions: in free
// flight its kinetic plus potential energy is constant, so the energies
// recorded at the two crossings (translational + rotational, interpolated
// within an advance) differ by exactly m g times the drop between them.
TEST(Simulate, CrossingsInFlightKeepTheEnergyOfATumblingBlock) {
  const double tan40 = std::tan(40.0 * M_PI / 180.0);
  Material m = SmoothMaterial(0.6, 0.005, 0.6);
  m.roughness_m = 0.2;
  // A 40-degree slope down to x = 20 m (60 m high), then a 60 m cliff.
  Scene scene = GridScene(
      90, 12, 1.0, [&](double x, double) { return x <= 20.0 ? 60.0 + (20.0 - x) * tan40 : 0.0; },
      m);
  RockGroup g = PointGroup(Shape::kBox, 1.0, 4.0, 6.0, 0.5, 6);
  g.box = Eigen::Vector3d(1.0, 0.7, 0.4);
  scene.groups = {g};
  scene.partitions = {{"P1", Partition::Kind::kX, 23.0}, {"P2", Partition::Kind::kX, 27.5}};
  scene.options.max_time = 20.0;
  const SimulationResult result = Simulate(scene);
  int checked = 0;
  for (const RockRecord& r : result.rocks) {
    const Crossing& a = r.crossings[0];
    const Crossing& b = r.crossings[1];
    if (!a.crossed || !b.crossed) continue;
    // Both in the air, far above the cliff's foot (z = 0).
    if (a.point.z() < 5.0 || b.point.z() < 5.0) continue;
    const double drop = a.point.z() - b.point.z();
    const double expected = a.energy + r.mass * kG * drop;
    EXPECT_NEAR(b.energy, expected, 1e-6 * expected) << "rock " << r.rock;
    ++checked;
  }
  EXPECT_GE(checked, 3) << "rocks that flew over both partitions";
}

TEST(Simulate, PartitionRecordsCrossing) {
  Scene scene = RoughSlope(3);
  scene.partitions = {{"P-x", Partition::Kind::kX, 40.0}, {"P-z", Partition::Kind::kZ, 20.0}};
  const Terrain terrain = BuildTerrain(scene);
  ASSERT_GT(terrain.sag(), 0.0);
  const SimulationResult result = Simulate(scene, terrain);
  int crossed = 0;
  for (const auto& r : result.rocks) {
    ASSERT_EQ(r.crossings.size(), 2u);
    if (r.crossings[0].crossed) {
      ++crossed;
      EXPECT_NEAR(r.crossings[0].point.x(), 40.0, 1e-9);
      EXPECT_GT(r.crossings[0].height, 0.0);
      EXPECT_GT(r.crossings[0].speed, 0.0);
    }
    if (r.crossings[1].crossed) {
      // The triangulated ground at the crossing point is the partition's Z
      // (within the linear interpolation of one step); the height is measured
      // from the surface the rock touches, the virtual spheres, which sag
      // below it between the nodes by at most sag().
      const double ground = r.crossings[1].point.z() - r.crossings[1].height;
      EXPECT_LE(ground, 20.0 + 0.05);
      EXPECT_GE(ground, 20.0 - 0.05 - terrain.sag());
      EXPECT_GT(r.crossings[1].height, 0.0);
    }
  }
  EXPECT_GT(crossed, 0);
  const ResultStats stats = ComputeStats(scene, result);
  EXPECT_EQ(stats.partitions[0].passed, crossed);
}

// The runout of every rock by hand: plan distance from release to the stop
// (or the last point) and the energy-line angle; a rock that left ranks
// beyond every other, whatever its last point.
TEST(Simulate, RunoutCountsEveryRockAndRanksTheRocksThatLeftBeyond) {
  auto rock = [](Eigen::Vector3d start, Eigen::Vector3d stop, Outcome outcome) {
    RockRecord r;
    r.start = start, r.stop = stop, r.outcome = outcome;
    return r;
  };
  const Eigen::Vector3d s0(100.0, 200.0, 10.0);
  const std::vector<RockRecord> rocks = {
      rock(s0, s0 + Eigen::Vector3d(6, 8, -10), Outcome::kStopped),    // d 10, 45 deg
      rock(s0, s0 + Eigen::Vector3d(3, -4, -10), Outcome::kStopped),   // d 5, atan(2)
      rock(s0, s0 + Eigen::Vector3d(-20, 0, -10), Outcome::kStopped),  // d 20, atan(1/2)
      rock(s0, s0 + Eigen::Vector3d(0, 40, -10), Outcome::kTimeout),   // d 40, atan(1/4)
      rock(s0, s0 + Eigen::Vector3d(2, 0, -1), Outcome::kLeft)};       // beyond
  EXPECT_DOUBLE_EQ(RunoutDistance(rocks[0]), 10.0);
  EXPECT_DOUBLE_EQ(TravelAngleDeg(rocks[0]), 45.0);
  EXPECT_DOUBLE_EQ(TravelAngleDeg(rocks[1]), std::atan(2.0) * kDeg);
  EXPECT_DOUBLE_EQ(TravelAngleDeg(rock(s0, s0, Outcome::kStopped)), 90.0);
  const RunoutStats r = ComputeRunout(rocks);
  EXPECT_EQ(r.rocks, 5);
  EXPECT_EQ(r.beyond_edge, 1);
  // Distances {5, 10, 20, 40, beyond}: p10 at pos 0.4, p50 at 2, p90 at 3.6.
  EXPECT_DOUBLE_EQ(r.distance_m.p10, 7.0);
  EXPECT_DOUBLE_EQ(r.distance_m.p50, 20.0);
  EXPECT_TRUE(std::isinf(r.distance_m.p90)) << r.distance_m.p90;
  EXPECT_TRUE(std::isinf(r.distance_m.max)) << r.distance_m.max;
  // Angles {beyond, atan(1/4), atan(1/2), 45, atan(2)}.
  EXPECT_TRUE(std::isinf(r.travel_angle_deg.p10)) << r.travel_angle_deg.p10;
  EXPECT_DOUBLE_EQ(r.travel_angle_deg.p50, std::atan(0.5) * kDeg);
  EXPECT_DOUBLE_EQ(r.travel_angle_deg.p90, 45.0 + 0.6 * (std::atan(2.0) * kDeg - 45.0));
  EXPECT_DOUBLE_EQ(r.travel_angle_deg.max, std::atan(2.0) * kDeg);
}

// The fence check by the rock's lowest point, by hand: two spheres thrown
// level at 10 m/s with their centres 3.1 m above flat ground cross x = 1 m
// from their release 0.1 s later, their centres g (0.1 s)^2 / 2 lower. A
// 2.8 m fence is below both centres; the large sphere's (radius 0.5 m)
// lowest point is under it, the small one's (radius 0.1 m) above it. A
// 10 kJ capacity lies between their energies, m (v^2 + (g 0.1 s)^2) / 2.
TEST(Simulate, TheFenceIsCheckedByTheRocksLowestPoint) {
  Scene scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5));
  scene.groups = {PointGroup(Shape::kSphere, 1.0, 2.0, 10.0, 2.6),   // centre 3.1 m
                  PointGroup(Shape::kSphere, 0.2, 2.0, 10.0, 3.0)};  // centre 3.1 m
  for (RockGroup& g : scene.groups) g.release.velocity = Eigen::Vector3d(10.0, 0.0, 0.0);
  scene.partitions = {{"fence", Partition::Kind::kX, 3.0}};
  scene.options.max_time = 0.5;
  const SimulationResult result = Simulate(scene);
  const double t = 0.1, centre = 3.1 - 0.5 * kG * t * t;
  for (const RockRecord& r : result.rocks) {
    ASSERT_TRUE(r.crossings[0].crossed) << "rock " << r.rock;
    EXPECT_NEAR(r.crossings[0].height, centre, 1e-6) << "rock " << r.rock;
    EXPECT_NEAR(r.bounding_radius, 0.5 * r.size, 1e-12) << "rock " << r.rock;
    const double e = 0.5 * r.mass * (100.0 + kG * t * kG * t);
    EXPECT_NEAR(r.crossings[0].energy, e, 1e-6 * e) << "rock " << r.rock;
  }
  ASSERT_GT(result.rocks[0].crossings[0].energy, 10e3);  // 1388 kg: 70 kJ
  ASSERT_LT(result.rocks[1].crossings[0].energy, 10e3);  // 11 kg: 0.56 kJ
  const FenceCheck f = CheckFence(result, 0, 2.8, 10e3);
  EXPECT_EQ(f.passed, 2);
  EXPECT_EQ(f.over_by_centre, 2);
  EXPECT_EQ(f.over_by_top, 2);
  // A fence between the small sphere's top and the large one's: only the
  // large one's top reaches above it.
  EXPECT_EQ(CheckFence(result, 0, centre + 0.3, 1e9).over_by_top, 1);
  EXPECT_EQ(CheckFence(result, 0, centre + 0.3, 1e9).over_by_centre, 0);
  EXPECT_EQ(f.over, 1) << "only the small sphere's lowest point, " << centre - 0.1
                       << " m, clears 2.8 m; the large one's is at " << centre - 0.5 << " m";
  EXPECT_EQ(f.over_capacity, 1);
  EXPECT_EQ(f.defeated, 2);
  // Raised from just under the small sphere's lowest point to just over it,
  // the fence stops it too.
  EXPECT_EQ(CheckFence(result, 0, centre - 0.1 - 1e-3, 1e9).over, 1);
  EXPECT_EQ(CheckFence(result, 0, centre - 0.1 + 1e-3, 1e9).over, 0);
  EXPECT_EQ(CheckFence(result, 0, centre - 0.1 + 1e-3, 1e9).defeated, 0);
}

// A barrier drawn in plan, by hand: four spheres thrown along x from x = 2 m
// with their centres 3.1 m above flat ground, at y = 4, 8, 12 and 16 m,
// meet the polyline (3, 0) - (4, 10) - (3, 20) at x = 3.4, 3.8, 3.8 and
// 3.4 m (its second segment for the last two). On the exact flight a rock
// thrown at u crosses it t = (x - 2) / u later, its centre g t^2 / 2 lower,
// with kinetic energy m (u^2 + (g t)^2) / 2. The rock at y = 12 m is
// thrown at 5 m/s, the others at 10 m/s; the ones at y = 8 and 16 m are
// small (radius 0.1 m), the others large (0.5 m).
struct BarrierThrow {
  double y, size, speed, x_cross;
};
const BarrierThrow kBarrierThrows[] = {
    {4.0, 1.0, 10.0, 3.4}, {8.0, 0.2, 10.0, 3.8}, {12.0, 1.0, 5.0, 3.8}, {16.0, 0.2, 10.0, 3.4}};

Scene BarrierScene(bool stops) {
  Scene scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5));
  for (const BarrierThrow& b : kBarrierThrows) {
    scene.groups.push_back(PointGroup(Shape::kSphere, b.size, 2.0, b.y, 3.1 - b.size / 2));
    scene.groups.back().release.velocity = Eigen::Vector3d(b.speed, 0.0, 0.0);
  }
  Partition line;
  line.id = "net";
  line.kind = Partition::Kind::kLine;
  line.line = {{3.0, 0.0}, {4.0, 10.0}, {3.0, 20.0}};
  line.height = 2.8;     // m
  line.capacity = 50e3;  // J
  line.stops = stops;
  Partition behind = line;  // behind the releases: no rock reaches it
  behind.id = "behind";
  behind.line = {{1.0, 0.0}, {1.0, 20.0}};
  scene.partitions = {line, behind};
  scene.options.max_time = 3.0;
  return scene;
}

double ThrowTime(const BarrierThrow& b) { return (b.x_cross - 2.0) / b.speed; }

TEST(Simulate, ABarrierLineRecordsTheRocksThatReachIt) {
  const Scene scene = BarrierScene(false);
  const SimulationResult result = Simulate(scene);
  std::vector<double> lowest, centre, energy;
  int over = 0, over_capacity = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const BarrierThrow& b = kBarrierThrows[k];
    const RockRecord& r = result.rocks[k];
    const double t = ThrowTime(b), z = 3.1 - 0.5 * kG * t * t;
    const double e = 0.5 * r.mass * (b.speed * b.speed + kG * t * kG * t);
    ASSERT_TRUE(r.crossings[0].crossed) << "rock " << k;
    EXPECT_FALSE(r.crossings[1].crossed) << "rock " << k;
    EXPECT_NEAR(r.crossings[0].point.x(), b.x_cross, 1e-9) << "rock " << k;
    EXPECT_NEAR(r.crossings[0].point.y(), b.y, 1e-9) << "rock " << k;
    EXPECT_NEAR(r.crossings[0].height, z, 1e-9) << "rock " << k;
    EXPECT_NEAR(r.crossings[0].energy, e, 1e-9 * e) << "rock " << k;
    EXPECT_EQ(r.stopped_by, -1) << "rock " << k;
    lowest.push_back(z - b.size / 2);
    centre.push_back(z);
    energy.push_back(e);
    over += z - b.size / 2 > 2.8;
    over_capacity += e > 50e3;
  }
  // By hand: the small spheres' lowest points (3.00 and 2.94 m less 0.1 m)
  // clear 2.8 m, the large ones' (2.50 and 2.46 m) do not; the fast large
  // sphere carries 71 kJ, the slow one 26 kJ, the small ones under 1 kJ.
  ASSERT_EQ(over, 2);
  ASSERT_EQ(over_capacity, 1);
  const std::vector<BarrierStats> barriers = ComputeBarriers(scene, result);
  ASSERT_EQ(barriers.size(), 2u);
  const BarrierStats& net = barriers[0];
  EXPECT_EQ(net.partition, 0u);
  EXPECT_EQ(net.check.passed, 4);
  EXPECT_EQ(net.check.over, 2);
  EXPECT_EQ(net.check.over_by_centre, 3) << "the slow sphere's centre is at " << centre[2] << " m";
  EXPECT_EQ(net.check.over_capacity, 1);
  EXPECT_EQ(net.stopped, 0);
  std::sort(lowest.begin(), lowest.end());
  std::sort(centre.begin(), centre.end());
  std::sort(energy.begin(), energy.end());
  // Type 7 over four values: p95 = v3 + 0.85 (v4 - v3), p99 = v3 + 0.97 (v4 - v3).
  auto q = [](const std::vector<double>& v, double w) { return v[2] + w * (v[3] - v[2]); };
  EXPECT_NEAR(net.lowest_p95, q(lowest, 0.85), 1e-9);
  EXPECT_NEAR(net.lowest_p99, q(lowest, 0.97), 1e-9);
  EXPECT_NEAR(net.centre_p95, q(centre, 0.85), 1e-9);
  EXPECT_NEAR(net.centre_p99, q(centre, 0.97), 1e-9);
  EXPECT_NEAR(net.energy_p95, q(energy, 0.85), 1e-9 * energy[3]);
  EXPECT_NEAR(net.energy_p99, q(energy, 0.97), 1e-9 * energy[3]);
  EXPECT_EQ(barriers[1].check.passed, 0);
  EXPECT_TRUE(std::isnan(barriers[1].energy_p95)) << barriers[1].energy_p95;
}

// The same barrier stopping the rocks it catches: only the slow large
// sphere reaches it below its height and capacity; its run ends at the
// crossing, its runout the distance to the line. The others pass on as
// before, whether crossings are recorded or not.
TEST(Simulate, ABarrierThatStopsEndsTheRunOfTheRocksItCatches) {
  const SimulationResult free_run = Simulate(BarrierScene(false));
  for (bool record : {true, false}) {
    Scene scene = BarrierScene(true);
    scene.options.record.partitions = record;
    const SimulationResult result = Simulate(scene);
    for (std::size_t k = 0; k < 4; ++k) {
      const RockRecord& r = result.rocks[k];
      if (k != 2) {
        EXPECT_EQ(r.stopped_by, -1) << "rock " << k;
        EXPECT_EQ(r.stop, free_run.rocks[k].stop) << "rock " << k << " record " << record;
        EXPECT_EQ(r.outcome, free_run.rocks[k].outcome) << "rock " << k;
        continue;
      }
      const BarrierThrow& b = kBarrierThrows[k];
      const double t = ThrowTime(b);
      EXPECT_EQ(r.stopped_by, 0);
      EXPECT_EQ(r.outcome, Outcome::kStopped);
      EXPECT_NEAR(r.time, t, 1e-12);
      EXPECT_NEAR((r.stop - Eigen::Vector3d(b.x_cross, b.y, 3.1 - 0.5 * kG * t * t)).norm(), 0.0,
                  1e-9)
          << "stopped at " << r.stop.transpose();
      EXPECT_NEAR(RunoutDistance(r), b.x_cross - 2.0, 1e-9);
    }
    if (record) {
      const BarrierStats net = ComputeBarriers(scene, result)[0];
      EXPECT_EQ(net.check.passed, 4);
      EXPECT_EQ(net.stopped, 1);
      EXPECT_EQ(net.check.over, 2);
      EXPECT_EQ(net.check.over_capacity, 1);
    }
  }
}

// Spheres rolling from rest down the smooth 30-degree incline, at y = 1, 2
// and 3 m, meet a barrier line drawn slanting across the slope, (20, 0) -
// (30, 4), at x = 22.5, 25 and 27.5 m. Rolling without slip loses nothing:
// the kinetic energy at the crossing is m g times the centre's drop,
// (x - 5) tan 30, and the speed sqrt(10/7 g drop); the centre is r / cos 30
// above the ground. The barrier stops them: each run ends on the line.
TEST(Simulate, SpheresRollingDownAnInclineMeetABarrierLineWithTheirFallsEnergy) {
  const double theta = 30.0 * M_PI / 180.0, r = 0.2;
  Scene scene = Incline30(SmoothMaterial(0.3, 0.005, 1.0));
  for (double y : {1.0, 2.0, 3.0})
    scene.groups.push_back(PointGroup(Shape::kSphere, 2 * r, 5.0, y, 0.0));
  Partition line;
  line.id = "net";
  line.kind = Partition::Kind::kLine;
  line.line = {{20.0, 0.0}, {30.0, 4.0}};
  line.height = 2.0;
  line.capacity = 1e9;
  line.stops = true;
  scene.partitions = {line};
  scene.options.max_time = 6.0;
  const SimulationResult result = Simulate(scene);
  for (int k = 0; k < 3; ++k) {
    const RockRecord& rock = result.rocks[static_cast<std::size_t>(k)];
    const double y = 1.0 + k, x = 20.0 + 2.5 * y;
    const Crossing& c = rock.crossings[0];
    ASSERT_TRUE(c.crossed) << "rock " << k << " ended at " << rock.stop.transpose();
    const double drop = (x - 5.0) * std::tan(theta);
    EXPECT_NEAR(c.point.x(), x, 1e-3) << "rock " << k;
    EXPECT_NEAR(c.point.y(), y, 1e-3) << "rock " << k;
    EXPECT_NEAR(c.energy / (rock.mass * kG * drop), 1.0, 1e-3)
        << "rock " << k << ": " << c.energy << " J, exact " << rock.mass * kG * drop;
    EXPECT_NEAR(c.speed / std::sqrt(10.0 / 7.0 * kG * drop), 1.0, 1e-3) << "rock " << k;
    EXPECT_NEAR(c.height, r / std::cos(theta), 1e-3) << "rock " << k;
    EXPECT_EQ(rock.stopped_by, 0) << "rock " << k;
    EXPECT_EQ(rock.outcome, Outcome::kStopped) << "rock " << k;
    EXPECT_EQ(rock.stop, c.point) << "rock " << k;
  }
  const BarrierStats net = ComputeBarriers(scene, result)[0];
  EXPECT_EQ(net.check.passed, 3);
  EXPECT_EQ(net.stopped, 3);
  EXPECT_EQ(net.check.over, 0);
}

// Scene::IsValid refuses a barrier without a line, height or capacity.
TEST(Scene, IsValidNamesTheBarrierAndTheRule) {
  Scene scene = BarrierScene(true);
  std::string error;
  ASSERT_TRUE(scene.IsValid(&error)) << error;
  scene.partitions[1].line.pop_back();
  EXPECT_FALSE(scene.IsValid(&error));
  EXPECT_EQ(error,
            "barrier behind (1 vertices, height 2.8 m, capacity 50000 J): expected a line of at "
            "least 2 vertices");
  scene = BarrierScene(true);
  scene.partitions[0].line[1].x() = std::nan("");
  EXPECT_FALSE(scene.IsValid(&error));
  EXPECT_THAT(error, ::testing::HasSubstr("barrier net (3 vertices"));
  EXPECT_THAT(error, ::testing::HasSubstr("expected finite vertices"));
  scene = BarrierScene(true);
  scene.partitions[0].height = -1.0;
  EXPECT_FALSE(scene.IsValid(&error));
  EXPECT_THAT(error, ::testing::HasSubstr("height -1 m"));
  EXPECT_THAT(error, ::testing::HasSubstr("expected a finite height > 0"));
  scene = BarrierScene(true);
  scene.partitions[0].capacity = 0.0;
  EXPECT_FALSE(scene.IsValid(&error));
  EXPECT_THAT(error, ::testing::HasSubstr("expected a finite capacity > 0"));
}

// The plan crossing of a path and a polyline: the first segment met, none
// for a path that only starts on the line or runs along it.
TEST(Scene, CrossesLineFindsTheFirstSegmentMet) {
  const std::vector<Eigen::Vector2d> line = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}};
  double f = -1.0;
  ASSERT_TRUE(CrossesLine(line, {1.0, -1.0}, {1.0, 3.0}, &f));
  EXPECT_DOUBLE_EQ(f, 0.25);
  // Meets the second segment at (2, 0.5) before the first at (1, 0).
  ASSERT_TRUE(CrossesLine(line, {3.0, 1.0}, {-1.0, -1.0}, &f));
  EXPECT_DOUBLE_EQ(f, 0.25);
  EXPECT_FALSE(CrossesLine(line, {1.0, 0.0}, {1.0, 1.0}, &f));  // starts on it
  EXPECT_TRUE(CrossesLine(line, {1.0, 1.0}, {1.0, 0.0}, &f));   // ends on it
  EXPECT_DOUBLE_EQ(f, 1.0);
  EXPECT_FALSE(CrossesLine(line, {0.5, 0.0}, {1.5, 0.0}, &f));   // along it
  EXPECT_FALSE(CrossesLine(line, {3.0, -1.0}, {3.0, 3.0}, &f));  // beside it
}

// Rocks thrown over the terrain's edge count as beyond it: three rocks rest
// where they were released (no runout), two fly off the x-max edge.
TEST(Simulate, RocksThrownOverTheEdgeAreBeyondIt) {
  Scene scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5));
  scene.groups = {PointGroup(Shape::kSphere, 0.4, 5.0, 10.0, 0.0, 3),
                  PointGroup(Shape::kSphere, 0.4, 15.0, 10.0, 1.0, 2)};
  scene.groups[1].release.velocity = Eigen::Vector3d(10.0, 0.0, 0.0);
  const SimulationResult result = Simulate(scene);
  ASSERT_EQ(result.count(Outcome::kLeft), 2);
  ASSERT_EQ(result.count(Outcome::kStopped), 3);
  const ResultStats stats = ComputeStats(scene, result);
  EXPECT_EQ(stats.runout.beyond_edge, 2);
  EXPECT_EQ(stats.runout.distance_m.count, 5);
  // {0, 0, 0, beyond, beyond}: p50 at pos 2 is a resting rock's, p90 beyond.
  EXPECT_NEAR(stats.runout.distance_m.p50, 0.0, 1e-6);
  EXPECT_TRUE(std::isinf(stats.runout.distance_m.p90)) << stats.runout.distance_m.p90;
  // The stopped-only figure the older key keeps: stop x of the three.
  EXPECT_EQ(stats.runout_x.count, 3);
  EXPECT_NEAR(stats.runout_x.max, 5.0, 1e-6);
}

// A rock that flies off the data (a hole: no elevation past x = 19 m) crosses
// a partition over the hole in its last advance. Its height is measured from
// the ground where its path left the slope (the flat ground, z = 0), never
// recorded as a silent 0.
TEST(Simulate, CrossingOverAHoleIsMeasuredFromTheNearestGround) {
  Scene scene = GridScene(41, 5, 1.0, [](double x, double) { return x < 19.5 ? 0.0 : NAN; },
                          SmoothMaterial(0.5, 0.005, 0.5));
  scene.partitions = {{"on-slope", Partition::Kind::kX, 18.5},
                      {"over-hole", Partition::Kind::kX, 19.2}};
  scene.groups = {PointGroup(Shape::kSphere, 0.4, 10.3, 2.0, 5.0)};
  scene.groups[0].release.velocity = Eigen::Vector3d(10.0, 0.0, 0.0);
  const SimulationResult result = Simulate(scene);
  const RockRecord& r = result.rocks[0];
  EXPECT_EQ(r.outcome, Outcome::kLeft);
  ASSERT_EQ(r.crossings.size(), 2u);
  ASSERT_TRUE(r.crossings[0].crossed);
  EXPECT_NEAR(r.crossings[0].height, r.crossings[0].point.z(), 1e-9);
  ASSERT_TRUE(r.crossings[1].crossed);
  EXPECT_NEAR(r.crossings[1].point.x(), 19.2, 1e-9);
  EXPECT_GT(r.crossings[1].point.z(), 0.5) << "still in flight over the hole";
  EXPECT_NEAR(r.crossings[1].height, r.crossings[1].point.z(), 1e-9)
      << "height " << r.crossings[1].height << " at centre z " << r.crossings[1].point.z();
}

// ---- The fast paths against the reference path ------------------------------
// The production path leaves out what a rock does not need (exact flight, the
// long step of gentle contact, the neighbour list, spheres without
// orientation); SimulationOptions::reference_path turns all of that off.

// Trajectory of the first rock on both paths, sampled every `sample` s.
struct BothPaths {
  SimulationResult fast, reference;
};
BothPaths RunBothPaths(Scene scene, double sample) {
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = sample;
  BothPaths out;
  out.fast = Simulate(scene);
  scene.options.reference_path = true;
  out.reference = Simulate(scene);
  // The levers were on, then off.
  EXPECT_GT(out.fast.figures.gentle_steps, 0);
  EXPECT_EQ(out.reference.figures.gentle_steps, 0);
  EXPECT_EQ(out.reference.figures.flights, 0);
  return out;
}

// Largest distance between the two paths' positions at the common samples up
// to time t_end (the regular samples; each path's last one is at its own end).
double PathDistance(const BothPaths& p, double t_end) {
  const auto& a = p.fast.rocks[0].trajectory;
  const auto& b = p.reference.rocks[0].trajectory;
  double worst = 0.0;
  for (std::size_t k = 0; k + 1 < std::min(a.size(), b.size()) && a[k].t <= t_end; ++k) {
    EXPECT_NEAR(a[k].t, b[k].t, 1e-9);
    worst = std::max(worst, (a[k].x - b[k].x).norm());
  }
  return worst;
}

// A sphere dropped 5 m onto flat ground (exact flight, landing, bounces,
// then gentle contact until it rests): the same rebound and rest point.
TEST(Simulate, BouncingSphereFastPathsMatchReference) {
  Scene scene = FlatScene(SmoothMaterial(0.5, 0.005, 0.5, 0.05));
  scene.groups = {PointGroup(Shape::kSphere, 0.4, 10.0, 10.0, 5.0)};
  scene.options.max_time = 4.0;
  const BothPaths p = RunBothPaths(scene, 0.005);
  EXPECT_GT(p.fast.figures.flights, 0);
  // Free fall: exact on both (constant acceleration).
  EXPECT_LT(PathDistance(p, 0.95), 1e-9);
  // The first rebound's apex (bottom above ground, 5 e^2 = 1.25 m): the fast
  // path lands exactly and keeps e to well under 1 %; the step-only
  // reference's first-order error at N_c = 50 is about 1 % in e, 2 % in height.
  auto apex = [](const RockRecord& r) {
    double top = -1.0;
    for (const auto& s : r.trajectory)
      if (s.t > 1.05 && s.t < 2.0) top = std::max(top, s.x.z() - 0.2);
    return top;
  };
  EXPECT_NEAR(apex(p.fast.rocks[0]) / 1.25, 1.0, 0.01);
  EXPECT_NEAR(apex(p.reference.rocks[0]) / apex(p.fast.rocks[0]), 1.0, 0.03);
  EXPECT_NEAR(p.fast.rocks[0].stop.z(), p.reference.rocks[0].stop.z(), 1e-4) << "the same rest";
}

// A sphere rolling down a smooth 30-degree incline (gentle contact all the
// way): the same path within a millimetre over 20 m.
TEST(Simulate, RollingSphereFastPathsMatchReference) {
  Scene scene = Incline30(SmoothMaterial(0.3, 0.005, 1.0, 0.05));
  scene.groups = {PointGroup(Shape::kSphere, 0.4, 5.0, 2.0, 0.0)};
  scene.options.max_time = 3.0;
  const BothPaths p = RunBothPaths(scene, 0.1);
  EXPECT_GT(p.fast.rocks[0].stop.x() - 5.0, 10.0) << "it rolled";
  // Within 1e-3 of the distance travelled (the two differ by the contact
  // spring's small oscillation, resolved differently).
  EXPECT_LT(PathDistance(p, 3.0), 1e-3 * (p.fast.rocks[0].stop - p.fast.rocks[0].start).norm());
  EXPECT_LT(p.fast.figures.steps, p.reference.figures.steps / 2) << "the gentle step is longer";
}

// A cube (a sphere cluster) sliding down a smooth 30-degree incline.
TEST(Simulate, SlidingClusterFastPathsMatchReference) {
  Scene scene = Incline30(SmoothMaterial(0.3, 0.005, 0.2, 0.0));
  scene.groups = {PointGroup(Shape::kCube, 0.4, 5.0, 2.0, 0.0)};
  scene.options.max_time = 2.0;
  const BothPaths p = RunBothPaths(scene, 0.1);
  EXPECT_GT(p.fast.rocks[0].stop.x() - 5.0, 5.0) << "it slid";
  EXPECT_LT(PathDistance(p, 2.0), 1e-3 * (p.fast.rocks[0].stop - p.fast.rocks[0].start).norm());
}


// A 2D profile (one cell wide): a sphere rolls down a 30-degree slope onto a
// flat and stops; its neighbourhood holds only the two rows there are.
TEST(Simulate, ProfileFastPathsMatchReference) {
  const double theta = 30.0 * M_PI / 180.0;
  Scene scene = GridScene(
      61, 2, 1.0, [&](double x, double) { return x < 10.0 ? (10.0 - x) * std::tan(theta) : 0.0; },
      SmoothMaterial(0.3, 0.005, 1.0, 0.3));
  scene.groups = {PointGroup(Shape::kSphere, 0.4, 1.0, 0.5, 0.0)};
  scene.options.max_time = 12.0;
  const BothPaths p = RunBothPaths(scene, 0.1);
  const RockRecord& fast = p.fast.rocks[0];
  EXPECT_EQ(fast.outcome, Outcome::kStopped);
  EXPECT_EQ(p.reference.rocks[0].outcome, Outcome::kStopped);
  EXPECT_GT(fast.stop.x(), 15.0) << "it rolled onto the flat";
  // At the toe it hits the flat at 2.9 m/s along the normal: the step-only
  // reference's restitution error (about 1 % at N_c = 50, first order) shows
  // in the rebound speed (0.4 %) and in the stop point (0.3 % of the way).
  EXPECT_LT(PathDistance(p, 3.5), 1e-3 * (fast.stop - fast.start).norm()) << "the slope";
  EXPECT_LT(PathDistance(p, 12.0), 5e-3 * (fast.stop - fast.start).norm());
}


// A surveyed drop: the rock's lowest point starts at the given elevation
// (a sphere's centre one radius above it), never below the ground; the
// velocity spread draws after everything else, so a rock's position and
// size do not move with it.
TEST(Simulate, ReleaseAtAnElevationWithAVelocitySpread) {
  Scene scene = GridScene(21, 21, 1.0, [](double, double) { return 10.0; },
                          SmoothMaterial(0.3, 0.005, 0.5));
  scene.options.max_time = 0.05;
  RockGroup g = PointGroup(Shape::kSphere, 0.4, 10.0, 10.0, 0.0, 200);
  g.release.zone = {{5, 5}, {15, 5}, {15, 15}, {5, 15}};
  g.release.elevation = 13.0;
  scene.groups = {g};
  const SimulationResult still = Simulate(scene);
  for (const RockRecord& r : still.rocks) EXPECT_NEAR(r.start.z(), 13.2, 1e-12);
  scene.groups[0].release.elevation = 5.0;  // below the ground: on it
  for (const RockRecord& r : Simulate(scene).rocks) EXPECT_NEAR(r.start.z(), 10.2, 1e-6);

  scene.groups[0].release.elevation = 13.0;
  scene.groups[0].release.velocity = Eigen::Vector3d(2.0, 0.0, 0.0);
  scene.groups[0].release.velocity_spread = Eigen::Vector3d(0.5, 0.0, 0.0);
  scene.options.record.trajectories = 200;
  const SimulationResult spread = Simulate(scene);
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t k = 0; k < spread.rocks.size(); ++k) {
    const RockRecord& r = spread.rocks[k];
    EXPECT_EQ(r.start, still.rocks[k].start) << "rock " << k;
    const double vx = r.trajectory.front().v.x();
    EXPECT_EQ(r.trajectory.front().v.y(), 0.0);
    sum += vx;
    sum2 += vx * vx;
  }
  const double n = static_cast<double>(spread.rocks.size());
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  // 200 normal draws: the mean within 4 standard errors, the spread within 20 %.
  EXPECT_NEAR(mean, 2.0, 4 * 0.5 / std::sqrt(n)) << "mean " << mean;
  EXPECT_NEAR(sd, 0.5, 0.1) << "sd " << sd;
}

// An inventory's blocks are released in turn, each at its own mass and shape.
TEST(Simulate, InventoryBlocksAreReleasedInTurn) {
  Scene scene = GridScene(21, 21, 1.0, [](double, double) { return 10.0; },
                          SmoothMaterial(0.3, 0.005, 0.5));
  scene.options.max_time = 0.05;
  RockGroup g = PointGroup(Shape::kBox, 1.0, 10.0, 10.0, 0.5, 5);
  g.inventory = {{Shape::kBox, Eigen::Vector3d(1.0, 0.8, 0.5), 700.0},
                 {Shape::kSphere, Eigen::Vector3d(0.6, 0.6, 0.6), 300.0}};
  scene.groups = {g};
  const SimulationResult result = Simulate(scene);
  ASSERT_EQ(result.rocks.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(result.rocks[k].mass, k % 2 == 0 ? 700.0 : 300.0) << "rock " << k;
    EXPECT_EQ(result.rocks[k].shape, k % 2 == 0 ? Shape::kBox : Shape::kSphere);
    EXPECT_EQ(result.rocks[k].size, k % 2 == 0 ? 1.0 : 0.6);
  }
}


// Each rock's random stream is keyed by its group and its index within the
// group: adding rocks to one group leaves every rock of the others
// bit-identical.
TEST(Simulate, AddingRocksToOneGroupLeavesTheOthersAlone) {
  Scene scene = GridScene(21, 21, 1.0, [](double x, double) { return 20.0 - 0.5 * x; },
                          SmoothMaterial(0.3, 0.005, 0.5));
  scene.options.max_time = 0.5;
  RockGroup a = PointGroup(Shape::kSphere, 0.4, 3.0, 10.0, 0.5, 3);
  a.size_max = 0.8;
  a.release.zone = {{2, 5}, {5, 5}, {5, 15}, {2, 15}};
  RockGroup b = a;
  b.shape = Shape::kCube;
  scene.groups = {a, b};
  const SimulationResult before = Simulate(scene);
  scene.groups[0].count = 5;
  const SimulationResult after = Simulate(scene);
  for (int k = 0; k < 3; ++k) {
    const RockRecord& x = before.rocks[static_cast<std::size_t>(3 + k)];
    const RockRecord& y = after.rocks[static_cast<std::size_t>(5 + k)];
    EXPECT_EQ(x.start, y.start) << "group 2, rock " << k;
    EXPECT_EQ(x.size, y.size) << "group 2, rock " << k;
    EXPECT_EQ(x.stop, y.stop) << "group 2, rock " << k;
    EXPECT_EQ(x.steps, y.steps) << "group 2, rock " << k;
  }
}

}  // namespace simulate_test
}  // namespace rockcal::core
