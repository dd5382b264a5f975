#include "rockcal/core/statistics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <utility>

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

double StudentT975(int df) {
  assert(df >= 1);
  static constexpr double kTable[30] = {
      12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
      2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
      2.080,  2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
  if (df <= 30) return kTable[df - 1];
  const double z = 1.959964;
  return z + (z * z * z + z) / (4.0 * df);
}

double Quantile(const std::vector<double>& sorted, double q) {
  assert(!sorted.empty());
  return AtPosition(sorted, std::clamp(q, 0.0, 1.0) * static_cast<double>(sorted.size() - 1));
}

double AtPosition(const std::vector<double>& sorted, double position) {
  assert(!sorted.empty());
  const std::size_t k = static_cast<std::size_t>(std::floor(position));
  if (k + 1 >= sorted.size()) return sorted.back();
  const double f = position - static_cast<double>(k);
  return sorted[k] + f * (sorted[k + 1] - sorted[k]);
}

double QuantileOf(std::vector<double>* values, double q) {
  if (values->empty()) return std::nan("");
  std::sort(values->begin(), values->end());
  return Quantile(*values, q);
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
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

double QuantileWithBeyond(const std::vector<double>& sorted, int beyond, double q, bool above) {
  assert(beyond >= 0 && sorted.size() + static_cast<std::size_t>(beyond) > 0);
  const std::size_t n = sorted.size() + static_cast<std::size_t>(beyond);
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(n - 1);
  const std::size_t k = static_cast<std::size_t>(std::floor(pos));
  const double f = pos - static_cast<double>(k);
  const std::size_t last = f > 0.0 && k + 1 < n ? k + 1 : k;  // the values it reads: k .. last
  const std::size_t b = static_cast<std::size_t>(beyond);
  if (above) {
    if (last >= sorted.size()) return std::numeric_limits<double>::infinity();
  } else {
    if (k < b) return -std::numeric_limits<double>::infinity();
  }
  const std::size_t first = above ? 0 : b;  // index in the whole sample of sorted[0]
  const double lo = sorted[k - first];
  return last == k ? lo : lo + f * (sorted[last - first] - lo);
}

BeyondStats SummarizeWithBeyond(std::vector<double> known, int beyond, bool above) {
  BeyondStats s;
  if (known.empty() && beyond <= 0) return s;
  std::sort(known.begin(), known.end());
  s.count = static_cast<int>(known.size()) + beyond;
  s.beyond = beyond;
  s.min = QuantileWithBeyond(known, beyond, 0.0, above);
  s.p10 = QuantileWithBeyond(known, beyond, 0.1, above);
  s.p50 = QuantileWithBeyond(known, beyond, 0.5, above);
  s.p90 = QuantileWithBeyond(known, beyond, 0.9, above);
  s.p95 = QuantileWithBeyond(known, beyond, 0.95, above);
  s.max = QuantileWithBeyond(known, beyond, 1.0, above);
  return s;
}

std::vector<int> SpreadOverGroups(const std::vector<int>& counts, int n) {
  std::vector<int> out;
  long total = 0;
  int groups = 0;
  for (int c : counts) total += std::max(c, 0), groups += c > 0;
  if (n <= 0 || total == 0) return out;
  const std::size_t ng = counts.size();
  std::vector<int> take(ng, 0);
  if (n >= total) {
    for (std::size_t g = 0; g < ng; ++g) take[g] = std::max(counts[g], 0);
  } else {
    // One per non-empty group first (while n allows), the rest by share.
    int left = n;
    if (n >= groups)
      for (std::size_t g = 0; g < ng; ++g)
        if (counts[g] > 0) take[g] = 1, --left;
    std::vector<std::pair<double, std::size_t>> remainders;
    const double per = static_cast<double>(left) / static_cast<double>(total);
    int given = 0;
    for (std::size_t g = 0; g < ng; ++g) {
      if (counts[g] <= 0) continue;
      const double want = per * counts[g];
      const int whole = std::min(static_cast<int>(std::floor(want)), counts[g] - take[g]);
      take[g] += whole, given += whole;
      remainders.push_back({-(want - whole), g});  // largest remainder first, then group order
    }
    std::sort(remainders.begin(), remainders.end());
    for (std::size_t k = 0; given < left && k < remainders.size(); ++k) {
      const std::size_t g = remainders[k].second;
      if (take[g] < counts[g]) ++take[g], ++given;
    }
  }
  int offset = 0;
  for (std::size_t g = 0; g < ng; ++g) {
    const int c = std::max(counts[g], 0);
    for (int j = 0; j < take[g]; ++j)
      out.push_back(offset + static_cast<int>((j + 0.5) * c / take[g]));
    offset += c;
  }
  return out;
}

double KolmogorovTail(double lambda) {
  // The series converges slowly below lambda ~ 0.2, where Q is 1 to 1e-12.
  if (lambda < 0.2) return 1.0;
  double sum = 0.0, sign = 1.0;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * lambda * lambda);
    sum += sign * term;
    if (term < 1e-16) break;
    sign = -sign;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

KsTest TwoSampleKs(std::vector<double> a, std::vector<double> b) {
  KsTest t;
  if (a.empty() || b.empty()) return t;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size());
  // Walk both samples in order; after each distinct value both empirical
  // distribution functions are exact, so their distance is compared there.
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double v = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= v) ++i;
    while (j < b.size() && b[j] <= v) ++j;
    t.distance =
        std::max(t.distance, std::abs(static_cast<double>(i) / na - static_cast<double>(j) / nb));
  }
  const double ne = std::sqrt(na * nb / (na + nb));
  t.p_value = KolmogorovTail((ne + 0.12 + 0.11 / ne) * t.distance);
  return t;
}

}  // namespace rockcal::core
