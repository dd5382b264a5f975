#ifndef ROCKCAL_CORE_STATISTICS_H_
#define ROCKCAL_CORE_STATISTICS_H_

#include <vector>

namespace rockcal::core {

struct Stats {
  int count = 0;
  double mean = 0, p50 = 0, p90 = 0, p95 = 0, max = 0;
};

// Quantile q in [0, 1] of `sorted` (ascending), linear interpolation between
// order statistics (type 7). Requires a non-empty vector.
double Quantile(const std::vector<double>& sorted, double q);
// Sample standard deviation of `values` (divisor n - 1, the mean as their sum
// over n). Requires at least two values.
double SampleStandardDeviation(const std::vector<double>& values);
// Summary of `values` (any order); all zero when empty.
Stats Summarize(std::vector<double> values);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_STATISTICS_H_
