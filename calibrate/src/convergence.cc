// The convergence study of `rockcal study convergence` (study.h): a grid of
// rock counts and steps per contact, each statistic's error against the
// finest run, with its Monte Carlo and step parts, and the cheapest setting
// within the target.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/study.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/random.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using text::Num;
using text::Percent;

using core::kInf;
using core::kNaN;

}  // namespace

// ---- Convergence -----------------------------------------------------------------

namespace {

constexpr double kLevels[] = {0.5, 0.9, 0.95};
constexpr const char* kLevelNames[] = {"p50", "p90", "p95"};
constexpr int kLevelCount = 3;

// Per rock, the value of each source (partition heights, then runout travel),
// NaN where the rock has none.
struct RunSamples {
  std::vector<std::vector<double>> values;  // [source][rock]
};

RunSamples Samples(const core::Scene& scene, const core::SimulationResult& r) {
  const std::size_t np = scene.partitions.size();
  RunSamples s;
  s.values.assign(np + 1, std::vector<double>(r.rocks.size(), kNaN));
  for (std::size_t k = 0; k < r.rocks.size(); ++k) {
    const core::RockRecord& rock = r.rocks[k];
    for (std::size_t p = 0; p < np && p < rock.crossings.size(); ++p)
      if (rock.crossings[p].crossed) s.values[p][k] = rock.crossings[p].height;
    if (rock.outcome == core::Outcome::kStopped) s.values[np][k] = rock.stop.x() - rock.start.x();
  }
  return s;
}

// Quantiles kLevels of the finite values of `v` picked by `pick` (all when
// empty); NaN when there are none. *count gets how many there were.
void SourceQuantiles(const std::vector<double>& v, const std::vector<std::size_t>& pick,
                     std::vector<double>* scratch, double out[kLevelCount], int* count) {
  scratch->clear();
  if (pick.empty()) {
    for (double x : v)
      if (!std::isnan(x)) scratch->push_back(x);
  } else {
    for (std::size_t k : pick)
      if (!std::isnan(v[k])) scratch->push_back(v[k]);
  }
  if (count) *count = static_cast<int>(scratch->size());
  if (scratch->empty()) {
    for (int l = 0; l < kLevelCount; ++l) out[l] = kNaN;
    return;
  }
  std::sort(scratch->begin(), scratch->end());
  for (int l = 0; l < kLevelCount; ++l) out[l] = core::Quantile(*scratch, kLevels[l]);
}

// Bootstrap replicates of every source quantile, resampling the run's rocks:
// [source * kLevelCount + level][resample], NaN where a resample had no
// value. Runs of the same rocks with the same stream draw the same resamples,
// so replicates of two such runs pair up.
std::vector<std::vector<double>> BootstrapReplicates(const RunSamples& s, int resamples,
                                                     std::uint64_t seed, std::uint64_t stream) {
  const std::size_t sources = s.values.size();
  const std::size_t n = sources ? s.values[0].size() : 0;
  std::vector<std::vector<double>> out(
      sources * kLevelCount, std::vector<double>(static_cast<std::size_t>(resamples), kNaN));
  if (n == 0) return out;
  core::RandomStream rng(seed, stream);
  std::vector<std::size_t> pick(n);
  std::vector<double> scratch;
  for (std::size_t b = 0; b < static_cast<std::size_t>(resamples); ++b) {
    for (auto& k : pick) k = rng.Index(n);
    for (std::size_t src = 0; src < sources; ++src) {
      double q[kLevelCount];
      SourceQuantiles(s.values[src], pick, &scratch, q, nullptr);
      for (int l = 0; l < kLevelCount; ++l) out[src * kLevelCount + l][b] = q[l];
    }
  }
  return out;
}

// Half-width of the central `confidence` interval of the finite replicates;
// NaN when fewer than half of them are finite.
double HalfWidth(const std::vector<double>& replicates, double confidence) {
  std::vector<double> d;
  for (double x : replicates)
    if (std::isfinite(x)) d.push_back(x);
  if (d.empty() || 2 * d.size() < replicates.size()) return kNaN;
  std::sort(d.begin(), d.end());
  const double tail = 0.5 * (1.0 - confidence);
  return 0.5 * (core::Quantile(d, 1.0 - tail) - core::Quantile(d, tail));
}

struct RunData {
  int steps_per_contact = 0, rocks = 0;
  core::SimulationResult result;
  RunSamples samples;
  std::vector<double> values;                   // [source * kLevelCount + level]
  std::vector<int> counts;                      // [source]
  std::vector<std::vector<double>> replicates;  // BootstrapReplicates
};

}  // namespace

