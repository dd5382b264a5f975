#include "runs.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

#include "../compare.h"
#include "../reader.h"
#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/file_keys.h"
#include "rockcal/sites/geometry.h"
#include "runout.h"

namespace rockcal::observations {
namespace kinds {
namespace {

using sites::FormatNumber;
using sites::JsonNode;

// ---------------------------------------------------------------------------
// Reader: the runs fill Observations::runout (Runout::has_runs), so they
// take the runout's measurement error and folds (runout.cc).

// Adds run `id` tied to group `group` (its id) stopped at `stop` (SI) to
// `runout`; `where` names the JSON path or the CSV file and line of the
// run for the errors (no such group, a stop off the terrain, a repeated id).
void AddRun(const Reader& reader, const std::string& where, const std::string& id,
            const std::string& group, const Eigen::Vector2d& stop, Runout* runout) {
  if (id.empty()) throw InputError(where, "expected a non-empty run id");
  for (const std::string& other : runout->run_ids)
    if (other == id)
      throw InputError(where, "run id '" + id + "' is given twice; expected each run once");
  int index = -1;
  for (std::size_t g = 0; g < reader.scene().groups.size(); ++g)
    if (reader.scene().groups[g].id == group) index = static_cast<int>(g);
  if (index < 0) {
    std::string ids;
    int shown = 0;
    for (const core::RockGroup& g : reader.scene().groups)
      if (!g.id.empty() && shown++ < 8) ids += (ids.empty() ? "" : ", ") + g.id;
    throw InputError(where, "run '" + id + "': no rock group of the site has the id '" + group +
                                "' (expected the 'id' of the rock group released as this run " +
                                "was; " +
                                (ids.empty() ? "the site's groups have no ids"
                                             : "ids: " + ids + (shown > 8 ? ", ..." : "")) +
                                ")");
  }
  if (!sites::OnTerrain(reader.scene().grid, stop.x(), stop.y()))
    throw InputError(where, "run '" + id + "': stop point " + FormatPoint(stop) +
                                " m is off the terrain (outside the grid or over a hole); "
                                "expected a stop point on the terrain");
  const Eigen::Vector2d origin =
      ReleaseCentroid(reader.scene().groups[static_cast<std::size_t>(index)].release);
  runout->run_ids.push_back(id);
  runout->run_groups.push_back(index);
  runout->run_origins.push_back(origin);
  runout->stop_points.push_back(stop);
  runout->distances.push_back((stop - origin).norm());
}

void NoteRuns(const Runout& runout, std::vector<std::string>* notes) {
  const std::vector<double>& d = runout.distances;
  notes->push_back("runout: " + std::to_string(d.size()) +
                   " tracked runs, each measured from its own rock group's release (runout " +
                   FormatNumber(*std::min_element(d.begin(), d.end()), "%.4g") + "-" +
                   FormatNumber(*std::max_element(d.begin(), d.end()), "%.4g") +
                   " m) and compared with that group's rocks only");
}

// The "runs" array.
Runout ReadRuns(const Reader& reader, const JsonNode& node, std::vector<std::string>* notes) {
  Runout runout;
  for (const JsonNode& run : node.Array(1)) {
    run.Keys(ObservationsKeysAt("$.runs[]"));
    const std::string id = run.Get("id").String();
    const std::string group = run.Has("group") ? run.Get("group").String() : id;
    const std::vector<double> v = sites::CoordinatesToSI(run.Get("stop"), 2, reader.units());
    AddRun(reader, run.where(), id, group, Eigen::Vector2d(v[0], v[1]), &runout);
  }
  NoteRuns(runout, notes);
  return runout;
}

// The "runs_file" CSV.
Runout ReadRunsFile(const Reader& reader, const JsonNode& ref, std::vector<std::string>* notes) {
  // A table with a header naming its columns: the run's id ("id" or
  // "run"), its rock group ("group", default the run's id) and its stop
  // point ("stop_x", "stop_y", or with the suffix "_m" or "_ft"); other
  // columns (a tracked campaign's release state, masses...) are ignored.
  const CsvTable table{reader.CsvFile(ref), {}};
  sites::LineReader in(table.file);
  CsvRow row;
  std::string text;
  std::vector<std::string> header;
  int id_col = -1, group_col = -1, x_col = -1, y_col = -1;
  Runout runout;
  while (NextCsvRow(&in, &row, &text)) {
    if (header.empty()) {
      header = row.fields;
      auto find = [&](std::initializer_list<const char*> names) {
        for (std::size_t c = 0; c < header.size(); ++c)
          for (const char* n : names)
            if (header[c] == n) return static_cast<int>(c);
        return -1;
      };
      id_col = find({"id", "run"});
      group_col = find({"group"});
      x_col = find({"stop_x", "stop_x_m", "stop_x_ft"});
      y_col = find({"stop_y", "stop_y_m", "stop_y_ft"});
      if (id_col < 0 || x_col < 0 || y_col < 0)
        CsvFail(table, row,
                "expected a header naming the columns 'id' (or 'run'), 'stop_x' and 'stop_y' "
                "(optionally 'group'; found " +
                    sites::Excerpt(text) + ")");
      continue;
    }
    if (row.fields.size() != header.size())
      CsvFail(table, row,
              "expected " + std::to_string(header.size()) +
                  " values per row (as the header), "
                  "found " +
                  std::to_string(row.fields.size()) + " in " + sites::Excerpt(text));
    const std::size_t xi = static_cast<std::size_t>(x_col), yi = static_cast<std::size_t>(y_col);
    const Eigen::Vector2d stop(reader.Length(CsvNumber(table, row, xi, "stop_x")),
                               reader.Length(CsvNumber(table, row, yi, "stop_y")));
    const std::string id = row.fields[static_cast<std::size_t>(id_col)];
    const std::string group = group_col >= 0 ? row.fields[static_cast<std::size_t>(group_col)] : id;
    AddRun(reader, table.file + ":" + std::to_string(row.line), id, group, stop, &runout);
  }
  if (runout.distances.empty())
    throw InputError(
        table.file,
        "no data rows (expected a header and one row per run; referenced at " + ref.where() + ")");
  NoteRuns(runout, notes);
  return runout;
}

void Read(const Reader& reader, const JsonNode& root, Observations* obs) {
  CheckOneRunoutForm(root);
  if (const auto runs = root.Find("runs")) obs->runout = ReadRuns(reader, *runs, &obs->notes);
  if (const auto runs = root.Find("runs_file"))
    obs->runout = ReadRunsFile(reader, *runs, &obs->notes);
  if (obs->runout && obs->runout->has_runs())
    obs->runout->observed_rocks = static_cast<int>(obs->runout->distances.size());
}

// ---------------------------------------------------------------------------
// Misfit

// Per-run observations: run i's runout (from its own release) against the
// runouts of its group's rocks from the same release; a rock that did not
// stop is censored as above (at or beyond every distance) when every
// observed rock stopped, and left out when not (the runs given are those
// that stopped; the stopped share compares the rest). Two comparisons,
// as options.run_terms says:
// - pooled: the runs' runouts pooled into one distribution compared by
//   quantiles as above (each run adds its group's rocks, so the pooled
//   simulated sample is the mixture of the runs' predictions);
// - per run: one residual per run, (median_i - observed_i) / sigma_i with
//   sigma_i^2 = error^2 + s_i^2 (1 + pi / (2 n_i)): the observed stop is one
//   draw of the run's predictive distribution (spread s_i), the median of n_i
//   rocks has the Monte Carlo variance pi s_i^2 / (2 n_i). The spread s_i is
//   the run's own rocks' standard deviation (n_i - 1 degrees of freedom)
//   shrunk toward the spread pooled over all runs' rocks about their group
//   medians (1.4826 x their median absolute deviation, groups of 2 rocks or
//   more; options.run_spread_prior degrees of freedom):
//   s_i^2 = (nu0 s_pool^2 + (n_i - 1) s_own^2) / (nu0 + n_i - 1).
//   A run of one rock takes the pooled spread; a run split between rocks
//   that stuck and rocks that ran has a large own spread, so a moderate
//   residual; a run with no simulated rock adds a residual 0.
// The stopped share is compared in both cases. Each run's fit goes to
// misfit->runs.
void CompareRuns(const Runout& runout, double error, const core::SimulationResult& result,
                 const MisfitOptions& options, const Comparer& compare, Misfit* misfit) {
  std::vector<std::vector<const core::RockRecord*>> by_group;
  for (const core::RockRecord& rock : result.rocks) {
    const std::size_t g = static_cast<std::size_t>(rock.group);
    if (by_group.size() <= g) by_group.resize(g + 1);
    by_group[g].push_back(&rock);
  }
  double farthest = *std::max_element(runout.distances.begin(), runout.distances.end());
  for (std::size_t i = 0; i < runout.run_groups.size(); ++i) {
    const std::size_t g = static_cast<std::size_t>(runout.run_groups[i]);
    if (g >= by_group.size()) continue;
    for (const core::RockRecord* rock : by_group[g])
      farthest = std::max(farthest, (rock->stop.head<2>() - runout.run_origins[i]).norm());
  }
  // As for the pooled runout (runout.cc): when some observed rocks did not
  // stop either, the runs given are those that stopped, and the simulated
  // rocks are compared in kind (those that stopped), the share on its own.
  const bool all_stopped = runout.stopped_fraction >= 1.0;
  std::vector<double> pooled;
  std::vector<std::vector<double>> samples;  // each run's runouts, ascending
  int stopped = 0, released = 0;
  for (std::size_t i = 0; i < runout.run_groups.size(); ++i) {
    const std::size_t g = static_cast<std::size_t>(runout.run_groups[i]);
    RunFit fit;
    fit.id = runout.run_ids[i];
    fit.group = runout.run_groups[i];
    fit.observed = runout.distances[i];
    std::vector<double> run;
    if (g < by_group.size()) {
      for (const core::RockRecord* rock : by_group[g]) {
        const double d = (rock->stop.head<2>() - runout.run_origins[i]).norm();
        const bool stop = rock->outcome == core::Outcome::kStopped;
        if (stop || all_stopped) run.push_back(stop ? d : farthest);
        fit.stopped += stop ? 1 : 0;
        const double moved = (rock->stop.head<2>() - rock->start.head<2>()).norm();
        if (RunFit::StuckNearRelease(moved, fit.observed)) ++fit.stuck;
      }
      fit.rocks = static_cast<int>(by_group[g].size());
    }
    if (!run.empty()) {
      std::sort(run.begin(), run.end());
      fit.simulated = core::Quantile(run, 0.5);
    }
    stopped += fit.stopped;
    released += fit.rocks;
    pooled.insert(pooled.end(), run.begin(), run.end());
    samples.push_back(std::move(run));
    misfit->runs.push_back(fit);
  }
  if (options.run_terms != RunTerms::kPerRun)
    compare.Distributions(ResidualId::Of(ObservationKind::kRunoutDistance), std::move(pooled),
                          runout.distances, error);
  const int observed_rocks =
      runout.observed_rocks > 0 ? runout.observed_rocks : static_cast<int>(runout.distances.size());
  compare.Share(ResidualId::Of(ObservationKind::kRunoutStopped), stopped, released,
                runout.stopped_fraction, observed_rocks);
  if (options.run_terms == RunTerms::kPooled) return;

  std::vector<double> deviations;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].size() < 2) continue;
    for (const double d : samples[i]) deviations.push_back(std::abs(d - misfit->runs[i].simulated));
  }
  double pool = 0.0;
  if (!deviations.empty()) {
    std::sort(deviations.begin(), deviations.end());
    pool = 1.4826 * core::Quantile(deviations, 0.5);
  }
  using core::kPi;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    RunFit& fit = misfit->runs[i];
    const std::vector<double>& run = samples[i];
    const double n = static_cast<double>(run.size());
    double own2 = 0.0;
    if (run.size() >= 2) {
      double mean = 0.0;
      for (const double d : run) mean += d;
      mean /= n;
      for (const double d : run) own2 += (d - mean) * (d - mean);
      own2 /= n - 1.0;
    }
    const double dof = options.run_spread_prior + std::max(n - 1.0, 0.0);
    const double spread2 =
        dof > 0.0 ? (options.run_spread_prior * pool * pool + std::max(n - 1.0, 0.0) * own2) / dof
                  : 0.0;
    fit.spread = std::sqrt(spread2);
    const double fixed = std::max(error, compare.SigmaFloor(error));
    fit.sigma = run.empty()
                    ? fixed
                    : std::max(std::sqrt(error * error + spread2 * (1.0 + kPi / (2.0 * n))), fixed);
    const double value = run.empty() ? 0.0 : (fit.simulated - fit.observed) / fit.sigma;
    compare.Residual(ResidualId::Of(ObservationKind::kRun, static_cast<int>(i), fit.id),
                     Statistic::kRunout, fit.simulated, fit.observed, fit.sigma, value, fixed);
  }
}

