// The posterior sampler and stage (calibrate/src/mcmc.cc, posterior.cc) on
// analytic targets whose posterior is known exactly.
#include "rockcal/calibrate/posterior.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "rockcal/calibrate/posterior_draws.h"
#include "rockcal/calibrate/residual_correlation.h"
#include "rockcal/core/polygon.h"
#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"

namespace rockcal::calibrate {
namespace {

// Two parameters of the default kind and bounds (materials "a" and "b"): the
// test objectives' space.
ParameterSpace TwoValues() {
  Parameter a, b;
  a.material = "a";
  b.material = "b";
  return ParameterSpace({a, b});
}

// An analytic objective of TwoValues(): EvaluateAll evaluates its points
// one by one, in order.
class TwoValueObjective : public ObjectiveFunction {
 public:
  TwoValueObjective() : space_(TwoValues()) {}
  const ParameterSpace& space() const override { return space_; }
  std::vector<observations::Misfit> EvaluateAll(
      const std::vector<std::vector<double>>& points,
      const std::function<void(int, const observations::Misfit&)>& done) const override {
    std::vector<observations::Misfit> out;
    for (std::size_t k = 0; k < points.size(); ++k) {
      out.push_back(Evaluate(points[k]));
      if (done) done(static_cast<int>(k), out.back());
    }
    return out;
  }

 private:
  ParameterSpace space_;
};

// Residuals linear in the unit box: r = A (u - centre) / s, so exp(-misfit)
// is a Gaussian of mean `centre` and precision sum_i a_i a_i^T / s_i^2.
class LinearObjective final : public TwoValueObjective {
 public:
  int residual_count() const override { return 3; }
  observations::Misfit Evaluate(const std::vector<double>& x) const override {
    ++calls;
    observations::Misfit m;
    const double r[3] = {(x[0] - 0.4) / 0.08, (x[1] - 0.6) / 0.05, (x[0] + x[1] - 1.0) / 0.1};
    for (double v : r) {
      observations::Residual res;
      res.value = v;
      m.residuals.push_back(res);
      m.value += 0.5 * v * v;
    }
    return m;
  }
  mutable int calls = 0;
};

// The exact marginal standard deviations of LinearObjective's posterior.
Eigen::Vector2d ExactSd() {
  Eigen::Matrix2d precision = Eigen::Matrix2d::Zero();
  const Eigen::Vector2d a1(1, 0), a2(0, 1), a3(1, 1);
  precision += a1 * a1.transpose() / (0.08 * 0.08);
  precision += a2 * a2.transpose() / (0.05 * 0.05);
  precision += a3 * a3.transpose() / (0.1 * 0.1);
  const Eigen::Matrix2d cov = precision.inverse();
  return {std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1))};
}

TEST(AdaptiveMetropolis, SamplesAKnownGaussian) {
  const Eigen::Vector2d mean(0.3, 0.55), sd(0.05, 0.1);
  const double rho = 0.6;
  Eigen::Matrix2d cov;
  cov << sd(0) * sd(0), rho * sd(0) * sd(1), rho * sd(0) * sd(1), sd(1) * sd(1);
  const Eigen::Matrix2d precision = cov.inverse();
  McmcOptions o;
  o.seed = 5;
  const McmcResult r = AdaptiveMetropolis(
      [&](const Eigen::VectorXd& u) {
        const Eigen::Vector2d d = u - mean;
        return -0.5 * d.dot(precision * d);
      },
      {Eigen::Vector2d(0.9, 0.1), Eigen::Vector2d(0.1, 0.9)}, o);
  ASSERT_EQ(r.samples.size(), static_cast<std::size_t>(o.chains * o.steps / o.thin));
  for (int k = 0; k < 2; ++k) {
    std::vector<double> v;
    for (const auto& s : r.samples) v.push_back(s(k));
    // Monte Carlo tolerance: ~4000 samples with an autocorrelation time of
    // a few steps; 0.15 sd for the median, 0.25 sd for the outer quantiles.
    EXPECT_NEAR(core::QuantileOf(&v, 0.5), mean(k), 0.15 * sd(k)) << "coordinate " << k;
    EXPECT_NEAR(core::QuantileOf(&v, 0.05), mean(k) - 1.645 * sd(k), 0.25 * sd(k)) << "coordinate " << k;
    EXPECT_NEAR(core::QuantileOf(&v, 0.95), mean(k) + 1.645 * sd(k), 0.25 * sd(k)) << "coordinate " << k;
    EXPECT_LT(r.rhat[static_cast<std::size_t>(k)], 1.05);
  }
  EXPECT_GT(r.acceptance, 0.15);
  EXPECT_LT(r.acceptance, 0.6);
}

