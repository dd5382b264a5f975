#ifndef ROCKCAL_CORE_STATISTICS_H_
#define ROCKCAL_CORE_STATISTICS_H_

#include <vector>

namespace rockcal::core {

struct Stats {
  int count = 0;
  double mean = 0, p50 = 0, p90 = 0, p95 = 0, max = 0;
};

// Quantile q in [0, 1] of `sorted` (ascending), linear interpolation between
// order statistics (type 7). Requires a non-empty vector. The project's one
// quantile: every other quantile of a sample is this one.
double Quantile(const std::vector<double>& sorted, double q);
// The value at 0-based `position` of `sorted` (ascending, non-empty),
// linear between order statistics; the last one at or beyond n - 1. Quantile
// is this at q (n - 1); a quantile of another definition is this at its own
// position.
double AtPosition(const std::vector<double>& sorted, double position);
// Quantile of `values` in any order: sorts them in place, then Quantile; NaN
// when there are none.
double QuantileOf(std::vector<double>* values, double q);
// Median of `values` (any order): the middle one of the sorted values, or
// the mean of the two middle ones; NaN when empty.
double Median(std::vector<double> values);
// Sample standard deviation of `values` (divisor n - 1, the mean as their sum
// over n). Requires at least two values.
double SampleStandardDeviation(const std::vector<double>& values);
// Student's t distribution's 97.5 % quantile with `df` >= 1 degrees of
// freedom: tabulated to 3 decimals up to 30, then the Cornish-Fisher
// expansion z + (z^3 + z) / (4 df) (within 0.002 there).
double StudentT975(int df);
// Summary of `values` (any order); all zero when empty.
Stats Summarize(std::vector<double> values);

// Quantile q in [0, 1] of a sample made of `sorted` (ascending, finite) and
// `beyond` more values known only to lie past every one of them: above them
// (`above`, e.g. the runout of rocks that left the terrain) or below them.
// Type 7 as Quantile over all sorted.size() + beyond values; +infinity
// (above) or -infinity (below) when the quantile falls on a value beyond or
// interpolates towards one. Requires sorted.size() + beyond > 0, beyond >= 0.
double QuantileWithBeyond(const std::vector<double>& sorted, int beyond, double q, bool above);

// A summary over every value of a sample part of which lies beyond the
// known ones (QuantileWithBeyond): a figure that falls among those is
// +infinity (beyond above) or -infinity (beyond below); all zero when there
// are no values at all.
struct BeyondStats {
  int count = 0;   // every value, the ones beyond included
  int beyond = 0;  // of which beyond
  double min = 0, p10 = 0, p50 = 0, p90 = 0, p95 = 0, max = 0;
};
BeyondStats SummarizeWithBeyond(std::vector<double> known, int beyond, bool above);

// At most `n` items spread over consecutive groups of `counts[g]` items
// each (items numbered group after group): every item when n covers them
// all; else each group's share of n (largest remainders), at least one item
// of every non-empty group while n allows, evenly spaced within the group.
// Ascending indices. A sample of rocks from every group, not the first n.
std::vector<int> SpreadOverGroups(const std::vector<int>& counts, int n);

// The two-sample Kolmogorov-Smirnov test of whether two samples come from
// one distribution: the largest distance between their empirical
// distribution functions, and the chance of a distance at least that large
// between two samples of one continuous distribution (asymptotic, with
// Stephens' small-sample correction: Press et al., Numerical Recipes, 3rd
// ed., 14.3.3). A whole distribution where a quantile check compares three
// points of it.
struct KsTest {
  double distance = 0.0;  // D in [0, 1]
  double p_value = 1.0;
};
// Samples in any order; D = 0 and p = 1 when either is empty.
KsTest TwoSampleKs(std::vector<double> a, std::vector<double> b);
// The Kolmogorov distribution's tail Q(lambda) = 2 sum_{k>=1} (-1)^(k-1)
// exp(-2 k^2 lambda^2): 1 at lambda <= 0, falling to 0.
double KolmogorovTail(double lambda);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_STATISTICS_H_
