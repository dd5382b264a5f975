#include "rockcal/observations/misfit.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"

namespace rockcal::observations {
namespace {

using ::testing::HasSubstr;

// Two X partitions and one rock group released at the origin; no terrain is
// needed because the records are built by hand.
core::Scene TwoPartitionScene() {
  core::Scene scene;
  scene.name = "hand-made";
  core::Partition a;
  a.id = "BP-1";
  a.value = 50.0;
  core::Partition b;
  b.id = "BP-2";
  b.value = 80.0;
  scene.partitions = {a, b};
  core::RockGroup group;
  group.count = 40;
  scene.groups = {group};
  return scene;
}

core::RockRecord StoppedRock(int index, double stop_x, double stop_y) {
  core::RockRecord rock;
  rock.rock = index;
  rock.outcome = core::Outcome::kStopped;
  rock.stop = Eigen::Vector3d(stop_x, stop_y, 1.0);
  rock.crossings.resize(2);
  return rock;
}

// Rocks that cross `partition` at the given heights (each rock crosses once).
core::SimulationResult CrossingAt(int partition, const std::vector<double>& heights) {
  core::SimulationResult result;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    core::RockRecord rock = StoppedRock(static_cast<int>(i), 100.0, 0.0);
    core::Crossing& c = rock.crossings[static_cast<std::size_t>(partition)];
    c.crossed = true;
    c.height = heights[i];
    c.speed = 5.0;
    c.energy = 100.0;
    result.rocks.push_back(rock);
  }
  return result;
}

Observations ScarsAt(int partition, std::vector<double> heights, double error) {
  Observations obs;
  ScarSet set;
  set.label = "tree_scars[0] BP-" + std::to_string(partition + 1);
  set.partition = partition;
  set.heights = std::move(heights);
  obs.tree_scars.push_back(set);
  obs.error.height = error;
  return obs;
}

// 40 heights from 0.2 to 4.1 m in a scrambled order.
std::vector<double> SomeHeights() {
  std::vector<double> h;
  for (int i = 0; i < 40; ++i) h.push_back(0.2 + 0.1 * ((i * 17) % 40));
  return h;
}

std::vector<double> Shifted(std::vector<double> v, double d) {
  for (double& x : v) x += d;
  return v;
}

TEST(MisfitTest, IdenticalDistributionsGiveZero) {
  const core::Scene scene = TwoPartitionScene();
  const std::vector<double> heights = SomeHeights();
  std::vector<double> observed = heights;
  std::sort(observed.begin(), observed.end());  // order does not matter
  const Misfit m = ComputeMisfit(ScarsAt(0, observed, 0.3), scene, CrossingAt(0, heights));
  EXPECT_FALSE(m.penalised) << m.message;
  EXPECT_EQ(m.value, 0.0);
  ASSERT_EQ(m.residuals.size(), 10u);  // p10 ... p90 and max
  EXPECT_EQ(m.residuals[0].id.quantity(), "p10");
  EXPECT_EQ(m.residuals[8].id.quantity(), "p90");
  EXPECT_EQ(m.residuals[9].id.quantity(), "max");
  for (const Residual& r : m.residuals) {
    EXPECT_EQ(r.id.observation(), "tree_scars[0] BP-1");
    EXPECT_EQ(r.value, 0.0) << r.id.quantity();
    EXPECT_GE(r.sigma, 0.3);
  }
}

TEST(MisfitTest, GrowsMonotonicallyWithAShiftAndResidualsFollowItsSign) {
  const core::Scene scene = TwoPartitionScene();
  const std::vector<double> heights = SomeHeights();
  const Observations obs = ScarsAt(0, heights, 0.3);
  double previous = 0.0;
  for (const double shift : {0.02, 0.1, 0.3, 1.0, 3.0, 10.0}) {
    const Misfit up = ComputeMisfit(obs, scene, CrossingAt(0, Shifted(heights, shift)));
    const Misfit down = ComputeMisfit(obs, scene, CrossingAt(0, Shifted(heights, -shift)));
    EXPECT_GT(up.value, previous) << "shift " << shift;
    // The sigmas do not depend on the shift, so the misfit is symmetric.
    EXPECT_NEAR(down.value, up.value, 1e-9 * up.value) << "shift " << shift;
    for (std::size_t i = 0; i < up.residuals.size(); ++i) {
      EXPECT_GT(up.residuals[i].value, 0.0) << up.residuals[i].id.quantity();
      EXPECT_LT(down.residuals[i].value, 0.0) << down.residuals[i].id.quantity();
      EXPECT_NEAR(up.residuals[i].simulated - up.residuals[i].observed, shift, 1e-9);
    }
    previous = up.value;
  }
}

TEST(MisfitTest, SigmaCombinesMeasurementMonteCarloAndSamplingErrors) {
  const core::Scene scene = TwoPartitionScene();
  std::vector<double> simulated, observed;
  for (int i = 0; i < 100; ++i) simulated.push_back(0.05 * i);
  for (int i = 0; i < 10; ++i) observed.push_back(0.3 * i * i / 9.0);
  const double e = 0.25;
  const Misfit m = ComputeMisfit(ScarsAt(0, observed, e), scene, CrossingAt(0, simulated));
  ASSERT_EQ(m.residuals.size(), 10u);
  // p50: the quantiles' standard errors (Maritz-Jarrett, by mpmath 1.3.0's
  // betainc at 30 digits): 0.2479573413659190 for the simulated 0, 0.05,
  // ..., 4.95 (about half the spread five positions either side, 0.25), and
  // 0.4509412062999286 for the observed 0.3 i^2 / 9, i = 0..9.
  const double sim_error = 0.2479573413659190, obs_error = 0.4509412062999286;
  const Residual& p50 = m.residuals[4];
  EXPECT_EQ(p50.id.quantity(), "p50");
  EXPECT_NEAR(p50.sigma, std::sqrt(e * e + sim_error * sim_error + obs_error * obs_error), 1e-12);
  EXPECT_NEAR(p50.simulated, 2.475, 1e-12);
  EXPECT_NEAR(p50.observed, 0.3 * (16 + 0.5 * 9) / 9.0, 1e-12);
  EXPECT_NEAR(p50.value, (p50.simulated - p50.observed) / p50.sigma, 1e-12);
  // max: the observed maximum of 10 against the simulated order statistic
  // that exceeds it with probability 1/2 (MaxOrderPosition(100, 10) =
  // 92.93780262374514, checked below): 0.05 * 92.9378...; its error the
  // slope 0.05 over h = sqrt(100 p (1 - p)) positions, p = 92.9378... / 99;
  // the observed side's the gap between its two largest, 0.3 * 17 / 9.
  const Residual& max = m.residuals[9];
  const double k = 92.93780262374514, p = k / 99.0;
  const double max_error = 0.05 * std::sqrt(100.0 * p * (1.0 - p));
  EXPECT_NEAR(max.sigma, std::sqrt(e * e + max_error * max_error + std::pow(0.3 * 17 / 9.0, 2)),
              1e-12);
  EXPECT_NEAR(max.simulated, 0.05 * k, 1e-12);
  EXPECT_NEAR(max.observed, 0.3 * 9, 1e-12);
  double sum = 0.0;
  for (const Residual& r : m.residuals) sum += r.value * r.value;
  EXPECT_NEAR(m.value, 0.5 * sum, 1e-12 * m.value);
  // The part of each sigma the simulation does not change: the measurement
  // error and the observed side's error; the log term sums log(sigma /
  // fixed) over the residuals.
  EXPECT_NEAR(p50.fixed_sigma, std::sqrt(e * e + obs_error * obs_error), 1e-12);
  EXPECT_NEAR(max.fixed_sigma, std::sqrt(e * e + std::pow(0.3 * 17 / 9.0, 2)), 1e-12);
  double log_scale = 0.0;
  for (const Residual& r : m.residuals) {
    EXPECT_GT(r.fixed_sigma, 0.0) << r.id.quantity();
    EXPECT_LE(r.fixed_sigma, r.sigma) << r.id.quantity();
    log_scale += std::log(r.sigma / r.fixed_sigma);
  }
  EXPECT_NEAR(m.log_scale, log_scale, 1e-12);
  EXPECT_GT(m.log_scale, 0.0);
}

// Samples of different sizes from one distribution: each quantile's
// residual has mean 0 over many draws (within 4 standard errors of that
// mean). 120 simulated values against 30 observed, from an exponential and
// a normal distribution. The same draws compared at the type-7 quantiles
// (core::Quantile, the misfit's before) are biased beyond that bound: a
// smaller sample's type-7 p10 and p90 lie nearer its median, by
// (1 - 2p) / (n + 1) in probability.
TEST(MisfitTest, QuantileResidualsOfOneDistributionHaveMeanZeroAtUnequalCounts) {
  const core::Scene scene = TwoPartitionScene();
  core::RandomStream rng(54, 1);
  const int draws = 2000, n = 120, m = 30;
  for (const bool normal : {false, true}) {
    auto sample = [&](int count) {
      std::vector<double> v;
      for (int i = 0; i < count; ++i) {
        const double u = rng.Uniform(), w = rng.Uniform();
        // Exponential of mean 1, or Box-Muller's normal about 5.
        v.push_back(normal ? 5.0 + std::sqrt(-2.0 * std::log1p(-u)) * std::cos(2.0 * M_PI * w)
                           : -std::log1p(-u));
      }
      return v;
    };
    std::vector<double> sum(9, 0.0), square(9, 0.0), type7(9, 0.0);
    for (int k = 0; k < draws; ++k) {
      const std::vector<double> simulated = sample(n), observed = sample(m);
      const Misfit misfit =
          ComputeMisfit(ScarsAt(0, observed, 1e-3), scene, CrossingAt(0, simulated));
      ASSERT_EQ(misfit.residuals.size(), 10u);
      std::vector<double> s = simulated, o = observed;
      std::sort(s.begin(), s.end());
      std::sort(o.begin(), o.end());
      for (std::size_t l = 0; l < 9; ++l) {
        const Residual& r = misfit.residuals[l];
        sum[l] += r.value;
        square[l] += r.value * r.value;
        type7[l] += (core::Quantile(s, r.id.level) - core::Quantile(o, r.id.level)) / r.sigma;
      }
    }
    for (const std::size_t l : {0u, 1u, 4u, 7u, 8u}) {
      const double mean = sum[l] / draws;
      const double error = std::sqrt((square[l] / draws - mean * mean) / draws);
      const std::string what =
          std::string(normal ? "normal" : "exponential") + " p" + std::to_string(10 * (l + 1));
      EXPECT_LT(std::abs(mean), 4.0 * error) << what << ": mean " << mean << ", s.e. " << error;
      if (l == 0 || l == 8) {
        EXPECT_GT(std::abs(type7[l] / draws), 4.0 * error)
            << what << " at type 7: mean " << type7[l] / draws << ", s.e. " << error;
      }
    }
  }
}

TEST(MisfitTest, SigmaHasAPositiveFloor) {
  const core::Scene scene = TwoPartitionScene();
  const std::vector<double> same(20, 1.5);
  // A hand-built observation without a measurement error: no sigma is zero and
  // every value stays finite.
  const Observations obs = ScarsAt(0, same, 0.0);
  const Misfit equal = ComputeMisfit(obs, scene, CrossingAt(0, same));
  EXPECT_EQ(equal.value, 0.0);
  const Misfit apart = ComputeMisfit(obs, scene, CrossingAt(0, Shifted(same, 1e-3)));
  for (const Residual& r : apart.residuals) {
    EXPECT_GT(r.sigma, 0.0);
    EXPECT_TRUE(std::isfinite(r.value)) << r.value;
  }
  EXPECT_TRUE(std::isfinite(apart.value));
  EXPECT_GT(apart.value, 0.0);
}

TEST(MisfitTest, NonFiniteResultIsPenalisedWithAFiniteValue) {
  const core::Scene scene = TwoPartitionScene();
  core::SimulationResult result = CrossingAt(0, SomeHeights());
  result.figures.non_finite = 1;
  MisfitOptions options;
  options.penalty = 42.0;
  const Misfit m = ComputeMisfit(ScarsAt(0, SomeHeights(), 0.3), scene, result, options);
  EXPECT_TRUE(m.penalised);
  EXPECT_EQ(m.value, 42.0);
  EXPECT_TRUE(m.residuals.empty());
  EXPECT_THAT(m.message, HasSubstr("non-finite"));

  // A non-finite value in a record counts too, even when non_finite is 0.
  result.figures.non_finite = 0;
  result.rocks[3].crossings[0].height = std::numeric_limits<double>::quiet_NaN();
  const Misfit n = ComputeMisfit(ScarsAt(0, SomeHeights(), 0.3), scene, result);
  EXPECT_TRUE(n.penalised);
  EXPECT_EQ(n.value, MisfitOptions().penalty);
  EXPECT_TRUE(std::isfinite(n.value));
}

TEST(MisfitTest, NoCrossingsGiveAFiniteLargeMisfit) {
  const core::Scene scene = TwoPartitionScene();
  // Every rock crossed BP-2, none crossed BP-1 where the scars are.
  const Observations obs = ScarsAt(0, SomeHeights(), 0.3);
  for (const std::size_t crossed_bp1 : {0u, 1u}) {
    core::SimulationResult result = CrossingAt(1, SomeHeights());
    for (std::size_t i = 0; i < crossed_bp1; ++i) {
      result.rocks[i].crossings[0].crossed = true;
      result.rocks[i].crossings[0].height = 1.0;
    }
    const Misfit m = ComputeMisfit(obs, scene, result);
    SCOPED_TRACE(crossed_bp1);
    EXPECT_TRUE(m.penalised);
    EXPECT_TRUE(std::isfinite(m.value));
    EXPECT_NEAR(m.value, MisfitOptions().penalty, 1e-9 * MisfitOptions().penalty);
    EXPECT_THAT(m.message, HasSubstr("tree_scars[0] BP-1"));
    EXPECT_THAT(m.message, HasSubstr("fewer than 2"));
    ASSERT_EQ(m.residuals.size(), 10u);
    for (const Residual& r : m.residuals) {
      EXPECT_TRUE(std::isfinite(r.value));
      EXPECT_TRUE(std::isfinite(r.simulated));
      EXPECT_GT(r.sigma, 0.0);
    }
  }
}

Observations RunoutAlongX(std::vector<Eigen::Vector2d> stops, double error) {
  Observations obs;
  Runout r;
  r.from = Eigen::Vector2d(0, 0);
  r.direction = Eigen::Vector2d(1, 0);
  r.stop_points = std::move(stops);
  for (const Eigen::Vector2d& p : r.stop_points) {
    r.distances.push_back(r.Distance(p));
    r.lateral.push_back(r.Lateral(p));
  }
  obs.runout = r;
  obs.error.runout = error;
  return obs;
}

TEST(MisfitTest, RunoutComparesDistanceAndLateralOffsetOfStoppedRocks) {
  const core::Scene scene = TwoPartitionScene();
  std::vector<Eigen::Vector2d> stops;
  for (int i = 0; i < 30; ++i)
    stops.emplace_back(100.0 + 3.0 * ((i * 7) % 30), -10.0 + (i % 5) * 5);
  const Observations obs = RunoutAlongX(stops, 2.0);

  auto simulate = [&](double dx, double dy) {
    core::SimulationResult result;
    for (std::size_t i = 0; i < stops.size(); ++i) {
      result.rocks.push_back(
          StoppedRock(static_cast<int>(i), stops[i].x() + dx, stops[i].y() + dy));
    }
    return result;
  };

  const Misfit same = ComputeMisfit(obs, scene, simulate(0, 0));
  EXPECT_FALSE(same.penalised) << same.message;
  EXPECT_EQ(same.value, 0.0);
  ASSERT_EQ(same.residuals.size(), 21u);
  EXPECT_EQ(same.residuals[0].id.observation(), "runout distance");
  EXPECT_EQ(same.residuals[10].id.observation(), "runout lateral");
  EXPECT_EQ(same.residuals[20].id.observation(), "runout stopped");
  EXPECT_EQ(same.residuals[20].id.quantity(), "share");

  const Misfit longer = ComputeMisfit(obs, scene, simulate(15, 0));
  for (std::size_t i = 0; i < 10; ++i) EXPECT_GT(longer.residuals[i].value, 0.0);
  for (std::size_t i = 10; i < 20; ++i) EXPECT_NEAR(longer.residuals[i].value, 0.0, 1e-12);

  const Misfit right = ComputeMisfit(obs, scene, simulate(0, -8));
  for (std::size_t i = 0; i < 10; ++i) EXPECT_NEAR(right.residuals[i].value, 0.0, 1e-12);
  for (std::size_t i = 10; i < 20; ++i) EXPECT_LT(right.residuals[i].value, 0.0);

  EXPECT_GT(ComputeMisfit(obs, scene, simulate(30, 0)).value, longer.value);

  // No rock stopped: the lateral offsets (of stopped rocks) are penalised,
  // finitely, and the distances and the stopped share count the loss.
  core::SimulationResult none = simulate(0, 0);
  for (core::RockRecord& rock : none.rocks) rock.outcome = core::Outcome::kLeft;
  const Misfit gone = ComputeMisfit(obs, scene, none);
  EXPECT_TRUE(gone.penalised);
  EXPECT_GT(gone.value, MisfitOptions().penalty);
  EXPECT_LT(gone.value, 2 * MisfitOptions().penalty);
}

// A rock that left the terrain or timed out travelled at least to where it
// was last seen: it counts in the upper tail of the runout, and in the
// stopped share. Losing rocks never lowers the misfit.
TEST(MisfitTest, LostRocksAreCensoredAndNeverLowerTheMisfit) {
  const core::Scene scene = TwoPartitionScene();
  std::vector<Eigen::Vector2d> stops;
  for (int i = 0; i < 30; ++i) stops.emplace_back(100.0 + 2.0 * i, 0.0);
  const Observations obs = RunoutAlongX(stops, 2.0);
  // 30 rocks at the observed stops but the farthest `lost` of them run on to
  // x = 200 and stop there, or leave the terrain there.
  auto simulate = [&](int lost, core::Outcome outcome) {
    core::SimulationResult result;
    for (std::size_t i = 0; i < stops.size(); ++i) {
      const bool gone = static_cast<int>(i) >= 30 - lost;
      core::RockRecord rock = StoppedRock(static_cast<int>(i), gone ? 200.0 : stops[i].x(), 0.0);
      if (gone) rock.outcome = outcome;
      result.rocks.push_back(rock);
    }
    return result;
  };
  const Misfit all = ComputeMisfit(obs, scene, simulate(0, core::Outcome::kStopped));
  EXPECT_EQ(all.value, 0.0);
  for (int lost : {1, 5, 15}) {
    const Misfit stopped = ComputeMisfit(obs, scene, simulate(lost, core::Outcome::kStopped));
    for (core::Outcome outcome : {core::Outcome::kLeft, core::Outcome::kTimeout}) {
      const Misfit left = ComputeMisfit(obs, scene, simulate(lost, outcome));
      EXPECT_GT(left.value, stopped.value)
          << lost << " rocks " << core::OutcomeName(outcome) << ": " << left.value << " against "
          << stopped.value << " when they stop where they were last seen";
      const Residual& share = left.residuals.back();
      EXPECT_EQ(share.id.observation(), "runout stopped");
      EXPECT_NEAR(share.simulated, (30.0 - lost) / 30.0, 1e-12);
      EXPECT_LT(share.value, 0.0);
    }
    EXPECT_GT(stopped.value, all.value);
  }
  // A lost rock left short of the observed stops still lands in the upper tail.
  core::SimulationResult early = simulate(0, core::Outcome::kStopped);
  early.rocks[0].stop.x() = 10.0;
  early.rocks[0].outcome = core::Outcome::kLeft;
  const Misfit m = ComputeMisfit(obs, scene, early);
  EXPECT_GE(m.residuals[9].simulated, 158.0) << "p90 " << m.residuals[9].simulated;
  EXPECT_GE(m.residuals[0].simulated, 101.0) << "p10 " << m.residuals[0].simulated;
}

// With the blocks' masses, the runout is also compared per mass class: a
// model whose light rocks stop short and heavy rocks run on cannot hide
// behind a right pooled distribution.
TEST(MisfitTest, RunoutPerMassClassSeesASizeTrend) {
  const core::Scene scene = TwoPartitionScene();
  std::vector<Eigen::Vector2d> stops;
  std::vector<double> masses;
  for (int i = 0; i < 40; ++i) {
    stops.emplace_back(100.0 + 1.0 * ((i * 7) % 40), 0.0);  // no size trend
    masses.push_back(100.0 + 10.0 * i);
  }
  Observations obs = RunoutAlongX(stops, 1.0);
  obs.runout->masses = masses;
  obs.runout->mass_classes = 4;
  ASSERT_EQ(obs.runout->MassClassBounds().size(), 3u);
  // The same stop distances pooled, but sorted by mass: light short, heavy long.
  auto simulate = [&](bool trend) {
    std::vector<double> xs;
    for (const auto& p : stops) xs.push_back(p.x());
    if (trend) std::sort(xs.begin(), xs.end());
    core::SimulationResult result;
    for (std::size_t i = 0; i < xs.size(); ++i) {
      core::RockRecord rock = StoppedRock(static_cast<int>(i), xs[i], 0.0);
      rock.mass = masses[i];
      result.rocks.push_back(rock);
    }
    return result;
  };
  const Misfit same = ComputeMisfit(obs, scene, simulate(false));
  const Misfit trend = ComputeMisfit(obs, scene, simulate(true));
  std::vector<double> by_class;
  for (const Residual& r : trend.residuals) {
    if (r.id.kind != ObservationKind::kRunoutMassClass) continue;
    by_class.push_back(r.value);
    EXPECT_EQ(r.id.quantity(), "p50");
  }
  ASSERT_EQ(by_class.size(), 4u);
  EXPECT_NEAR(same.value, 0.0, 1e-12);
  // The light class stops short of its observed median, the heavy one beyond,
  // by more than two standard errors (the median of 10 rocks on each side).
  EXPECT_LT(by_class.front(), -1.0) << trend.Report();
  EXPECT_GT(by_class.back(), 2.0) << trend.Report();
  EXPECT_GT(trend.value, same.value + 4.0) << trend.Report();
  // The pooled comparison alone cannot tell them apart.
  for (std::size_t k = 0; k < 10; ++k)
    EXPECT_NEAR(trend.residuals[k].value, same.residuals[k].value, 1e-12);
}

TEST(MisfitTest, RunoutGivenAsDistancesHasNoLateralResiduals) {
  const core::Scene scene = TwoPartitionScene();
  Observations obs;
  Runout r;
  r.from = Eigen::Vector2d(10, 0);
  r.direction = Eigen::Vector2d(0, 1);
  r.distances = {20, 30, 40};
  obs.runout = r;
  obs.error.runout = 1.0;
  core::SimulationResult result;
  for (int i = 0; i < 3; ++i) result.rocks.push_back(StoppedRock(i, 50.0, 20.0 + 10 * i));
  const Misfit m = ComputeMisfit(obs, scene, result);
  ASSERT_EQ(m.residuals.size(), 11u);
  for (std::size_t k = 0; k < 10; ++k)
    EXPECT_EQ(m.residuals[k].id.observation(), "runout distance");
  EXPECT_EQ(m.residuals[10].id.observation(), "runout stopped");
  EXPECT_EQ(m.value, 0.0);
}

// Two tracked runs released 40 m apart: each run's runout is measured from
// its own release and compared with its own group's rocks only.
TEST(MisfitTest, RunsAreMeasuredFromTheirOwnRelease) {
  core::Scene scene = TwoPartitionScene();
  core::RockGroup a, b;
  a.id = "a";
  a.release.point = Eigen::Vector2d(0, 0);
  b.id = "b";
  b.release.point = Eigen::Vector2d(0, 40);
  scene.groups = {a, b};
  Observations obs;
  Runout r;
  r.run_ids = {"a", "b"};
  r.run_groups = {0, 1};
  r.run_origins = {a.release.point, b.release.point};
  r.stop_points = {Eigen::Vector2d(30, 0), Eigen::Vector2d(0, 90)};
  r.distances = {30, 50};
  obs.runout = r;
  obs.error.runout = 1.0;
  auto rock = [](int index, int group, double x, double y, double sx, double sy) {
    core::RockRecord rec = StoppedRock(index, x, y);
    rec.group = group;
    rec.start = Eigen::Vector3d(sx, sy, 0);
    return rec;
  };
  core::SimulationResult result;
  // Run a's rock stops 30 m from (0, 0), run b's 50 m from (0, 40): every
  // quantile matches, though from the first release b's is 90 m off.
  result.rocks = {rock(0, 0, 30, 0, 0, 0), rock(1, 1, 0, 90, 0, 40)};
  Misfit m = ComputeMisfit(obs, scene, result);
  EXPECT_NEAR(m.value, 0.0, 1e-12) << m.Report();
  ASSERT_EQ(m.runs.size(), 2u);
  EXPECT_EQ(m.runs[1].id, "b");
  EXPECT_DOUBLE_EQ(m.runs[1].simulated, 50.0);
  EXPECT_DOUBLE_EQ(m.MeanRunError(), 0.0);
  EXPECT_EQ(m.StuckRocks(), 0);
  // Run b's rocks stuck at its release: counted, and the runout short.
  result.rocks[1] = rock(1, 1, 0.2, 40, 0, 40);
  result.rocks.push_back(rock(2, 1, 0, 40.5, 0, 40));
  m = ComputeMisfit(obs, scene, result);
  EXPECT_EQ(m.runs[1].stuck, 2);
  EXPECT_EQ(m.runs[1].rocks, 2);
  EXPECT_EQ(m.StuckRocks(), 2);
  EXPECT_NEAR(m.runs[1].simulated, 0.35, 1e-9);
  EXPECT_NEAR(m.MeanRunError(), (50 - 0.35) / 2, 1e-9);
  // Near the release means within a tenth of the run's own runout (b: 5 m),
  // and at least RunFit::kStuckDistance.
  result.rocks[1] = rock(1, 1, 0, 44.9, 0, 40);
  result.rocks[2] = rock(2, 1, 0, 45.1, 0, 40);
  m = ComputeMisfit(obs, scene, result);
  EXPECT_EQ(m.runs[1].stuck, 1);
  EXPECT_GT(m.value, 10.0) << m.Report();
}

// Tracked runs released at x = 0, 100, 200, ... along y = 0, each run's
// rocks stopping at the given runouts (a negative runout: the rock left the
// terrain at that distance), each run observed at its own runout.
struct RunCase {
  core::Scene scene = TwoPartitionScene();
  Observations obs;
  core::SimulationResult result;
  RunCase(const std::vector<std::vector<double>>& runouts, const std::vector<double>& observed,
          double error) {
    scene.groups.clear();
    Runout r;
    for (std::size_t i = 0; i < runouts.size(); ++i) {
      core::RockGroup g;
      g.id = "r" + std::to_string(i);
      g.release.point = Eigen::Vector2d(100.0 * static_cast<double>(i), 0);
      scene.groups.push_back(g);
      r.run_ids.push_back(g.id);
      r.run_groups.push_back(static_cast<int>(i));
      r.run_origins.push_back(g.release.point);
      r.stop_points.push_back(g.release.point + Eigen::Vector2d(0, observed[i]));
      r.distances.push_back(observed[i]);
      for (const double d : runouts[i]) {
        core::RockRecord rock =
            StoppedRock(static_cast<int>(result.rocks.size()), g.release.point.x(), std::abs(d));
        rock.group = static_cast<int>(i);
        rock.start = Eigen::Vector3d(g.release.point.x(), 0, 0);
        if (d < 0) rock.outcome = core::Outcome::kLeft;
        result.rocks.push_back(rock);
      }
    }
    obs.runout = r;
    obs.error.runout = error;
  }
  // Run `id`'s residual (observation "" when it has none).
  Residual Run(const Misfit& m, const std::string& id) const {
    for (const Residual& res : m.residuals)
      if (res.id.kind == ObservationKind::kRun && res.id.name == id) return res;
    return Residual{};
  }
};

// One residual per run: its group's median against its stop, scaled by the
// error, the run's spread shrunk toward the pooled spread, and the median's
// Monte Carlo error; a run of one rock takes the pooled spread.
TEST(MisfitTest, PerRunResidualShrinksTheRunsSpreadTowardThePool) {
  const RunCase c({{70.0}, {40.0, 50.0, 60.0}}, {60.0, 56.0}, 1.0);
  const Misfit m = ComputeMisfit(c.obs, c.scene, c.result);
  // The pool: run r1's deviations about its median 50 are 10, 0, 10 (r0 has
  // one rock and gives none): 1.4826 x 10.
  const double pool = 14.826, pi = 3.14159265358979323846;
  const Residual a = c.Run(m, "r0");
  const Residual b = c.Run(m, "r1");
  ASSERT_EQ(a.id.observation(), "run r0") << m.Report();
  ASSERT_EQ(b.id.observation(), "run r1") << m.Report();
  EXPECT_EQ(a.id.quantity(), "runout");
  EXPECT_EQ(a.id, ResidualId::Of(ObservationKind::kRun, 0, "r0").With(Statistic::kRunout));
  EXPECT_EQ(b.id.index, 1);
  // r0: one rock, the pool's spread; its median is the rock.
  const double sigma_a = std::sqrt(1.0 + pool * pool * (1.0 + pi / 2.0));
  EXPECT_DOUBLE_EQ(a.simulated, 70.0);
  EXPECT_NEAR(a.sigma, sigma_a, 1e-9);
  EXPECT_NEAR(a.value, 10.0 / sigma_a, 1e-12);
  // r1: own variance 100 (2 degrees of freedom) shrunk toward the pool (4).
  const double s2 = (4.0 * pool * pool + 2.0 * 100.0) / 6.0;
  const double sigma_b = std::sqrt(1.0 + s2 * (1.0 + pi / 6.0));
  EXPECT_NEAR(b.sigma, sigma_b, 1e-9);
  EXPECT_NEAR(b.value, -6.0 / sigma_b, 1e-12);
  EXPECT_NEAR(m.runs[1].spread, std::sqrt(s2), 1e-9);
  EXPECT_NEAR(m.runs[1].sigma, sigma_b, 1e-9);
  // The predictive spread is the simulation's: only the error is fixed.
  EXPECT_DOUBLE_EQ(a.fixed_sigma, 1.0);
  EXPECT_DOUBLE_EQ(b.fixed_sigma, 1.0);
  // Pooled quantiles (10 + max) and the share come first, as without runs.
  EXPECT_EQ(m.residuals.size(), 10u + 1u + 2u);
  // Without a pool (no spread in any group), a run's sigma is the error.
  const RunCase d({{70.0}, {50.0, 50.0}}, {60.0, 56.0}, 2.0);
  const Misfit md = ComputeMisfit(d.obs, d.scene, d.result);
  EXPECT_NEAR(d.Run(md, "r0").value, 5.0, 1e-12) << md.Report();
  EXPECT_NEAR(d.Run(md, "r1").value, -3.0, 1e-12) << md.Report();
}

// A run split between rocks that stuck and rocks that ran, and a run with a
// censored rock, give moderate residuals, not wild ones.
TEST(MisfitTest, PerRunResidualOfASplitOrCensoredRunStaysModerate) {
  // r0: two rocks stuck at the release, two ran to 80 m (the run: 80 m);
  // r1: three rocks near its 60 m, one left the terrain at 150 m.
  const RunCase c({{0.2, 0.3, 80.0, 80.0}, {58.0, 60.0, 62.0, -150.0}, {90.0, 100.0}},
                  {80.0, 60.0, 95.0}, 2.0);
  const Misfit m = ComputeMisfit(c.obs, c.scene, c.result);
  EXPECT_EQ(m.runs[0].stuck, 2);
  const Residual split = c.Run(m, "r0");
  ASSERT_TRUE(split.id.kind == ObservationKind::kRun) << m.Report();
  EXPECT_NEAR(split.simulated, 40.15, 1e-9);  // (0.3 + 80) / 2
  EXPECT_LT(std::abs(split.value), 2.0) << m.Report();
  EXPECT_GT(split.sigma, 20.0) << m.Report();
  const Residual censored = c.Run(m, "r1");
  ASSERT_TRUE(censored.id.kind == ObservationKind::kRun) << m.Report();
  EXPECT_LT(std::abs(censored.value), 1.0) << m.Report();
  // The same split run with every rock stuck is far off, as it should be.
  const RunCase stuck({{0.2, 0.3, 0.2, 0.3}, {58.0, 60.0, 62.0, 61.0}, {90.0, 100.0}},
                      {80.0, 60.0, 95.0}, 2.0);
  const Misfit ms = ComputeMisfit(stuck.obs, stuck.scene, stuck.result);
  EXPECT_LT(stuck.Run(ms, "r0").value, -3.0) << ms.Report();
}

// When not every observed rock stopped, the runs given are those that did,
// and the simulated rocks are compared in kind, as the pooled runout does:
// a run's median and the pooled quantiles of the rocks that stopped, the
// share stopped of every rock. Counted at the far end instead, the rocks
// that left raised the simulated runouts the field could not show, and a
// value that loses more rocks was pushed away (the scene family's tracked
// runs: bench/README.md).
TEST(MisfitTest, RunsWithRocksThatLeftAreComparedInKind) {
  RunCase c({{58.0, 60.0, -150.0, -150.0}, {88.0, 90.0, 92.0, -150.0}}, {60.0, 90.0}, 1.0);
  const auto run_medians = [&](double stopped_fraction) {
    c.obs.runout->stopped_fraction = stopped_fraction;
    c.obs.runout->observed_rocks = 3;
    const Misfit m = ComputeMisfit(c.obs, c.scene, c.result);
    EXPECT_EQ(m.runs[0].rocks, 4);
    EXPECT_EQ(m.runs[0].stopped, 2);
    EXPECT_EQ(m.runs[1].rocks, 4);
    for (const Residual& r : m.residuals) {
      if (r.id.kind == ObservationKind::kRunoutStopped) {
        EXPECT_DOUBLE_EQ(r.simulated, 5.0 / 8.0);
      }
    }
    return std::vector<double>{m.runs[0].simulated, m.runs[1].simulated};
  };
  // Every observed rock stopped: the rocks that left enter at the far end.
  const std::vector<double> all = run_medians(1.0);
  EXPECT_GT(all[0], 100.0);
  EXPECT_DOUBLE_EQ(all[1], 91.0);
  // Two of three observed rocks stopped: only the simulated ones that did.
  const std::vector<double> some = run_medians(2.0 / 3.0);
  EXPECT_DOUBLE_EQ(some[0], 59.0);
  EXPECT_DOUBLE_EQ(some[1], 90.0);
}

// options.run_terms: the pooled quantiles, the per-run residuals, or both.
TEST(MisfitTest, RunTermsChooseTheComparisons) {
  const RunCase c({{40.0, 50.0}, {70.0, 80.0}}, {45.0, 85.0}, 1.0);
  auto count = [&](RunTerms terms, int* runs, int* pooled) {
    MisfitOptions o;
    o.run_terms = terms;
    const Misfit m = ComputeMisfit(c.obs, c.scene, c.result, o);
    *runs = *pooled = 0;
    for (const Residual& r : m.residuals) {
      *runs += r.id.kind == ObservationKind::kRun ? 1 : 0;
      *pooled += r.id.kind == ObservationKind::kRunoutDistance ? 1 : 0;
    }
  };
  int runs = 0, pooled = 0;
  count(RunTerms::kPooled, &runs, &pooled);
  EXPECT_EQ(runs, 0);
  EXPECT_EQ(pooled, 10);
  count(RunTerms::kPerRun, &runs, &pooled);
  EXPECT_EQ(runs, 2);
  EXPECT_EQ(pooled, 0);
  count(RunTerms::kBoth, &runs, &pooled);
  EXPECT_EQ(runs, 2);
  EXPECT_EQ(pooled, 10);
  for (const RunTerms t : {RunTerms::kPooled, RunTerms::kPerRun, RunTerms::kBoth}) {
    RunTerms parsed = RunTerms::kPooled;
    EXPECT_TRUE(StringToRunTerms(RunTermsToString(t), &parsed));
    EXPECT_EQ(parsed, t);
  }
  RunTerms unused;
  EXPECT_FALSE(StringToRunTerms("all", &unused));
  MisfitOptions bad;
  bad.run_spread_prior = -1.0;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("run_spread_prior = -1"));
}

