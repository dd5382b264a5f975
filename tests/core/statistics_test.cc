#include "rockcal/core/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

TEST(Statistics, QuantileWithBeyondRanksTheValuesBeyondPastTheKnownOnes) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> known = {1.0, 2.0, 3.0};
  // Above: the sample is {1, 2, 3, beyond, beyond}; type 7 at pos = q (n - 1).
  EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 2, 0.1, true), 1.4);  // pos 0.4
  EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 2, 0.5, true), 3.0);  // pos 2
  EXPECT_EQ(QuantileWithBeyond(known, 2, 0.6, true), inf);         // pos 2.4, towards beyond
  EXPECT_EQ(QuantileWithBeyond(known, 2, 1.0, true), inf);
  EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 2, 0.0, true), 1.0);
  // Below: {beyond, beyond, 1, 2, 3}.
  EXPECT_EQ(QuantileWithBeyond(known, 2, 0.0, false), -inf);
  EXPECT_EQ(QuantileWithBeyond(known, 2, 0.4, false), -inf);  // pos 1.6, towards beyond
  EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 2, 0.5, false), 1.0);
  EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 2, 0.9, false), 2.6);  // pos 3.6
  EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 2, 1.0, false), 3.0);
  // Nothing beyond: Quantile's values; only values beyond: every figure beyond.
  for (double q : {0.0, 0.1, 0.35, 0.5, 0.9, 0.95, 1.0}) {
    EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 0, q, true), Quantile(known, q)) << "q = " << q;
    EXPECT_DOUBLE_EQ(QuantileWithBeyond(known, 0, q, false), Quantile(known, q)) << "q = " << q;
    EXPECT_EQ(QuantileWithBeyond({}, 3, q, true), inf) << "q = " << q;
  }
  const BeyondStats s = SummarizeWithBeyond({3.0, 1.0, 2.0}, 2, true);
  EXPECT_EQ(s.count, 5);
  EXPECT_EQ(s.beyond, 2);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.p10, 1.4);
  EXPECT_DOUBLE_EQ(s.p50, 3.0);
  EXPECT_EQ(s.p90, inf);
  EXPECT_EQ(s.p95, inf);
  EXPECT_EQ(s.max, inf);
  EXPECT_EQ(SummarizeWithBeyond({}, 0, true).count, 0);
}

TEST(Statistics, SpreadOverGroupsSamplesEveryGroupEvenly) {
  // Two equal groups: half each, evenly spaced (centres of equal slices).
  EXPECT_EQ(SpreadOverGroups({10, 10}, 4), (std::vector<int>{2, 7, 12, 17}));
  // A small group still gets one; the rest by share.
  const std::vector<int> s = SpreadOverGroups({1000, 5}, 30);
  ASSERT_EQ(s.size(), 30u);
  EXPECT_EQ(std::count_if(s.begin(), s.end(), [](int k) { return k >= 1000; }), 1);
  EXPECT_TRUE(std::is_sorted(s.begin(), s.end()));
  EXPECT_EQ(std::adjacent_find(s.begin(), s.end()), s.end()) << "no rock twice";
  // Enough for all: all; fewer than the groups: the largest shares; none.
  EXPECT_EQ(SpreadOverGroups({2, 1}, 5), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(SpreadOverGroups({2, 6, 2}, 1), (std::vector<int>{5}));
  EXPECT_EQ(SpreadOverGroups({0, 4}, 2), (std::vector<int>{1, 3}));
  EXPECT_TRUE(SpreadOverGroups({3}, 0).empty());
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
