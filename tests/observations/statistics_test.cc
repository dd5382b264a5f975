// The misfit's shared statistics (observations/src/statistics.cc): the
// standard errors of a quantile, of the maximum and of an order statistic,
// the maximum's order position, level names, and the verdict on a fit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rockcal/core/random.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::observations {
namespace {

using ::testing::HasSubstr;

TEST(QuantileErrorTest, RegularisedIncompleteBetaAgainstClosedFormsAndMpmath) {
  for (const double x : {0.05, 0.3, 0.5, 0.77}) {
    EXPECT_NEAR(RegularisedIncompleteBeta(x, 1.0, 1.0), x, 1e-13);
    EXPECT_NEAR(RegularisedIncompleteBeta(x, 3.5, 1.0), std::pow(x, 3.5), 1e-13);
    EXPECT_NEAR(RegularisedIncompleteBeta(x, 1.0, 4.0), 1.0 - std::pow(1.0 - x, 4.0), 1e-13);
    EXPECT_NEAR(RegularisedIncompleteBeta(x, 2.0, 2.0), 3 * x * x - 2 * x * x * x, 1e-13);
    EXPECT_NEAR(RegularisedIncompleteBeta(x, 6.5, 2.25),
                1.0 - RegularisedIncompleteBeta(1.0 - x, 2.25, 6.5), 1e-13);
  }
  EXPECT_NEAR(RegularisedIncompleteBeta(0.5, 40.0, 40.0), 0.5, 1e-13);
  // mpmath 1.3.0, betainc(a, b, 0, x, regularized=True).
  EXPECT_NEAR(RegularisedIncompleteBeta(0.3, 2.5, 4.0), 0.3521975859067672, 1e-13);
  EXPECT_NEAR(RegularisedIncompleteBeta(0.7, 30.2, 12.5), 0.4404796451620253, 1e-13);
  EXPECT_NEAR(RegularisedIncompleteBeta(0.01, 0.5, 0.5), 0.06376856085851985, 1e-13);
  EXPECT_EQ(RegularisedIncompleteBeta(0.0, 2.0, 3.0), 0.0);
  EXPECT_EQ(RegularisedIncompleteBeta(1.0, 2.0, 3.0), 1.0);
}

TEST(QuantileErrorTest, OrderStatisticsOfASample) {
  std::vector<double> s;
  for (int i = 0; i < 100; ++i) s.push_back(i);
  // The Maritz-Jarrett sums of 0..99 by mpmath 1.3.0's betainc. On evenly
  // spread values it is about sqrt(n p (1 - p)) positions' worth: 5 at the
  // median, 3 at p = 0.1.
  EXPECT_NEAR(QuantileStandardError(s, 0.5), 4.959146827318379, 1e-9);
  EXPECT_NEAR(QuantileStandardError(s, 0.1), 3.0188174554062854, 1e-9);
  EXPECT_NEAR(QuantileStandardError(s, 0.99), 1.1236941384355392, 1e-9);
  EXPECT_EQ(QuantileStandardError({3.0}, 0.5), 0.0);
  EXPECT_EQ(QuantileStandardError({}, 0.5), 0.0);
  // Scales with the values and ignores their offset.
  std::vector<double> t;
  for (const double v : s) t.push_back(7.0 + 0.25 * v);
  EXPECT_NEAR(QuantileStandardError(t, 0.3), 0.25 * QuantileStandardError(s, 0.3), 1e-12);

  EXPECT_EQ(MaxStandardError({1.0, 2.0, 7.0}), 5.0);
  EXPECT_EQ(MaxStandardError({7.0}), 0.0);
}

// Values in clusters (stop points in the hollows between virtual spheres):
// the quantile of a sample jumps from one cluster to the next between
// samples while the order statistics about it agree. 2000 samples of 60
// values, 30 % at 9, 40 % at 11, 30 % at 13: the error estimated from each
// sample against the quantile's spread over the samples.
TEST(QuantileErrorTest, ClusteredValuesKeepTheChanceOfTheNextCluster) {
  core::RandomStream rng(7, 0);
  for (const double level : {0.3, 0.6}) {
    std::vector<double> quantiles;
    double square = 0.0;
    const int samples = 2000;
    for (int k = 0; k < samples; ++k) {
      std::vector<double> x;
      for (int i = 0; i < 60; ++i) {
        const double u = rng.Uniform();
        x.push_back(u < 0.3 ? 9.0 : u < 0.7 ? 11.0 : 13.0);
      }
      std::sort(x.begin(), x.end());
      quantiles.push_back(ComparedQuantile(x, level));
      square += std::pow(QuantileStandardError(x, level), 2) / samples;
    }
    double mean = 0.0, spread = 0.0;
    for (const double q : quantiles) mean += q / samples;
    for (const double q : quantiles) spread += (q - mean) * (q - mean) / samples;
    // p = 0.3 sits on the first cluster's edge (spread 0.94 in a check by
    // hand, estimated 0.82), p = 0.6 inside the second (0.39, 0.57).
    EXPECT_GT(std::sqrt(square), 0.7 * std::sqrt(spread)) << level;
    EXPECT_LT(std::sqrt(square), 1.6 * std::sqrt(spread)) << level;
  }
}

// The design effect of a clustered sample's quantile: exact where every
// cluster repeats one value (m copies: m), 1 for independent values, and
// with it the quantile's error matches the spread of the quantile over
// samples of correlated clusters (the flights of one rock).
TEST(QuantileErrorTest, DesignEffectOfClusteredValues) {
  std::vector<double> values;
  std::vector<int> clusters, singles;
  for (int c = 0; c < 100; ++c)
    for (int k = 0; k < 5; ++k) {
      values.push_back(c);
      clusters.push_back(c);
      singles.push_back(5 * c + k);
    }
  // 30 of the 100 clusters below 29.5.
  EXPECT_NEAR(QuantileDesignEffect(values, clusters, 29.5, 0.3), 5.0, 1e-12);
  EXPECT_EQ(QuantileDesignEffect(values, singles, 29.5, 0.3), 1.0);
  EXPECT_EQ(QuantileDesignEffect(values, clusters, 29.5, 0.0), 1.0);
  EXPECT_EQ(QuantileDesignEffect(values, {}, 29.5, 0.3), 1.0);

  core::RandomStream rng(11, 0);
  for (const double level : {0.2, 0.5}) {
    std::vector<double> quantiles;
    double square = 0.0, plain = 0.0;
    const int samples = 2000;
    for (int k = 0; k < samples; ++k) {
      std::vector<double> x;
      std::vector<int> by;
      for (int c = 0; c < 30; ++c) {
        const double centre = rng.Normal();
        for (int i = 0; i < 6; ++i) {
          x.push_back(centre + 0.5 * rng.Normal());
          by.push_back(c);
        }
      }
      std::vector<double> sorted = x;
      std::sort(sorted.begin(), sorted.end());
      const double q = ComparedQuantile(sorted, level);
      quantiles.push_back(q);
      const double e = QuantileStandardError(sorted, level);
      square += e * e * QuantileDesignEffect(x, by, q, level) / samples;
      plain += e * e / samples;
    }
    double mean = 0.0, spread = 0.0;
    for (const double q : quantiles) mean += q / samples;
    for (const double q : quantiles) spread += (q - mean) * (q - mean) / samples;
    // Intra-cluster correlation 0.8, six values a cluster: the independent
    // values' error is some 2.3 times too small.
    EXPECT_LT(std::sqrt(plain), 0.6 * std::sqrt(spread)) << level;
    EXPECT_GT(std::sqrt(square), 0.8 * std::sqrt(spread)) << level;
    EXPECT_LT(std::sqrt(square), 1.25 * std::sqrt(spread)) << level;
  }
}

// The maximum's error is the larger of the top gap and the top tenth's mean
// excess over the next value: a tie at the top does not zero it, and a lone
// far maximum keeps its gap.
// Type 8: (n + 1/3) p - 2/3, clamped to the sample; the median as type 7.
TEST(QuantileErrorTest, ComparedQuantileIsHyndmanAndFansType8) {
  EXPECT_NEAR(ComparedQuantilePosition(100, 0.1), 10.0 + 1.0 / 30.0 - 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(ComparedQuantilePosition(100, 0.9), 90.3 - 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(ComparedQuantilePosition(41, 0.5), 20.0, 1e-12);
  EXPECT_NEAR(ComparedQuantilePosition(40, 0.5), 19.5, 1e-12);
  EXPECT_EQ(ComparedQuantilePosition(5, 0.05), 0.0);  // 0.267 - 0.667 < 0
  EXPECT_EQ(ComparedQuantilePosition(5, 0.99), 4.0);  // 5.28 - 0.667 > 4
  EXPECT_EQ(ComparedQuantilePosition(1, 0.3), 0.0);
  std::vector<double> s;
  for (int i = 0; i < 10; ++i) s.push_back(2.0 * i);
  // n = 10, p = 0.25: position 10.333 / 4 - 2/3 = 1.9167, value 3.8333.
  EXPECT_NEAR(ComparedQuantile(s, 0.25), 2.0 * (10.0 + 1.0 / 3.0) / 4.0 - 4.0 / 3.0, 1e-12);
  EXPECT_EQ(ComparedQuantile({7.0}, 0.9), 7.0);
}

TEST(QuantileErrorTest, MaxStandardErrorIsTheTopGapOrTheTopTenthsMeanExcess) {
  // Below 20 values, one spacing: the gap of the two largest.
  std::vector<double> small = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 14.0};
  EXPECT_EQ(MaxStandardError(small), 4.0);
  // 20 values, j = 2. The two largest tied: their excess over the third.
  std::vector<double> tied;
  for (int i = 0; i < 18; ++i) tied.push_back(i);
  tied.push_back(30.0);
  tied.push_back(30.0);
  EXPECT_EQ(MaxStandardError(tied), 13.0);
  // A lone far maximum: its gap (22), above the mean excess ((23 + 1) / 2).
  std::vector<double> lone;
  for (int i = 0; i < 19; ++i) lone.push_back(i);
  lone.push_back(40.0);
  EXPECT_EQ(MaxStandardError(lone), 22.0);
  // The quantiles of an exponential tail of scale 2 (n = 1000, j = 100), the
  // largest moved down onto the second: the gap is 0, and the mean excess
  // over the 0.9 quantile is the scale, less the moved value's 2 ln 3 / 100.
  std::vector<double> exponential;
  for (int i = 0; i < 1000; ++i) exponential.push_back(-2.0 * std::log(1.0 - (i + 0.5) / 1000.0));
  exponential.back() = exponential[998];
  EXPECT_NEAR(MaxStandardError(exponential), 2.0 - 2.0 * std::log(3.0) / 100.0, 0.01);
}

TEST(QuantileErrorTest, MaxOrderPositionExceedsTheObservedMaximumHalfTheTime) {
  // As many values or fewer: P_1 = n / (n + m) <= 1/2, the simulated maximum.
  EXPECT_EQ(MaxOrderPosition(41, 41), 40.0);
  EXPECT_EQ(MaxOrderPosition(8, 8), 7.0);
  EXPECT_EQ(MaxOrderPosition(10, 20), 9.0);
  EXPECT_EQ(MaxOrderPosition(1, 5), 0.0);
  // n = 2m = 120: P_1 = 2/3, P_2 = 120 * 119 / (180 * 179) = 14280 / 32220;
  // k = 1 + (2/3 - 1/2) / (2/3 - P_2), the position n - k.
  const double p2 = 14280.0 / 32220.0;
  EXPECT_NEAR(MaxOrderPosition(120, 60), 120.0 - (1.0 + (2.0 / 3 - 0.5) / (2.0 / 3 - p2)), 1e-12);
  // n = 4m = 164, m = 41: P_1 = 0.8, P_2 = 0.8 * 163 / 204,
  // P_3 = P_2 * 162 / 203 (0.5101 > 1/2), P_4 = P_3 * 161 / 202 (0.4066).
  const double q3 = 0.8 * 163 / 204 * 162 / 203, q4 = q3 * 161 / 202;
  EXPECT_NEAR(MaxOrderPosition(164, 41), 164.0 - (3.0 + (q3 - 0.5) / (q3 - q4)), 1e-12);
  EXPECT_NEAR(MaxOrderPosition(100, 10), 92.93780262374514, 1e-11);
}

TEST(QuantileErrorTest, OrderStatisticErrorIsTheLocalSlopeOverItsSpread) {
  std::vector<double> s;
  for (int i = 0; i < 100; ++i) s.push_back(2.0 * i);
  // Interior: half the spread h = 5 positions either side of the median
  // (slope 2), about QuantileStandardError's.
  EXPECT_NEAR(OrderStatisticError(s, 49.5), 10.0, 1e-12);
  EXPECT_NEAR(OrderStatisticError(s, 49.5), QuantileStandardError(s, 0.5), 0.1);
  // At the top, h = 1 over the one position below: the gap of the two largest.
  std::vector<double> t = {1.0, 2.0, 7.0};
  EXPECT_NEAR(OrderStatisticError(t, 2.0), MaxStandardError(t), 1e-12);
  // Near the top: p = 97.5 / 99, h = sqrt(100 p (1 - p)) = 1.2215, slope 2.
  EXPECT_NEAR(OrderStatisticError(s, 97.5), 2.0 * std::sqrt(100.0 * 97.5 / 99 * 1.5 / 99), 1e-12);
  // p = 98.5 / 99: h = sqrt(0.5025) < 1, so h = 1, the span [97.5, 99] clamped.
  std::vector<double> u = s;
  u.back() = 201.0;  // slope (201 - 195) / 1.5 = 4 over the clamped span
  EXPECT_NEAR(OrderStatisticError(u, 98.5), 4.0, 1e-12);
  EXPECT_EQ(OrderStatisticError({3.0}, 0.0), 0.0);
}

TEST(QuantileErrorTest, LevelNames) {
  EXPECT_EQ(LevelName(0.1), "p10");
  EXPECT_EQ(LevelName(0.9), "p90");
  EXPECT_EQ(LevelName(0.025), "p2.5");
  EXPECT_EQ(LevelName(1.0), "p100");
  EXPECT_EQ(LevelName(0.0), "p0");
}

// The verdict names the quantities outside their uncertainty and judges
// them by the chance that a correct model does as badly: the count beyond 2
// sigma (a binomial tail at q = P(|Z| > 2) = 0.0455003) and the largest
// (1 - (1 - P(|Z| >= x))^N); poor below 1 %, fair below 5 %. The chances
// below were computed apart (math.comb and math.erfc).
TEST(MisfitTest, VerdictJudgesByTheChanceOfACorrectModel) {
  Misfit m;
  auto add = [&](const ResidualId& id, double value) {
    Residual r;
    r.id = id;
    r.simulated = 40 + value;
    r.observed = 40;
    r.sigma = 1;
    r.value = value;
    m.residuals.push_back(r);
  };
  for (int k = 0; k < 20; ++k)
    add(ResidualId::Of(ObservationKind::kRunoutDistance).With(Statistic::kQuantile, 0.05 * k), 0.5);
  add(ResidualId::Of(ObservationKind::kRunoutStopped).With(Statistic::kShare), -1.0);
  FitVerdict v = AssessFit(m);
  EXPECT_FALSE(v.poor || v.fair);
  EXPECT_TRUE(v.outside.empty());
  EXPECT_EQ(v.count_chance, 1.0);
  EXPECT_THAT(v.Sentence(), HasSubstr("good: every compared quantity (21) within 2 sigma"));
  // One of 21 at 2.5 sigma: 62 % of correct models have one beyond 2 sigma,
  // 23 % a largest of 2.5 or more: good, and said so.
  m.residuals[3].value = 2.5;
  v = AssessFit(m);
  EXPECT_NEAR(v.count_chance, 0.6239097576503987, 1e-12);
  EXPECT_NEAR(v.largest_chance, 0.23082671467858062, 1e-12);
  EXPECT_FALSE(v.poor || v.fair);
  EXPECT_THAT(v.Sentence(), HasSubstr("good: 1 of 21 compared quantities outside 2 sigma, as a "
                                      "correct model gives"));
  // Four beyond 2 sigma of 21: P(K >= 4) = 1.4 %: fair; five: 0.21 %: poor.
  m.residuals[4].value = -2.2;
  m.residuals[5].value = 2.1;
  m.residuals[6].value = 2.05;
  v = AssessFit(m);
  EXPECT_NEAR(v.count_chance, 0.013772612871617582, 1e-12);
  EXPECT_TRUE(v.fair);
  EXPECT_FALSE(v.poor);
  EXPECT_THAT(v.Sentence(), HasSubstr("fair: 4 of 21 compared quantities outside 2 sigma (a "
                                      "correct model gives at least as many with probability "
                                      "1.4 %"));
  m.residuals[7].value = -2.3;
  v = AssessFit(m);
  EXPECT_NEAR(v.count_chance, 0.0021498699479894265, 1e-12);
  EXPECT_TRUE(v.poor);
  // One far residual alone: 3.2 sigma of 21 (2.8 %) fair, 4 sigma (0.13 %) poor.
  for (int k = 4; k < 8; ++k) m.residuals[static_cast<std::size_t>(k)].value = 0.0;
  m.residuals.back().value = -3.2;  // the stopped share, as any other quantity
  v = AssessFit(m);
  EXPECT_NEAR(v.largest_chance, 0.028466610986159647, 1e-12);
  EXPECT_TRUE(v.fair);
  EXPECT_THAT(v.outside.front(), HasSubstr("runout stopped share"));
  m.residuals.back().value = -4.0;
  v = AssessFit(m);
  EXPECT_NEAR(v.largest_chance, 0.0013293499181606645, 1e-12);
  EXPECT_TRUE(v.poor);
  EXPECT_THAT(v.Sentence(),
              HasSubstr("poor: 2 of 21 compared quantities outside 2 sigma (a correct model gives "
                        "at least as many with probability 25 %, a largest as far with "
                        "probability 0.13 %), the worst runout stopped share"));
  // The thresholds follow the count: 8 of 73 beyond 2 sigma is fair (1.8 %),
  // 9 poor (0.58 %), where 8 of 21 would be poor.
  Misfit many;
  for (int k = 0; k < 73; ++k) many.residuals.push_back(m.residuals[0]);
  for (int k = 0; k < 8; ++k) many.residuals[static_cast<std::size_t>(k)].value = 2.1;
  v = AssessFit(many);
  EXPECT_NEAR(v.count_chance, 0.017796117900413768, 1e-12);
  EXPECT_TRUE(v.fair);
  many.residuals[8].value = -2.1;
  EXPECT_NEAR(AssessFit(many).count_chance, 0.005828516649954717, 1e-12);
  EXPECT_TRUE(AssessFit(many).poor);
  // A penalised misfit is poor whatever its residuals.
  m.residuals.back().value = 0.0;
  m.penalised = true;
  EXPECT_TRUE(AssessFit(m).poor);
  EXPECT_THAT(AssessFit(m).Sentence(), HasSubstr("poor: the misfit was penalised"));
}

}  // namespace
}  // namespace rockcal::observations