TEST(MisfitTest, PassingFractionWithBinomialError) {
  const core::Scene scene = TwoPartitionScene();
  core::SimulationResult result = CrossingAt(1, std::vector<double>(4, 1.0));
  for (int i = 0; i < 6; ++i) result.rocks.push_back(StoppedRock(10 + i, 60.0, 0.0));
  Observations obs;
  Passing p;
  p.label = "passing[0] BP-2";
  p.partition = 1;
  p.fraction = 0.4;
  obs.passing.push_back(p);
  obs.error.passing = 0.05;

  Misfit m = ComputeMisfit(obs, scene, result);
  ASSERT_EQ(m.residuals.size(), 1u);  // no scars, no runout: nothing else
  EXPECT_EQ(m.residuals[0].id.quantity(), "fraction");
  EXPECT_DOUBLE_EQ(m.residuals[0].simulated, 0.4);
  EXPECT_NEAR(m.residuals[0].sigma, std::sqrt(0.05 * 0.05 + 0.4 * 0.6 / 10), 1e-12);
  EXPECT_EQ(m.value, 0.0);
  EXPECT_DOUBLE_EQ(m.residuals[0].fixed_sigma, 0.05);
  EXPECT_NEAR(m.log_scale, std::log(m.residuals[0].sigma / 0.05), 1e-12);

  obs.passing[0].fraction = 0.3;
  m = ComputeMisfit(obs, scene, result);
  EXPECT_GT(m.residuals[0].value, 0.0);
  EXPECT_NEAR(m.residuals[0].value, 0.1 / m.residuals[0].sigma, 1e-12);
}