void AddResiduals(const Observations& obs, const MisfitTerms& terms) {
  if (obs.runout && obs.runout->has_runs())
    CompareRuns(*obs.runout, obs.error.runout, terms.result, terms.options, terms.compare,
                terms.misfit);
}

std::string Text(const ResidualId& id) { return "run " + id.name; }

std::optional<ResidualId> ParseText(const std::string& text) {
  if (const auto id = After(text, "run ")) return ResidualId::Of(ObservationKind::kRun, -1, *id);
  return std::nullopt;
}

}  // namespace

Kind RunsKind() {
  Kind kind;
  kind.name = "runs";
  kind.root_keys = {"runs", "runs_file"};
  kind.objects = {{"$.runs[]", {"id", "group", "stop"}}};
  kind.residual_kinds = {ObservationKind::kRun};
  kind.observation_text = Text;
  kind.parse_text = ParseText;
  kind.read = Read;
  kind.misfit = AddResiduals;
  return kind;
}

}  // namespace kinds

namespace {

using sites::FormatNumber;

bool SameBlocks(const std::vector<core::Block>& a, const std::vector<core::Block>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].shape != b[k].shape || a[k].sides != b[k].sides || a[k].mass != b[k].mass ||
        a[k].scanned != b[k].scanned)
      return false;
  return true;
}