bool ConvergenceOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
    *error = "convergence." + field + " = " + value + ": " + rule;
    return false;
  };
  if (steps_per_contact.empty()) return fail("steps_per_contact", "[]", "needs at least one value");
  for (int n : steps_per_contact)
    if (n < 4 || n > 100000)
      return fail("steps_per_contact", std::to_string(n), "each must be in [4, 100000]");
  if (rock_counts.empty()) return fail("rock_counts", "[]", "needs at least one value");
  for (int n : rock_counts)
    if (n < 1) return fail("rock_counts", std::to_string(n), "each must be >= 1");
  if (!(target > 0 && target <= 10)) return fail("target", Num(target), "must be in (0, 10]");
  if (bootstrap < 20 || bootstrap > 1000000)
    return fail("bootstrap", std::to_string(bootstrap), "must be in [20, 1000000]");
  if (!(confidence > 0.5 && confidence < 1))
    return fail("confidence", Num(confidence), "must be in (0.5, 1)");
  if (min_values < 2) return fail("min_values", std::to_string(min_values), "must be >= 2");
  if (threads < 0) return fail("threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  return true;
}

namespace {

// The table of settings: N_c and rock counts, each ascending without repeats.
struct ConvergenceGrid {
  std::vector<int> ncs, counts;
  std::size_t index(std::size_t count_index, std::size_t nc_index) const {
    return count_index * ncs.size() + nc_index;
  }
};

ConvergenceGrid MakeGrid(const ConvergenceOptions& opt) {
  ConvergenceGrid grid{opt.steps_per_contact, opt.rock_counts};
  for (std::vector<int>* v : {&grid.ncs, &grid.counts}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return grid;
}

// The runner: every setting of the grid on `base`, rock count major so each
// count's N_c series shares its rocks; runs[grid.index(count, nc)].
std::vector<RunData> RunConvergenceGrid(const core::Scene& base, const core::Terrain& terrain,
                                        const ConvergenceGrid& grid,
                                        const ConvergenceOptions& opt) {
  const std::vector<int>& ncs = grid.ncs;
  const std::size_t sources = base.partitions.size() + 1;
  long total_work = 0;
  for (int n : grid.counts) total_work += static_cast<long>(n) * static_cast<long>(ncs.size());
  long done_before = 0;
  std::string error;
  std::vector<RunData> runs;
  for (int n : grid.counts) {
    core::Scene scene = base;
    scene.SetTotalRocks(n);
    for (int nc : ncs) {
      scene.options.steps_per_contact = nc;
      // The gentle-contact step is refined with the impact step, in the
      // site's ratio N_g / N_c (10 / 50 by default; 0 stays off).
      const int ng = base.options.gentle_steps_per_contact;
      if (ng > 0)
        scene.options.gentle_steps_per_contact =
            std::max(2, static_cast<int>(std::lround(static_cast<double>(ng) * nc /
                                                     base.options.steps_per_contact)));
      if (!scene.options.IsValid(&error)) throw std::invalid_argument(error);
      RunData run;
      run.steps_per_contact = nc;
      run.rocks = scene.total_rocks();
      const std::string what = "N_c " + std::to_string(nc) + ", " + std::to_string(n) + " rocks";
      core::ProgressFn progress;
      if (opt.progress) {
        progress = [&](int done, int) {
          const long total = std::min<long>(total_work, std::numeric_limits<int>::max());
          opt.progress(static_cast<int>(std::min(done_before + done, total)),
                       static_cast<int>(total), what);
        };
      }
      run.result = parallel::Simulate(scene, terrain, progress);
      done_before += run.rocks;
      run.samples = Samples(scene, run.result);
      run.values.assign(sources * kLevelCount, kNaN);
      run.counts.assign(sources, 0);
      std::vector<double> scratch;
      for (std::size_t src = 0; src < sources; ++src)
        SourceQuantiles(run.samples.values[src], {}, &scratch, &run.values[src * kLevelCount],
                        &run.counts[src]);
      // One bootstrap stream per rock count: the N_c series of a count
      // resample the same rocks (paired differences, equal errors for equal runs).
      const std::size_t count_index = runs.size() / ncs.size();
      run.replicates = BootstrapReplicates(run.samples, opt.bootstrap, base.options.seed,
                                           (std::uint64_t{1} << 48) + count_index);
      runs.push_back(std::move(run));
    }
  }
  return runs;
}

// A quantity the study measures: present at the reference with enough
// values and a non-zero value.
struct Quantity {
  std::size_t index;  // source * kLevelCount + level
  std::string name;
  double scale;
};

// The quantities of the reference run `ref`; out->quantities and notes on
// those left out.
std::vector<Quantity> MeasuredQuantities(const core::Scene& base, const RunData& ref,
                                         const ConvergenceOptions& opt, ConvergenceResult* out) {
  const std::size_t sources = base.partitions.size() + 1;
  std::vector<Quantity> quantities;
  for (std::size_t src = 0; src < sources; ++src) {
    const bool runout = src + 1 == sources;
    const std::string source = runout ? "runout" : base.partitions[src].id + ".height";
    const int count = ref.counts[src];
    if (count < opt.min_values) {
      out->notes.push_back(source + ": left out, only " + std::to_string(count) +
                           (runout ? " stopped rocks" : " crossings") +
                           " in the reference run (need " + std::to_string(opt.min_values) + ")");
      continue;
    }
    for (int l = 0; l < kLevelCount; ++l) {
      const std::size_t i = src * kLevelCount + l;
      const double v = ref.values[i];
      const std::string name = source + "." + kLevelNames[l];
      if (!(std::abs(v) > 1e-9)) {
        out->notes.push_back(name +
                             ": left out, zero at the reference (no scale for a relative error)");
        continue;
      }
      quantities.push_back({i, name, std::abs(v)});
      out->quantities.push_back(name);
    }
  }
  if (quantities.empty())
    out->notes.push_back(
        "no summary quantity to measure: no partition crossings or stopped rocks "
        "enough at the reference");
  out->notes.push_back(
      "runout quantities are distances along x from each rock's release point to where it "
      "stopped (stopped rocks only); heights are rock-centre heights above the ground at each "
      "partition");
  return quantities;
}

// The errors of quantity q in `run`, against the reference `ref`, the run
// of the finest N_c with the same rocks (`finest`) and the run of the same
// N_c with the most rocks (`most`).
QuantityError ErrorOf(const Quantity& q, const RunData& run, const RunData& finest,
                      const RunData& most, const RunData& ref, const ConvergenceOptions& opt) {
  QuantityError e;
  e.name = q.name;
  e.value = run.values[q.index];
  e.count = run.counts[q.index / kLevelCount];
  const double fine = finest.values[q.index];
  const double hw = HalfWidth(run.replicates[q.index], opt.confidence);
  std::vector<double> diff(run.replicates[q.index].size());
  for (std::size_t b = 0; b < diff.size(); ++b)
    diff[b] = run.replicates[q.index][b] - finest.replicates[q.index][b];
  const double diff_hw = HalfWidth(diff, opt.confidence);
  e.total_error = std::isnan(e.value) ? kInf : std::abs(e.value - ref.values[q.index]) / q.scale;
  e.discretisation_error =
      std::isnan(e.value) || std::isnan(fine) ? kInf : std::abs(e.value - fine) / q.scale;
  e.mc_error = e.count < opt.min_values || std::isnan(hw) ? kInf : hw / q.scale;
  e.discretisation_noise = &run == &finest                                   ? 0.0
                           : e.count < opt.min_values || std::isnan(diff_hw) ? kInf
                                                                             : diff_hw / q.scale;
  const double most_value = most.values[q.index];
  const double discretisation =
      std::isnan(most_value) ? kInf : std::abs(most_value - ref.values[q.index]) / q.scale;
  e.estimate = discretisation + e.mc_error;
  return e;
}

// The reducer: one row of the result from its run (see ErrorOf).
ConvergenceRow RowOf(const RunData& run, const RunData& finest, const RunData& most,
                     const RunData& ref, const std::vector<Quantity>& quantities,
                     const ConvergenceOptions& opt) {
  ConvergenceRow row;
  row.steps_per_contact = run.steps_per_contact;
  row.rocks = run.rocks;
  row.figures = run.result.figures;
  row.wall_seconds = run.result.wall_seconds;
  row.stopped = run.result.count(core::Outcome::kStopped);
  row.left = run.result.count(core::Outcome::kLeft);
  row.timeout = run.result.count(core::Outcome::kTimeout);
  for (const Quantity& q : quantities) {
    const QuantityError e = ErrorOf(q, run, finest, most, ref, opt);
    row.max_total_error = std::max(row.max_total_error, e.total_error);
    row.max_mc_error = std::max(row.max_mc_error, e.mc_error);
    row.max_discretisation_error = std::max(row.max_discretisation_error, e.discretisation_error);
    row.max_discretisation_noise = std::max(row.max_discretisation_noise, e.discretisation_noise);
    row.max_estimate = std::max(row.max_estimate, e.estimate);
    row.quantities.push_back(e);
  }
  if (quantities.empty()) row.max_estimate = kInf;
  row.meets_target = row.max_estimate <= opt.target;
  return row;
}

// out->recommended (the cheapest row within the target) and the sentence
// that says it, or why there is none.
void Recommend(const ConvergenceOptions& opt, ConvergenceResult* out) {
  for (std::size_t k = 0; k < out->rows.size(); ++k) {
    const ConvergenceRow& row = out->rows[k];
    if (row.meets_target &&
        (out->recommended < 0 ||
         row.wall_seconds < out->rows[static_cast<std::size_t>(out->recommended)].wall_seconds))
      out->recommended = static_cast<int>(k);
  }
  const ConvergenceRow& reference = out->rows[static_cast<std::size_t>(out->reference)];
  std::ostringstream sentence;
  if (out->recommended >= 0) {
    const ConvergenceRow& r = out->rows[static_cast<std::size_t>(out->recommended)];
    sentence << "N_c = " << r.steps_per_contact << " with " << r.rocks << " rocks: error estimate "
             << Percent(r.max_estimate) << " <= target " << Percent(opt.target) << " in "
             << Num(r.wall_seconds, "%.3g")
             << " s (the reference, N_c = " << reference.steps_per_contact << " with "
             << reference.rocks << " rocks, took " << Num(reference.wall_seconds, "%.3g") << " s)";
  } else {
    int best = -1;
    for (std::size_t k = 0; k < out->rows.size(); ++k)
      if (best < 0 ||
          out->rows[k].max_estimate < out->rows[static_cast<std::size_t>(best)].max_estimate)
        best = static_cast<int>(k);
    const ConvergenceRow& b = out->rows[static_cast<std::size_t>(best)];
    sentence << "none: no setting's error estimate is within the target " << Percent(opt.target);
    if (std::isfinite(b.max_estimate))
      sentence << " (smallest " << Percent(b.max_estimate) << " at N_c = " << b.steps_per_contact
               << " with " << b.rocks << " rocks)";
    // The reference's error is all Monte Carlo; it falls as 1 / sqrt(rocks).
    if (std::isfinite(reference.max_mc_error) && reference.max_mc_error > 0) {
      const double ratio = reference.max_mc_error / opt.target;
      sentence << "; the Monte Carlo error alone would reach the target at about "
               << Num(std::ceil(reference.rocks * ratio * ratio / 100.0) * 100.0, "%.0f")
               << " rocks (if it falls as 1/sqrt(rocks))";
    }
  }
  out->recommendation = sentence.str();
}

}  // namespace

ConvergenceResult RunConvergence(const core::Scene& site, const ConvergenceOptions& opt) {
  std::string error;
  if (!opt.IsValid(&error)) throw std::invalid_argument(error);
  const ConvergenceGrid grid = MakeGrid(opt);

  core::Scene base = site;
  if (opt.seed) base.options.seed = *opt.seed;
  base.options.threads = opt.threads;
  base.options.record = core::RecordOptions{};
  base.options.record.partitions = !base.partitions.empty();
  base.options.record.energy_check = false;  // the stability study's business
  const core::Terrain terrain = core::BuildTerrain(base);

  ConvergenceResult out;
  out.site = site.name;
  out.target = opt.target;
  out.bootstrap = opt.bootstrap;
  out.confidence = opt.confidence;
  out.seed = base.options.seed;
  out.threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();

  const std::vector<RunData> runs = RunConvergenceGrid(base, terrain, grid, opt);
  auto run_at = [&](std::size_t count_index, std::size_t nc_index) -> const RunData& {
    return runs[grid.index(count_index, nc_index)];
  };
  const std::size_t last_nc = grid.ncs.size() - 1, last_count = grid.counts.size() - 1;
  const RunData& ref = run_at(last_count, last_nc);
  const std::vector<Quantity> quantities = MeasuredQuantities(base, ref, opt, &out);

  // Rows in N_c order, then rock count.
  for (std::size_t ni = 0; ni < grid.ncs.size(); ++ni) {
    for (std::size_t ci = 0; ci < grid.counts.size(); ++ci) {
      const RunData& run = run_at(ci, ni);
      // The discretisation error of this N_c does not depend on the rock
      // count: the estimate takes it where it is best resolved, at the most rocks.
      if (&run == &ref) out.reference = static_cast<int>(out.rows.size());
      out.rows.push_back(
          RowOf(run, run_at(ci, last_nc), run_at(last_count, ni), ref, quantities, opt));
    }
  }
  Recommend(opt, &out);
  return out;
}

std::string ConvergenceReport(const ConvergenceResult& result) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line, "%6s %7s %9s %9s %7s %9s %9s %9s %9s %9s %9s  %s\n", "N_c",
                "rocks", "dt_min_s", "dt_max_s", "shrunk", "wall_s", "total", "discr", "d.noise",
                "mc", "estimate", "");
  out << line;
  for (std::size_t k = 0; k < result.rows.size(); ++k) {
    const ConvergenceRow& r = result.rows[k];
    std::string mark = static_cast<int>(k) == result.reference ? "reference" : "";
    if (static_cast<int>(k) == result.recommended)
      mark += mark.empty() ? "recommended" : ", recommended";
    std::snprintf(line, sizeof line, "%6d %7d %9.3g %9.3g %7d %9.3g %9s %9s %9s %9s %9s  %s\n",
                  r.steps_per_contact, r.rocks, r.figures.dt_min, r.figures.dt_max,
                  r.figures.dt_shrunk, r.wall_seconds, Percent(r.max_total_error).c_str(),
                  Percent(r.max_discretisation_error).c_str(),
                  Percent(r.max_discretisation_noise).c_str(), Percent(r.max_mc_error).c_str(),
                  Percent(r.max_estimate).c_str(), mark.c_str());
    out << line;
  }
  for (const auto& note : result.notes) out << "note: " << note << '\n';
  out << "recommendation: " << result.recommendation << '\n';
  return out.str();
}

}  // namespace rockcal::calibrate