TEST(MisfitTest, TreeScarsPoolTheTreesOfASet) {
  const core::Scene scene = TwoPartitionScene();
  Observations obs;
  ScarSet set;
  set.label = "tree_scars[0] trees";
  Tree a;
  a.probe = 0;
  a.heights = {1.0, 2.0, 3.0};
  Tree b;
  b.probe = 1;
  b.heights = {0.5, 1.5};
  set.trees = {a, b};
  obs.tree_scars.push_back(set);
  obs.error.height = 0.2;

  core::SimulationResult result;
  const double at_a[] = {1.0, 2.0, 3.0, -1};  // -1: did not pass the tree
  const double at_b[] = {0.5, -1, 1.5, -1};
  for (int i = 0; i < 4; ++i) {
    core::RockRecord rock = StoppedRock(i, 100, 0);
    rock.crossings.clear();  // partitions not recorded
    rock.trees.resize(2);
    if (at_a[i] >= 0)
      rock.trees[0] = core::Crossing{true, at_a[i], 1.0, 1.0, Eigen::Vector3d::Zero()};
    if (at_b[i] >= 0)
      rock.trees[1] = core::Crossing{true, at_b[i], 1.0, 1.0, Eigen::Vector3d::Zero()};
    result.rocks.push_back(rock);
  }
  const Misfit m = ComputeMisfit(obs, scene, result);
  EXPECT_FALSE(m.penalised) << m.message;
  EXPECT_EQ(m.value, 0.0);

  result.rocks[0].trees[1].height = 2.5;  // a higher pass at tree b
  EXPECT_GT(ComputeMisfit(obs, scene, result).value, 0.0);
}