// Whether two rock groups release the same rocks (wherever they release them).
bool SameRocks(const core::RockGroup& a, const core::RockGroup& b) {
  return a.shape == b.shape && a.size_min == b.size_min && a.size_max == b.size_max &&
         a.unit_weight == b.unit_weight && a.box == b.box && a.scanned == b.scanned &&
         SameBlocks(a.inventory, b.inventory);
}

}  // namespace

std::vector<std::string> DuplicateRunWarnings(const Observations& observations) {
  std::vector<std::string> out;
  if (!observations.runout || !observations.runout->has_runs()) return out;
  const Runout& r = *observations.runout;
  constexpr double kSame = 1e-3;  // m
  for (std::size_t i = 0; i < r.run_ids.size(); ++i)
    for (std::size_t j = i + 1; j < r.run_ids.size(); ++j)
      if ((r.run_origins[i] - r.run_origins[j]).norm() <= kSame &&
          (r.stop_points[i] - r.stop_points[j]).norm() <= kSame)
        out.push_back("runs '" + r.run_ids[i] + "' and '" + r.run_ids[j] +
                      "' have the same release point and the same stop point, " +
                      FormatPoint(r.stop_points[i]) +
                      " m: one run written twice counts twice in the misfit; remove the copy "
                      "if it is one");
  return out;
}

