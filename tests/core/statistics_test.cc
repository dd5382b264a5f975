#include "rockcal/core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rockcal/core/random.h"

namespace rockcal::core {
namespace {

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

}  // namespace
}  // namespace rockcal::core