// A tree that is a stem of the forest is compared with the heights at which
// rocks struck that stem, every strike on it counted, not with passages.
TEST(MisfitTest, TreeScarsAtAStemCompareTheStrikes) {
  const core::Scene scene = TwoPartitionScene();
  Observations obs;
  ScarSet set;
  set.label = "tree_scars[0] trees";
  Tree tree;
  tree.probe = 0;
  tree.stem = 3;
  tree.heights = {0.4, 0.9, 1.6};
  set.trees = {tree};
  obs.tree_scars.push_back(set);
  obs.error.height = 0.2;

  core::SimulationResult result;
  const std::vector<std::vector<double>> strikes = {{0.4}, {}, {0.9, 1.6}};
  for (int i = 0; i < 3; ++i) {
    core::RockRecord rock = StoppedRock(i, 100, 0);
    rock.crossings.clear();
    rock.trees.resize(1);
    rock.trees[0] = core::Crossing{true, 5.0 + i, 1.0, 1.0, Eigen::Vector3d::Zero()};  // passages
    for (const double h : strikes[static_cast<std::size_t>(i)]) {
      core::TreeStrike s;
      s.tree = 3;
      s.height = h;
      rock.strikes.push_back(s);
    }
    core::TreeStrike other;  // a strike on another stem
    other.tree = 2;
    other.height = 7.0;
    rock.strikes.push_back(other);
    result.rocks.push_back(rock);
  }
  const Misfit m = ComputeMisfit(obs, scene, result);
  EXPECT_FALSE(m.penalised) << m.message;
  EXPECT_EQ(m.value, 0.0);

  result.rocks[2].strikes[1].height = 3.0;  // a higher strike on the stem
  EXPECT_GT(ComputeMisfit(obs, scene, result).value, 0.0);
}