TEST(AdaptiveMetropolis, TheSameSeedGivesTheSameSamples) {
  McmcOptions o;
  o.burn_in = 200, o.steps = 400, o.seed = 3;
  const auto target = [](const Eigen::VectorXd& u) { return -0.5 * u.squaredNorm() / 0.01; };
  const McmcResult a = AdaptiveMetropolis(target, {Eigen::Vector2d(0.5, 0.5)}, o);
  const McmcResult b = AdaptiveMetropolis(target, {Eigen::Vector2d(0.5, 0.5)}, o);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t k = 0; k < a.samples.size(); ++k) EXPECT_EQ(a.samples[k], b.samples[k]);
}

TEST(SplitRhat, IsOneForAgreeingChainsAndLargeForDisagreeingOnes) {
  std::vector<std::vector<double>> same(4), apart(4);
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 200; ++k) {
      const double v = std::sin(0.7 * k + c);
      same[static_cast<std::size_t>(c)].push_back(v);
      apart[static_cast<std::size_t>(c)].push_back(v + 3.0 * c);
    }
  EXPECT_LT(SplitRhat(same), 1.02);
  EXPECT_GT(SplitRhat(apart), 2.0);
}

TEST(EffectiveSampleSize, CountsIndependentDrawsAndDiscountsCorrelatedOnes) {
  // Independent uniform draws: about every draw counts. An AR(1) chain with
  // coefficient 0.9: the integrated autocorrelation time is (1 + 0.9) / (1 - 0.9) = 19.
  core::RandomStream rng(5, 0);
  std::vector<std::vector<double>> iid(4), ar(4);
  for (int c = 0; c < 4; ++c) {
    double x = 0.0;
    for (int k = 0; k < 5000; ++k) {
      iid[static_cast<std::size_t>(c)].push_back(rng.Uniform());
      x = 0.9 * x + rng.Normal();
      ar[static_cast<std::size_t>(c)].push_back(x);
    }
  }
  const double n = 20000.0;
  const double e_iid = EffectiveSampleSize(iid), e_ar = EffectiveSampleSize(ar);
  EXPECT_GT(e_iid, 0.85 * n) << e_iid;
  EXPECT_LT(e_iid, 1.15 * n) << e_iid;
  EXPECT_GT(e_ar, n / 19.0 * 0.7) << e_ar;
  EXPECT_LT(e_ar, n / 19.0 * 1.3) << e_ar;
}

