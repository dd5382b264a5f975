#include "rockcal/core/statistics.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace rockcal::core {

double SampleStandardDeviation(const std::vector<double>& values) {
  assert(values.size() >= 2);
  double sum = 0.0;
  for (double v : values) sum += v;
  const double n = static_cast<double>(values.size());
  const double mean = sum / n;
  double ss = 0.0;
  for (double v : values) ss += (v - mean) * (v - mean);
  return std::sqrt(ss / (n - 1.0));
}

double Quantile(const std::vector<double>& sorted, double q) {
  assert(!sorted.empty());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(sorted.size() - 1);
  const std::size_t k = static_cast<std::size_t>(std::floor(pos));
  if (k + 1 >= sorted.size()) return sorted.back();
  const double f = pos - static_cast<double>(k);
  return sorted[k] + f * (sorted[k + 1] - sorted[k]);
}

Stats Summarize(std::vector<double> values) {
  Stats s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.count = static_cast<int>(values.size());
  double sum = 0.0;
  for (double v : values) sum += v;
  s.mean = sum / static_cast<double>(values.size());
  s.p50 = Quantile(values, 0.5);
  s.p90 = Quantile(values, 0.9);
  s.p95 = Quantile(values, 0.95);
  s.max = values.back();
  return s;
}

}  // namespace rockcal::core
