#include "rockcal/core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rockcal/core/random.h"

namespace rockcal::core {
namespace {

TEST(Statistics, MedianOfOddAndEvenCounts) {
  EXPECT_DOUBLE_EQ(Median({0.7}), 0.7);
  EXPECT_DOUBLE_EQ(Median({0.3, 0.1, 0.2}), 0.2);
  // Even: the mean of the two middle values, 0.2 and 0.3.
  EXPECT_DOUBLE_EQ(Median({0.4, 0.1, 0.3, 0.2}), 0.25);
  EXPECT_DOUBLE_EQ(Median({5.0, 1.0}), 3.0);
  EXPECT_TRUE(std::isnan(Median({})));
}

TEST(Statistics, SummaryOfKnownSample) {
  std::vector<double> v;
  for (int i = 10; i >= 0; --i) v.push_back(i);  // 0..10 reversed
  const Stats s = Summarize(v);
  EXPECT_EQ(s.count, 11);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_DOUBLE_EQ(s.p50, 5.0);
  EXPECT_DOUBLE_EQ(s.p90, 9.0);
  EXPECT_DOUBLE_EQ(s.p95, 9.5);
  EXPECT_DOUBLE_EQ(s.max, 10.0);
  EXPECT_EQ(Summarize({}).count, 0);
}

TEST(Random, StreamsAreReproducibleAndDistinct) {
  RandomStream a(7, 3), b(7, 3), c(7, 4), d(8, 3);
  for (int i = 0; i < 100; ++i) {
    const double x = a.Uniform();
    EXPECT_EQ(x, b.Uniform());
    EXPECT_GE(x, 0.0);
    EXPECT_LT(x, 1.0);
  }
  EXPECT_NE(c.NextU64(), d.NextU64());
  double sum = 0;
  RandomStream e(1, 0);
  for (int i = 0; i < 20000; ++i) sum += e.Uniform();
  EXPECT_NEAR(sum / 20000, 0.5, 0.01);
}

TEST(Statistics, SampleStandardDeviation) {
  // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, squared deviations sum 32, divisor 7.
  EXPECT_DOUBLE_EQ(SampleStandardDeviation({2, 4, 4, 4, 5, 5, 7, 9}), std::sqrt(32.0 / 7.0));
  EXPECT_DOUBLE_EQ(SampleStandardDeviation({1, 3}), std::sqrt(2.0));
}

// Closed forms at 1 and 2 degrees of freedom (tan(0.475 pi); 0.95 /
// sqrt(2 * 0.975 * 0.025)), published values at 10, 60 and 120, and the
// normal quantile in the limit.
TEST(Statistics, StudentT975KnownValues) {
  EXPECT_NEAR(StudentT975(1), std::tan(0.475 * 3.14159265358979323846), 1e-3);
  EXPECT_NEAR(StudentT975(2), 0.95 / std::sqrt(2 * 0.975 * 0.025), 1e-3);
  EXPECT_NEAR(StudentT975(10), 2.228, 1e-3);
  EXPECT_NEAR(StudentT975(60), 2.000, 2e-3);
  EXPECT_NEAR(StudentT975(120), 1.980, 2e-3);
  EXPECT_NEAR(StudentT975(1000000), 1.960, 1e-3);
  for (int df = 1; df < 200; ++df) EXPECT_GT(StudentT975(df), StudentT975(df + 1)) << df;
}

TEST(Statistics, KolmogorovTailKnownValues) {
  // The series summed to convergence; 1.3581 and 1.6276 are the familiar 5 %
  // and 1 % critical values.
  EXPECT_NEAR(KolmogorovTail(0.5), 0.96394524366, 1e-10);
  EXPECT_NEAR(KolmogorovTail(1.0), 0.26999967168, 1e-10);
  EXPECT_NEAR(KolmogorovTail(1.3581), 0.05, 1e-6);
  EXPECT_NEAR(KolmogorovTail(1.6276), 0.01, 1e-5);
  EXPECT_EQ(KolmogorovTail(0.0), 1.0);
  EXPECT_LT(KolmogorovTail(5.0), 1e-20);
}

TEST(Statistics, KsDistanceOfKnownSamples) {
  // {1,2,3,4} against {3,4,5,6}: the distribution functions part by 1/2
  // from 2 on (0.5 / 0, 0.75 / 0.25, 1 / 0.5).
  EXPECT_DOUBLE_EQ(TwoSampleKs({4, 3, 2, 1}, {3, 4, 5, 6}).distance, 0.5);
  EXPECT_DOUBLE_EQ(TwoSampleKs({1, 2}, {3, 4}).distance, 1.0);
  // Ties count once: equal samples are no distance apart.
  const KsTest same = TwoSampleKs({1, 2, 2, 3}, {3, 2, 1, 2});
  EXPECT_EQ(same.distance, 0.0);
  EXPECT_EQ(same.p_value, 1.0);
  EXPECT_EQ(TwoSampleKs({}, {1.0}).p_value, 1.0);
}

TEST(Statistics, KsPValueHoldsItsLevel) {
  // Two samples of one distribution fall below p = 0.05 about 5 % of the
  // time; a shift of a fifth of the range is found every time.
  RandomStream rng(11, 0);
  auto uniform = [&](int n, double shift) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(rng.Uniform() + shift);
    return v;
  };
  int rejected = 0, found = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    rejected += TwoSampleKs(uniform(300, 0.0), uniform(200, 0.0)).p_value < 0.05;
    found += TwoSampleKs(uniform(300, 0.0), uniform(200, 0.2)).p_value < 0.05;
  }
  // Binomial(400, 0.05): mean 20, standard deviation 4.4.
  EXPECT_GE(rejected, 8);
  EXPECT_LE(rejected, 34);
  EXPECT_EQ(found, trials);
}

}  // namespace
}  // namespace rockcal::core
