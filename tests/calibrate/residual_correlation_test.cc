#include "rockcal/calibrate/residual_correlation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rockcal/core/random.h"

namespace rockcal::calibrate {
namespace {

// Two x partitions crossed by every rock; no terrain (records by hand).
core::Scene TwoPartitions(int rocks) {
  core::Scene scene;
  for (int k = 0; k < 2; ++k) {
    core::Partition p;
    p.id = "BP-" + std::to_string(k + 1);
    p.value = 50.0 + 30.0 * k;
    scene.partitions.push_back(p);
  }
  core::RockGroup group;
  group.count = rocks;
  scene.groups = {group};
  return scene;
}

// Rocks crossing BP-1 at heights `a` and BP-2 at heights `b`.
core::SimulationResult Crossings(const std::vector<double>& a, const std::vector<double>& b) {
  core::SimulationResult result;
  for (std::size_t i = 0; i < a.size(); ++i) {
    core::RockRecord rock;
    rock.rock = static_cast<int>(i);
    rock.outcome = core::Outcome::kStopped;
    rock.stop = Eigen::Vector3d(100.0, 0.0, 1.0);
    rock.crossings.resize(2);
    const double h[2] = {a[i], b[i]};
    for (int k = 0; k < 2; ++k) {
      core::Crossing& c = rock.crossings[static_cast<std::size_t>(k)];
      c.crossed = true;
      c.height = h[k];
      c.speed = 5.0;
      c.energy = 100.0;
    }
    result.rocks.push_back(rock);
  }
  return result;
}

// Scars observed at both partitions (the values matter little: the
// correlation is of the simulated statistics).
observations::Observations ScarsAtBoth(const std::vector<double>& heights) {
  observations::Observations obs;
  for (int k = 0; k < 2; ++k) {
    observations::ScarSet set;
    set.label = "tree_scars[" + std::to_string(k) + "] BP-" + std::to_string(k + 1);
    set.partition = k;
    set.heights = heights;
    obs.tree_scars.push_back(set);
  }
  obs.error.height = 0.01;
  return obs;
}

std::vector<double> Exponential(core::RandomStream* random, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(-std::log(1.0 - random->Uniform()));
  return v;
}

// Index of the residual of scar set `set` at quantile `level` (9 quantiles
// and the maximum per set, in the misfit's order).
Eigen::Index At(int set, int decile) { return set * 10 + decile - 1; }

TEST(ResidualCorrelation, StatisticsOfTheSameRocksAreCorrelatedAcrossDistributions) {
  const int n = 200;
  core::RandomStream random(7, 1);
  const std::vector<double> a = Exponential(&random, n);
  std::vector<double> independent = Exponential(&random, n), same = a;
  for (double& h : same) h = 2.0 * h + 0.5;  // the same order: fully dependent
  const core::Scene scene = TwoPartitions(n);
  const observations::Observations obs = ScarsAtBoth(Exponential(&random, 60));

  double lambda = -1.0;
  const Eigen::MatrixXd dependent =
      BootstrapResidualCorrelation(obs, scene, Crossings(a, same), {}, 400, 3, &lambda);
  ASSERT_EQ(dependent.rows(), 20);
  EXPECT_GE(lambda, 0.0);
  EXPECT_LE(lambda, 1.0);
  // The same rocks, the same order: each quantile of one set moves with the
  // same quantile of the other, where the misfit takes them as independent.
  for (int d = 1; d <= 9; ++d) EXPECT_GT(dependent(At(0, d), At(1, d)), 0.9) << "p" << 10 * d;
  // Within a distribution, neighbouring quantiles share values, far ones
  // less (asymptotically 0.82 between p40 and p50, 0.11 between p10 and p90).
  EXPECT_GT(dependent(At(0, 4), At(0, 5)), 0.6);
  EXPECT_LT(dependent(At(0, 1), At(0, 9)), 0.4);

  const Eigen::MatrixXd apart =
      BootstrapResidualCorrelation(obs, scene, Crossings(a, independent), {}, 400, 3);
  for (int d = 1; d <= 9; ++d) EXPECT_LT(std::abs(apart(At(0, d), At(1, d))), 0.25) << "p" << 10 * d;
  EXPECT_GT(apart(At(0, 4), At(0, 5)), 0.6);

  // A seed fixes it.
  EXPECT_TRUE(apart.isApprox(
      BootstrapResidualCorrelation(obs, scene, Crossings(a, independent), {}, 400, 3), 0.0));
  // Its whitening makes residuals of that correlation independent.
  const Eigen::MatrixXd w = Whitening(dependent);
  EXPECT_TRUE((w * dependent * w.transpose()).isApprox(Eigen::MatrixXd::Identity(20, 20), 1e-9));
}

TEST(ResidualCorrelation, ShrinksTowardsTheTargetByTheReplicatesEvidence) {
  core::RandomStream random(11, 2);
  // x2 = 0.6 x1 + 0.8 z: correlation 0.6; x3 and x4 constant.
  auto draw = [&](int n) {
    Eigen::MatrixXd x(n, 4);
    for (int i = 0; i < n; ++i) {
      const double a = random.Normal(), z = random.Normal();
      x(i, 0) = a;
      x(i, 1) = 0.6 * a + 0.8 * z;
      x(i, 2) = 0.1 + 0.2;  // constant, its mean off by rounding
      x(i, 3) = 1.0 / 3.0;
    }
    return x;
  };
  Eigen::MatrixXd target = Eigen::MatrixXd::Identity(4, 4);
  target(0, 2) = target(2, 0) = 0.3;
  double lambda = -1.0;
  const Eigen::MatrixXd many = ShrunkCorrelation(draw(4000), target, &lambda);
  EXPECT_LT(lambda, 0.01);
  EXPECT_NEAR(many(0, 1), 0.6, 0.04);
  EXPECT_EQ(many(0, 2), 0.3) << "a column that does not vary keeps the target's";
  // Two constant columns are not correlated by their rounding.
  EXPECT_EQ(many(2, 3), 0.0);
  EXPECT_EQ(ShrunkCorrelation(draw(1000), target)(2, 3), 0.0);
  EXPECT_EQ(many(1, 1), 1.0);
  double few_lambda = -1.0;
  ShrunkCorrelation(draw(5), target, &few_lambda);
  EXPECT_GT(few_lambda, lambda) << "fewer replicates, less trust in their correlation";
  EXPECT_EQ(ShrunkCorrelation(draw(2), target), target);
}

}  // namespace
}  // namespace rockcal::calibrate