TEST(MisfitTest, MissingRecordsAreAProgrammerError) {
  const core::Scene scene = TwoPartitionScene();
  core::SimulationResult result = CrossingAt(0, SomeHeights());
  for (core::RockRecord& rock : result.rocks) rock.crossings.clear();
  EXPECT_THROW(ComputeMisfit(ScarsAt(0, SomeHeights(), 0.3), scene, result), std::invalid_argument);

  Observations trees;
  ScarSet set;
  set.label = "tree_scars[0] trees";
  Tree t;
  t.probe = 0;
  t.heights = {1};
  set.trees = {t};
  trees.tree_scars.push_back(set);
  trees.error.height = 0.1;
  EXPECT_THROW(ComputeMisfit(trees, scene, CrossingAt(0, SomeHeights())), std::invalid_argument);
}

TEST(MisfitOptionsTest, IsValidNamesTheFieldAndTheRule) {
  std::string error;
  EXPECT_TRUE(MisfitOptions().IsValid(&error)) << error;

  MisfitOptions bad_level;
  bad_level.levels = {0.5, 1.5};
  EXPECT_FALSE(bad_level.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("levels[1] = 1.5"));
  EXPECT_THROW(
      ComputeMisfit(Observations(), TwoPartitionScene(), core::SimulationResult(), bad_level),
      std::invalid_argument);

  MisfitOptions bad_penalty;
  bad_penalty.penalty = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(bad_penalty.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("penalty = inf"));

  MisfitOptions nothing;
  nothing.levels.clear();
  nothing.include_max = false;
  EXPECT_FALSE(nothing.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("include_max"));

  MisfitOptions bad_floor;
  bad_floor.sigma_floor = 0.0;
  EXPECT_FALSE(bad_floor.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("sigma_floor = 0"));
}