TEST(DrawSampleIndices, DistinctInRangeAndFixedByTheSeed) {
  const std::vector<int> a = DrawSampleIndices(50, 20, 7);
  ASSERT_EQ(a.size(), 20u);
  std::vector<int> sorted = a;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a sample twice";
  EXPECT_GE(sorted.front(), 0);
  EXPECT_LT(sorted.back(), 50);
  EXPECT_EQ(DrawSampleIndices(50, 20, 7), a);
  EXPECT_NE(DrawSampleIndices(50, 20, 8), a);
  // As many draws as samples: every sample once.
  std::vector<int> all = DrawSampleIndices(5, 5, 1);
  std::sort(all.begin(), all.end());
  EXPECT_EQ(all, (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(SamplePosterior, RecoversAKnownGaussianPosterior) {
  const LinearObjective objective;
  PosteriorOptions o;
  o.design_points = 20;
  o.rounds = 2;
  const PosteriorResult r = SamplePosterior(objective, {}, o, nullptr);
  const Eigen::Vector2d sd = ExactSd();
  const double centre[2] = {0.4, 0.6};
  for (int k = 0; k < 2; ++k) {
    const ParameterPosterior& p = r.parameters[static_cast<std::size_t>(k)];
    EXPECT_NEAR(p.median, centre[k], 0.15 * sd(k)) << "parameter " << k;
    EXPECT_NEAR(p.p05, centre[k] - 1.645 * sd(k), 0.25 * sd(k)) << "parameter " << k;
    EXPECT_NEAR(p.p95, centre[k] + 1.645 * sd(k), 0.25 * sd(k)) << "parameter " << k;
    EXPECT_FALSE(p.undetermined);
  }
  EXPECT_LT(r.max_rhat, 1.05);
  EXPECT_LT(r.emulator_variance, 0.02) << "a linear function is emulated almost exactly";
  EXPECT_EQ(r.simulated, objective.calls);
  EXPECT_TRUE(r.message.empty()) << r.message;
  // Fixed sigmas (no log term): the whole likelihood is the same one, and
  // the sampler takes the same steps.
  o.sigma_log_term = true;
  const PosteriorResult with_term = SamplePosterior(objective, {}, o, nullptr);
  ASSERT_EQ(with_term.samples.size(), r.samples.size());
  for (std::size_t k = 0; k < r.samples.size(); ++k) ASSERT_EQ(with_term.samples[k], r.samples[k]);
}

// LinearObjective's residuals and a fourth, much narrower, that wants the
// first value at 0.8.
class PulledObjective final : public TwoValueObjective {
 public:
  int residual_count() const override { return 4; }
  observations::Misfit Evaluate(const std::vector<double>& x) const override {
    observations::Misfit m = linear_.Evaluate(x);
    observations::Residual pull;
    pull.value = (x[0] - 0.8) / 0.02;
    m.residuals.push_back(pull);
    m.value += 0.5 * pull.value * pull.value;
    return m;
  }

 private:
  LinearObjective linear_;
};

// Residuals named: a median of `first`, medians of two scar sets (three
// observations, so independent) and a run's.
std::vector<observations::Residual> Layout(observations::ObservationKind first) {
  using observations::ObservationKind;
  using observations::ResidualId;
  using observations::Statistic;
  std::vector<observations::Residual> layout(4);
  layout[0].id = ResidualId::Of(first, 2, "tree_scars[2] R").With(Statistic::kQuantile, 0.5);
  for (int k = 0; k < 2; ++k)
    layout[static_cast<std::size_t>(k + 1)].id =
        ResidualId::Of(ObservationKind::kTreeScars, k, "tree_scars[" + std::to_string(k) + "]")
            .With(Statistic::kQuantile, 0.5);
  layout[3].id = ResidualId::Of(ObservationKind::kRun, 0, "r1").With(Statistic::kRunout);
  return layout;
}

// A site's per-run residuals are left out of the likelihood where its
// pooled runout quantiles compare the same stops, and only there (docs/
// posterior.md, "Tracked runs"): the posterior is then LinearObjective's.
TEST(SamplePosterior, PerRunResidualsBesideThePooledQuantilesAreLeftOut) {
  using observations::ObservationKind;
  const PulledObjective objective;
  PosteriorOptions o;
  o.design_points = 20;
  o.rounds = 2;
  const PosteriorResult left =
      SamplePosterior(objective, {}, o, nullptr, nullptr, Layout(ObservationKind::kRunoutDistance));
  EXPECT_EQ(left.left_out, 1);
  const Eigen::Vector2d sd = ExactSd();
  EXPECT_NEAR(left.parameters[0].median, 0.4, 0.15 * sd(0));
  EXPECT_NEAR(left.parameters[1].median, 0.6, 0.15 * sd(1));
  // Beside scars the run's residual is the only comparison of its stop: kept.
  const PosteriorResult kept =
      SamplePosterior(objective, {}, o, nullptr, nullptr, Layout(ObservationKind::kTreeScars));
  EXPECT_EQ(kept.left_out, 0);
  EXPECT_GT(kept.parameters[0].median, 0.75) << "the narrow residual holds the first value";
}

TEST(PointReleaseWarning, NamesTheGroupsThatStartAtAnExactPoint) {
  core::Scene scene;
  core::RockGroup zone;
  zone.id = "slope";
  zone.release.zone = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  scene.groups = {zone};
  EXPECT_EQ(PointReleaseWarning(scene), "");
  core::RockGroup point;
  point.id = "v004";
  point.release.point = {33.4, 236.67};
  scene.groups.push_back(point);
  const std::string warning = PointReleaseWarning(scene);
  EXPECT_NE(warning.find("1 of 2 rock groups start at an exact point (the first: 'v004')"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("position_spread"), std::string::npos) << warning;
  // A position spread makes the point a disc, released as a zone.
  scene.groups[1].release.zone = core::DiscPolygon(point.release.point, 0.5);
  EXPECT_EQ(PointReleaseWarning(scene), "");
}

TEST(LikelihoodResiduals, LeavesOutASitesRunsWhereItsStopsArePooledUnlessTheLogTermIsOn) {
  using observations::ObservationKind;
  using observations::Residual;
  using observations::ResidualId;
  std::vector<Residual> layout(5);
  layout[0].id = ResidualId::Of(ObservationKind::kRunoutDistance);
  layout[0].id.site = "a";
  layout[1].id = ResidualId::Of(ObservationKind::kRun, 0, "r1");
  layout[1].id.site = "a";
  layout[2].id = ResidualId::Of(ObservationKind::kRun, 0, "r1");
  layout[2].id.site = "b";  // site b compares its runs one by one only
  layout[3].id = ResidualId::Of(ObservationKind::kRunoutStopped);
  layout[3].id.site = "a";
  layout[4].id = ResidualId::Of(ObservationKind::kTreeScars, 0, "tree_scars[0] P");
  layout[4].id.site = "b";
  EXPECT_EQ(LikelihoodResiduals(layout, false), (std::vector<bool>{true, false, true, true, true}));
  EXPECT_EQ(LikelihoodResiduals(layout, true), std::vector<bool>(5, true));
}

TEST(SamplePosterior, AParameterTheDataDoNotSeeIsFlaggedUndetermined) {
  // Only the first parameter enters the residuals.
  class OneSided final : public TwoValueObjective {
   public:
    int residual_count() const override { return 1; }
    observations::Misfit Evaluate(const std::vector<double>& x) const override {
      observations::Misfit m;
      observations::Residual r;
      r.value = (x[0] - 0.5) / 0.05;
      m.residuals = {r};
      m.value = 0.5 * r.value * r.value;
      return m;
    }
  } objective;
  PosteriorOptions o;
  o.design_points = 16;
  const PosteriorResult r = SamplePosterior(objective, {}, o, nullptr);
  EXPECT_FALSE(r.parameters[0].undetermined) << "width share " << r.parameters[0].width_share;
  EXPECT_TRUE(r.parameters[1].undetermined) << "width share " << r.parameters[1].width_share;
  EXPECT_NEAR(r.parameters[1].width_share, 1.0, 0.1);
}

// A sigma that grows with a value enters the likelihood as -log sigma, not
// only through the residuals it scales: 20 residuals 0.5 / s with s = 0.1 +
// u0 (the simulation's spread, over a fixed part 0.1) give -log p = 5 / (2
// s^2) + 20 log s, whose mode is s = 0.5; the squared residuals alone would
// pile the posterior at the upper bound (PosteriorOptions::sigma_log_term
// off). The second value is a plain Gaussian, N(0.6, 0.05^2) in the unit
// box.
TEST(SamplePosterior, ASigmaThatGrowsWithTheValuesEntersAsItsLogarithm) {
  class SpreadObjective final : public TwoValueObjective {
   public:
    int residual_count() const override { return 21; }
    observations::Misfit Evaluate(const std::vector<double>& x) const override {
      const std::vector<double> u = space().ToUnit(x);
      const double s = 0.1 + u[0];
      observations::Misfit m;
      for (int i = 0; i < 20; ++i) {
        observations::Residual r;
        r.sigma = s;
        r.fixed_sigma = 0.1;
        r.value = 0.5 / s;
        m.residuals.push_back(r);
        m.value += 0.5 * r.value * r.value;
        m.log_scale += std::log(s / 0.1);
      }
      observations::Residual plain;
      plain.value = (u[1] - 0.6) / 0.05;
      m.residuals.push_back(plain);
      m.value += 0.5 * plain.value * plain.value;
      return m;
    }
  } objective;
  // The exact marginal of u0 on a fine grid: p(s) ~ s^-20 exp(-5 / (2 s^2)).
  const int n = 100000;
  std::vector<double> cdf(n + 1, 0.0);
  double mass = 0.0;
  for (int k = 1; k <= n; ++k) {
    const double s = 0.1 + (k - 0.5) / n;
    mass += std::exp(-2.5 / (s * s) - 20.0 * std::log(s / 0.5) + 10.0);
    cdf[static_cast<std::size_t>(k)] = mass;
  }
  auto quantile = [&](double q) {
    const auto it = std::lower_bound(cdf.begin(), cdf.end(), q * mass);
    return static_cast<double>(it - cdf.begin()) / n;
  };
  const double exact[3] = {quantile(0.05), quantile(0.5), quantile(0.95)};
  const double sd = (exact[2] - exact[0]) / (2.0 * 1.645);
  PosteriorOptions o;
  o.design_points = 20;
  o.rounds = 3;
  o.sigma_log_term = true;
  const PosteriorResult r = SamplePosterior(objective, {}, o, nullptr);
  EXPECT_TRUE(r.sigma_log_term);
  const Parameter& par = objective.space().parameters()[0];
  auto unit = [&](double x) { return (x - par.lower) / (par.upper - par.lower); };
  const ParameterPosterior& p = r.parameters[0];
  EXPECT_NEAR(unit(p.p05), exact[0], 0.25 * sd) << "exact " << exact[0];
  EXPECT_NEAR(unit(p.median), exact[1], 0.25 * sd) << "exact " << exact[1];
  EXPECT_NEAR(unit(p.p95), exact[2], 0.25 * sd) << "exact " << exact[2];
  EXPECT_LT(r.max_rhat, 1.05);
  // Without the term the squared residuals alone, 5 / (2 s^2), fall
  // towards the upper bound: the median lies far above the exact one.
  o.sigma_log_term = false;
  const PosteriorResult without = SamplePosterior(objective, {}, o, nullptr);
  EXPECT_GT(unit(without.parameters[0].median), exact[2]);
}

TEST(SamplePosterior, AResumedRunReplaysItsEvaluationsAndGivesTheSameSamples) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rockcal_posterior_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "evaluations.jsonl").string();
  PosteriorOptions o;
  o.design_points = 12;
  o.rounds = 1;
  o.round_points = 4;
  o.mcmc.burn_in = 300, o.mcmc.steps = 600;
  PosteriorResult first;
  {
    const LinearObjective objective;
    EvaluationLog log(path, false, objective.space(), 1, 10);
    first = SamplePosterior(objective, {}, o, &log);
    EXPECT_EQ(first.simulated, objective.calls);
    EXPECT_EQ(log.size(), first.simulated);
  }
  const LinearObjective objective;
  EvaluationLog log(path, true, objective.space(), 1, 10);
  const PosteriorResult again = SamplePosterior(objective, {}, o, &log);
  EXPECT_EQ(objective.calls, 0) << "every evaluation replayed from the log";
  EXPECT_EQ(again.evaluated, first.evaluated);
  ASSERT_EQ(again.samples.size(), first.samples.size());
  for (std::size_t k = 0; k < again.samples.size(); ++k) ASSERT_EQ(again.samples[k], first.samples[k]);
  std::filesystem::remove_all(dir);
}

TEST(QuantileCorrelation, WhitensTheQuantilesOfEachDistributionAndNothingElse) {
  std::vector<observations::Residual> layout;
  using observations::ObservationKind;
  using observations::ResidualId;
  using observations::Statistic;
  const ResidualId distance = ResidualId::Of(ObservationKind::kRunoutDistance);
  for (const ResidualId& id :
       {distance.With(Statistic::kQuantile, 0.1), distance.With(Statistic::kQuantile, 0.5),
        distance.With(Statistic::kQuantile, 0.9), distance.With(Statistic::kMax)}) {
    observations::Residual r;
    r.id = id;
    layout.push_back(r);
  }
  observations::Residual f;
  f.id = ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] P").With(Statistic::kFraction);
  layout.push_back(f);
  const Eigen::MatrixXd w = Whitening(QuantileCorrelation(layout));
  // The correlation of the levels 0.1, 0.5 and 0.9 (sample quantiles).
  const double p[3] = {0.1, 0.5, 0.9};
  Eigen::MatrixXd corr = Eigen::MatrixXd::Identity(5, 5);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double a = std::min(p[i], p[j]), b = std::max(p[i], p[j]);
      corr(i, j) = std::sqrt(a * (1 - b) / (b * (1 - a)));
    }
  EXPECT_NEAR(corr(0, 2), 1.0 / 9.0, 1e-12);
  const Eigen::MatrixXd white = w * corr * w.transpose();
  EXPECT_TRUE(white.isApprox(Eigen::MatrixXd::Identity(5, 5), 1e-12)) << white;
  EXPECT_EQ(w(3, 3), 1.0);
  EXPECT_EQ(w(4, 4), 1.0);
  EXPECT_EQ(w.row(3).sum(), 1.0) << "the maximum stays independent";
}