std::string RepeatScatter::Sentence() const {
  return "repeated runs: " + std::to_string(runs) + " runs in " + std::to_string(sets) +
         " sets (the same rocks released within " + FormatNumber(kRepeatRadius, "%g") +
         " m of one another); a run's runout differs from its set's median by " +
         FormatNumber(own_median_error_m, "%.3g") + " m on average, from the median of the " +
         "set's other runs by " + FormatNumber(others_median_error_m, "%.3g") +
         " m: a mean per-run error near these is the campaign's own repeatability";
}

std::optional<RepeatScatter> RunRepeatScatter(const Observations& observations,
                                              const core::Scene& scene) {
  if (!observations.runout || !observations.runout->has_runs()) return std::nullopt;
  const Runout& r = *observations.runout;
  const std::size_t n = r.run_ids.size();
  std::vector<bool> placed(n, false);
  RepeatScatter out;
  double own = 0.0, others = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (placed[i]) continue;
    const core::RockGroup& first = scene.groups[static_cast<std::size_t>(r.run_groups[i])];
    std::vector<std::size_t> set;
    for (std::size_t j = i; j < n; ++j)
      if (!placed[j] &&
          (r.run_origins[j] - r.run_origins[i]).norm() <= RepeatScatter::kRepeatRadius &&
          SameRocks(first, scene.groups[static_cast<std::size_t>(r.run_groups[j])])) {
        placed[j] = true;
        set.push_back(j);
      }
    if (set.size() < 3) continue;
    std::vector<double> runouts;
    for (const std::size_t j : set) runouts.push_back(r.distances[j]);
    const double median = core::Median(runouts);
    for (std::size_t k = 0; k < set.size(); ++k) {
      std::vector<double> rest = runouts;
      rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(k));
      own += std::abs(runouts[k] - median);
      others += std::abs(runouts[k] - core::Median(rest));
    }
    ++out.sets;
    out.runs += static_cast<int>(set.size());
  }
  if (out.sets == 0) return std::nullopt;
  out.own_median_error_m = own / out.runs;
  out.others_median_error_m = others / out.runs;
  return out;
}

}  // namespace rockcal::observations