TEST(MisfitOptionsTest, LevelsAndMaxAreChosen) {
  MisfitOptions options;
  options.levels = {0.5, 0.975};
  options.include_max = false;
  const Misfit m = ComputeMisfit(ScarsAt(0, SomeHeights(), 0.3), TwoPartitionScene(),
                                 CrossingAt(0, SomeHeights()), options);
  ASSERT_EQ(m.residuals.size(), 2u);
  EXPECT_EQ(m.residuals[0].id.quantity(), "p50");
  EXPECT_EQ(m.residuals[1].id.quantity(), "p97.5");
}

// A residual's identity prints as the outputs' names, and compares by its
// typed fields: the same text from different identities never matches.
TEST(ResidualIdTest, PrintsTheOutputsNamesAndComparesByItsFields) {
  const ResidualId distance = ResidualId::Of(ObservationKind::kRunoutDistance);
  EXPECT_EQ(distance.With(Statistic::kQuantile, 0.9).observation(), "runout distance");
  EXPECT_EQ(distance.With(Statistic::kQuantile, 0.9).quantity(), "p90");
  EXPECT_EQ(distance.With(Statistic::kQuantile, 0.025).quantity(), "p2.5");
  EXPECT_EQ(distance.With(Statistic::kMax).quantity(), "max");
  EXPECT_EQ(ResidualId::Of(ObservationKind::kRunoutMassClass, 1, "10-40").observation(),
            "runout distance, mass 10-40 kg");
  EXPECT_EQ(ResidualId::Of(ObservationKind::kRunoutLateral).observation(), "runout lateral");
  const ResidualId stopped =
      ResidualId::Of(ObservationKind::kRunoutStopped).With(Statistic::kShare);
  EXPECT_EQ(stopped.observation() + " " + stopped.quantity(), "runout stopped share");
  const ResidualId run = ResidualId::Of(ObservationKind::kRun, 2, "v083").With(Statistic::kRunout);
  EXPECT_EQ(run.observation() + " " + run.quantity(), "run v083 runout");
  const ResidualId passing =
      ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] BP-2").With(Statistic::kFraction);
  EXPECT_EQ(passing.observation() + " " + passing.quantity(), "passing[0] BP-2 fraction");
  EXPECT_EQ(ResidualId::Of(ObservationKind::kTreeScars, 1, "tree_scars[1] trees").observation(),
            "tree_scars[1] trees");
  const ResidualId none;
  EXPECT_EQ(none.observation() + none.quantity(), "");
  // A campaign site's: the site before the observation; a prior's: the
  // site in the quantity.
  ResidualId at_a = distance.With(Statistic::kQuantile, 0.5);
  at_a.site = "a";
  EXPECT_EQ(at_a.observation(), "a: runout distance");
  EXPECT_EQ(at_a.quantity(), "p50");
  ResidualId prior = ResidualId::Of(ObservationKind::kPrior, 0, "talus.hardness");
  prior = prior.With(Statistic::kOffset);
  prior.site = "a";
  EXPECT_EQ(prior.observation(), "prior");
  EXPECT_EQ(prior.quantity(), "a:talus.hardness_offset");
  // Equality and order by the fields.
  EXPECT_NE(at_a, distance.With(Statistic::kQuantile, 0.5)) << "another site";
  EXPECT_EQ(at_a.observation_id(), [&] {
    ResidualId of = distance;
    of.site = "a";
    return of;
  }());
  EXPECT_NE(ResidualId::Of(ObservationKind::kRun, 0, "x"),
            ResidualId::Of(ObservationKind::kRun, 1, "x"));
  const ResidualId p10 = distance.With(Statistic::kQuantile, 0.1);
  const ResidualId p90 = distance.With(Statistic::kQuantile, 0.9);
  EXPECT_NE(p10 < p90, p90 < p10);
  EXPECT_FALSE(p10 < p10);
}

TEST(MisfitTest, ReportListsEveryResidual) {
  const Misfit m = ComputeMisfit(ScarsAt(0, SomeHeights(), 0.3), TwoPartitionScene(),
                                 CrossingAt(0, Shifted(SomeHeights(), 0.5)));
  const std::string report = m.Report();
  EXPECT_THAT(report, HasSubstr("tree_scars[0] BP-1"));
  EXPECT_THAT(report, HasSubstr("p10"));
  EXPECT_THAT(report, HasSubstr("max"));
  EXPECT_THAT(report, HasSubstr("misfit "));
}

}  // namespace
}  // namespace rockcal::observations