// The predictive check reads each observed value against the band of a new
// observation: the draws' simulated values with the residual's sigma about
// them (the misfit's own likelihood), not the simulated values' band alone.
// Draws whose simulated value is the same m give exactly m -+ 1.6449 sigma;
// observed values drawn from that likelihood fall inside 90 % of the time,
// while the simulated values' own band (a tenth of sigma wide) holds almost
// none of them.
TEST(PredictiveBands, ANewObservationsBandHoldsNinetyPercentOfValuesDrawnFromTheLikelihood) {
  constexpr int kResiduals = 2000;
  constexpr double kMean = 3.0, kSigma = 0.5, kScatter = 0.02;
  std::vector<double> observed(kResiduals);
  core::RandomStream obs_rng(17, 0);
  for (double& o : observed) o = kMean + kSigma * obs_rng.Normal();
  const PredictiveDraw draw = [&](const std::vector<double>&, std::uint64_t seed) {
    PredictiveOutcome out;
    core::RandomStream rng(seed, 0);
    out.misfit.residuals.resize(kResiduals);
    for (int k = 0; k < kResiduals; ++k) {
      observations::Residual& r = out.misfit.residuals[static_cast<std::size_t>(k)];
      r.id = observations::ResidualId::Of(observations::ObservationKind::kTreeScars, k);
      // The first residual's draws all simulate kMean exactly.
      r.simulated = k == 0 ? kMean : kMean + kScatter * rng.Normal();
      r.observed = observed[static_cast<std::size_t>(k)];
      r.sigma = kSigma;
      r.value = (r.simulated - r.observed) / r.sigma;
    }
    return out;
  };
  PosteriorResult result;
  result.space = TwoValues();
  result.samples.assign(40, {0.3, 0.3});
  PredictiveBands(draw, 5, 100, 20, &result);
  ASSERT_EQ(result.bands.size(), static_cast<std::size_t>(kResiduals));
  const PredictiveBand& exact = result.bands[0];
  EXPECT_NEAR(exact.new_p05, kMean - 1.6448536 * kSigma, 1e-6);
  EXPECT_NEAR(exact.new_p95, kMean + 1.6448536 * kSigma, 1e-6);
  EXPECT_EQ(exact.p05, kMean);
  EXPECT_EQ(exact.p95, kMean);
  int inside = 0, inside_simulated = 0;
  for (const PredictiveBand& b : result.bands) {
    inside += b.inside();
    inside_simulated += b.observed >= b.p05 && b.observed <= b.p95;
  }
  // 90 % of 2000: binomial sd 13.4 (0.67 %).
  EXPECT_NEAR(inside / static_cast<double>(kResiduals), 0.9, 0.03) << inside;
  EXPECT_LT(inside_simulated, kResiduals / 10) << inside_simulated;
}

TEST(PosteriorOptions, InvalidValuesAreNamed) {
  PosteriorOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.rounds = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("rounds = -1"), std::string::npos) << error;
  o = PosteriorOptions();
  o.mcmc.chains = 1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("chains = 1"), std::string::npos) << error;
}

}  // namespace
}  // namespace rockcal::calibrate
