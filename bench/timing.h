// Helpers shared by the benchmarks: medians of repeated simulations,
// sample quantiles with a Monte Carlo standard error, and --name arguments.
#ifndef ROCKCAL_BENCH_TIMING_H_
#define ROCKCAL_BENCH_TIMING_H_

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"

namespace rockcal::bench {

// The whole number after --NAME on the command line, or `fallback`.
inline long Arg(int argc, char** argv, const std::string& name, long fallback) {
  for (int k = 1; k + 1 < argc; ++k)
    if (argv[k] == "--" + name) return std::strtol(argv[k + 1], nullptr, 10);
  return fallback;
}

// The number after --NAME on the command line, or `fallback` (Arg reads
// whole numbers only: "0.3" would be 0).
inline double RealArg(int argc, char** argv, const std::string& name, double fallback) {
  for (int k = 1; k + 1 < argc; ++k)
    if (argv[k] == "--" + name) return std::strtod(argv[k + 1], nullptr);
  return fallback;
}

// The text after --NAME on the command line, or `fallback`.
inline std::string TextArg(int argc, char** argv, const std::string& name,
                           const std::string& fallback) {
  for (int k = 1; k + 1 < argc; ++k)
    if (argv[k] == "--" + name) return argv[k + 1];
  return fallback;
}

// Median of `v` (mean of the two middle values for an even count); 0 when empty.
inline double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct TimedRuns {
  std::vector<double> walls;      // wall seconds of each run (SimulationResult::wall_seconds)
  double median_wall = 0.0;       // s
  core::SimulationResult result;  // of the last run (runs are deterministic)
};

// Runs `scene` on `terrain` `runs` times at `threads` threads.
inline TimedRuns TimeSimulation(core::Scene scene, const core::Terrain& terrain, int threads,
                                int runs) {
  scene.options.threads = threads;
  TimedRuns timed;
  for (int r = 0; r < runs; ++r) {
    timed.result = core::Simulate(scene, terrain);
    timed.walls.push_back(timed.result.wall_seconds);
  }
  timed.median_wall = Median(timed.walls);
  return timed;
}

// 1- and 2-thread runs of `scene` taken in pairs (one of each, `runs`
// times), so that the shared machine's drift in speed falls on both sides of
// a pair; the speed-up is the median of the pairs' ratios.
struct ScalingRuns {
  TimedRuns one, two;    // at 1 and at 2 threads
  double speedup = 0.0;  // median over pairs of wall(1 thread) / wall(2 threads)
  // Median over the 2-thread runs of busy_seconds / (2 wall_seconds): 1 when
  // neither thread waited for the other (the schedule's part of the speed-up).
  double balance = 0.0;
};

inline ScalingRuns TimeScaling(const core::Scene& scene, const core::Terrain& terrain, int runs) {
  ScalingRuns s;
  std::vector<double> ratios, balances;
  for (int r = 0; r < runs; ++r) {
    const TimedRuns one = TimeSimulation(scene, terrain, 1, 1);
    const TimedRuns two = TimeSimulation(scene, terrain, 2, 1);
    s.one.walls.push_back(one.median_wall);
    s.two.walls.push_back(two.median_wall);
    ratios.push_back(one.median_wall / two.median_wall);
    balances.push_back(two.result.busy_seconds / (2.0 * two.median_wall));
    if (r + 1 == runs) {
      s.one.result = one.result;
      s.two.result = two.result;
    }
  }
  s.one.median_wall = Median(s.one.walls);
  s.two.median_wall = Median(s.two.walls);
  s.speedup = Median(ratios);
  s.balance = Median(balances);
  return s;
}

// The rock-steps a fixed-step engine would take for the same simulated rock
// lives: the sum over rocks of (simulated time / the rock's contact step).
inline double FixedStepRockSteps(const core::SimulationResult& result) {
  double n = 0.0;
  for (const core::RockRecord& r : result.rocks)
    if (r.dt > 0.0) n += r.time / r.dt;
  return n;
}

// A sample quantile (type 7) with a distribution-free standard error from the
// order statistics: the number of values below the true p-quantile is
// Binomial(n, p), so the sample quantiles at p -/+ sqrt(p (1 - p) / n) bracket
// it with about 68 % probability; half that bracket is the standard error.
struct QuantileEstimate {
  bool valid = false;
  double value = 0.0, se = 0.0;
};

inline QuantileEstimate EstimateQuantile(std::vector<double> v, double p) {
  QuantileEstimate q;
  if (v.size() < 2) return q;
  std::sort(v.begin(), v.end());
  const double half = std::sqrt(p * (1.0 - p) / static_cast<double>(v.size()));
  q.valid = true;
  q.value = core::Quantile(v, p);
  q.se = 0.5 *
         (core::Quantile(v, std::min(p + half, 1.0)) - core::Quantile(v, std::max(p - half, 0.0)));
  return q;
}

// What the accuracy checks compare: the runout x of the stopped rocks and
// the bounce heights at the scene's first partition.
struct Samples {
  std::vector<double> runout, heights;
};

// Below this p value of the Kolmogorov-Smirnov test two samples' whole
// distributions are said to differ (PrintQuantileCheck).
constexpr double kKsLevel = 0.01;

inline Samples Collect(const core::SimulationResult& r) {
  Samples s;
  for (const core::RockRecord& rock : r.rocks) {
    if (rock.outcome == core::Outcome::kStopped) s.runout.push_back(rock.stop.x());
    if (!rock.crossings.empty() && rock.crossings[0].crossed)
      s.heights.push_back(rock.crossings[0].height);
  }
  return s;
}

// Prints the runout (p10, p50, p90) and bounce-height (p50, p90, p95)
// quantiles of each of `samples` (columns named by `names`) with their
// errors, each marked "ok" when within two combined errors of the last
// column's (the reference) and "NO" otherwise; then each whole
// distribution against the reference's by the two-sample Kolmogorov-Smirnov
// test (core::TwoSampleKs: distance D and its p value, "differs" below
// kKsLevel), which sees a change of shape that three quantiles can miss.
// Returns the count of NO; per_column (if given) gets each column's, and
// ks_differ (if given) each column's count of distributions that differ.
inline int PrintQuantileCheck(const std::vector<std::string>& names,
                              const std::vector<Samples>& samples, const std::string& partition,
                              std::vector<int>* per_column = nullptr,
                              std::vector<int>* ks_differ = nullptr) {
  int failed = 0;
  if (ks_differ) ks_differ->assign(samples.size(), 0);
  if (per_column) per_column->assign(samples.size(), 0);
  std::printf("%-26s", "quantity");
  for (const std::string& n : names) std::printf(" %22s", n.c_str());
  std::printf("\n");
  auto row = [&](const std::string& label, std::vector<double> Samples::*field, double p) {
    std::printf("%-26s", label.c_str());
    const QuantileEstimate ref = EstimateQuantile(samples.back().*field, p);
    for (const Samples& s : samples) {
      const QuantileEstimate q = EstimateQuantile(s.*field, p);
      const bool ok =
          q.valid && ref.valid && std::abs(q.value - ref.value) <= 2.0 * std::hypot(q.se, ref.se);
      const bool last = &s == &samples.back();
      failed += !last && !ok;
      if (per_column && !last && !ok)
        ++(*per_column)[static_cast<std::size_t>(&s - samples.data())];
      std::printf(" %9.2f +- %5.2f %-3s", q.value, q.se, last ? "" : ok ? "ok" : "NO");
    }
    std::printf("\n");
  };
  row("runout x p10 [m]", &Samples::runout, 0.1);
  row("runout x p50 [m]", &Samples::runout, 0.5);
  row("runout x p90 [m]", &Samples::runout, 0.9);
  if (!partition.empty()) {
    row("height at " + partition + " p50 [m]", &Samples::heights, 0.5);
    row("height at " + partition + " p90 [m]", &Samples::heights, 0.9);
    row("height at " + partition + " p95 [m]", &Samples::heights, 0.95);
  }
  auto ks = [&](const std::string& label, std::vector<double> Samples::*field) {
    std::printf("%-26s", label.c_str());
    for (const Samples& s : samples) {
      if (&s == &samples.back()) break;
      const core::KsTest t = core::TwoSampleKs(s.*field, samples.back().*field);
      const bool differs = t.p_value < kKsLevel;
      if (ks_differ && differs) ++(*ks_differ)[static_cast<std::size_t>(&s - samples.data())];
      std::printf("   D %.3f p %.3f %-7s", t.distance, t.p_value, differs ? "differs" : "");
    }
    std::printf("\n");
  };
  ks("runout x, whole (KS)", &Samples::runout);
  if (!partition.empty()) ks("height, whole (KS)", &Samples::heights);
  return failed;
}

}  // namespace rockcal::bench

#endif  // ROCKCAL_BENCH_TIMING_H_
