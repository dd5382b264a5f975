#include "runout.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "../compare.h"
#include "../reader.h"
#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/file_keys.h"

namespace rockcal::observations {

std::vector<double> Runout::MassClassBounds() const {
  std::vector<double> bounds;
  if (mass_classes < 2 || masses.empty()) return bounds;
  std::vector<double> sorted = masses;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 1; k < mass_classes; ++k)
    bounds.push_back(core::Quantile(sorted, static_cast<double>(k) / mass_classes));
  return bounds;
}

namespace kinds {
namespace {

using sites::FormatNumber;
using sites::JsonNode;
using sites::Units;

// ---------------------------------------------------------------------------
// Reader

// The unit vector from `from` towards the mean of `stop_points`: the runout
// direction when the file gives none. Throws, naming `node`, when the mean
// stop point is the origin or the direction has no finite normalisation.
Eigen::Vector2d TowardsMeanStop(const JsonNode& node,
                                const std::vector<Eigen::Vector2d>& stop_points,
                                const Eigen::Vector2d& from) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : stop_points) mean += p;
  mean /= static_cast<double>(stop_points.size());
  const Eigen::Vector2d d = mean - from;
  if (!(d.norm() > 1e-9 * (1.0 + from.norm()))) {
    throw InputError(node.where(), "cannot choose a runout direction: the mean stop point " +
                                       FormatPoint(mean) + " m coincides with the origin " +
                                       FormatPoint(from) + " m (expected 'direction' [dx, dy])");
  }
  const Eigen::Vector2d direction = d / d.norm();
  if (!direction.allFinite() || !(std::abs(direction.norm() - 1.0) < 1e-9)) {
    throw InputError(node.where(), "cannot choose a runout direction: the direction from " +
                                       FormatPoint(from) + " to the mean stop point " +
                                       FormatPoint(mean) +
                                       " m has no finite normalisation (expected 'direction')");
  }
  return direction;
}

Runout ReadRunoutPositions(const Reader& reader, const JsonNode& node,
                           std::vector<std::string>* notes) {
  node.Keys(ObservationsKeysAt("$.runout"));
  const std::string form =
      OneOf(node, {"stop_points", "stop_points_file", "distances", "distances_file"});
  std::optional<Eigen::Vector2d> from, direction;
  if (const auto f = node.Find("from")) {
    const std::vector<double> v = sites::CoordinatesToSI(*f, 2, reader.units());
    from = Eigen::Vector2d(v[0], v[1]);
  }
  if (const auto d = node.Find("direction")) {
    const std::vector<double> v = d->Numbers(2);
    const Eigen::Vector2d dir(v[0], v[1]);
    const Eigen::Vector2d unit = dir / dir.norm();
    if (!(dir.norm() > 0) || !unit.allFinite() || !(std::abs(unit.norm() - 1.0) < 1e-9))
      d->Fail("expected a non-zero direction [dx, dy] whose normalisation is finite");
    direction = unit;
  }

  Runout runout;
  if (form == "distances" || form == "distances_file") {
    if (!from) {
      throw InputError(
          node.where(),
          "missing required key 'from' (the point [x, y] distances are measured from)");
    }
    if (!direction) {
      throw InputError(node.where(),
                       "missing required key 'direction' ([dx, dy] along which distances are "
                       "measured)");
    }
    runout.from = *from;
    runout.direction = *direction;
    if (form == "distances") {
      for (const JsonNode& d : node.Get("distances").Array(1))
        runout.distances.push_back(reader.Length(d.Number()));
    } else {
      const CsvTable table = reader.ReadCsv(node.Get("distances_file"), {"distance"});
      for (const CsvRow& row : table.rows)
        runout.distances.push_back(reader.Length(CsvNumber(table, row, 0, "distance")));
    }
    notes->push_back("runout: " + std::to_string(runout.distances.size()) + " distances from " +
                     FormatPoint(runout.from) + " m along " + FormatPoint(runout.direction));
    return runout;
  }

  if (form == "stop_points") {
    for (const JsonNode& p : node.Get("stop_points").Array(1)) {
      const std::vector<double> v = sites::CoordinatesToSI(p, 2, reader.units());
      runout.stop_points.emplace_back(v[0], v[1]);
    }
  } else {
    const CsvTable table = reader.ReadCsv(node.Get("stop_points_file"), {"x", "y"});
    for (const CsvRow& row : table.rows) {
      runout.stop_points.emplace_back(reader.Length(CsvNumber(table, row, 0, "x")),
                                      reader.Length(CsvNumber(table, row, 1, "y")));
    }
  }

  std::string from_note = "as given";
  if (from) {
    runout.from = *from;
  } else {
    if (reader.scene().groups.empty()) {
      throw InputError(node.where(),
                       "missing required key 'from': the site has no rock group whose release "
                       "could be the origin of runout distances");
    }
    runout.from = ReleaseCentroid(reader.scene().groups[0].release);
    from_note = "the release of the first rock group";
  }
  std::string direction_note = "as given";
  if (direction) {
    runout.direction = *direction;
  } else {
    runout.direction = TowardsMeanStop(node, runout.stop_points, runout.from);
    direction_note = "towards the mean stop point";
  }
  for (const Eigen::Vector2d& p : runout.stop_points) {
    runout.distances.push_back(runout.Distance(p));
    runout.lateral.push_back(runout.Lateral(p));
  }
  // In the observations file's units (docs/reference/commands.md, validate).
  const double to_file = 1.0 / sites::LengthToSI(1.0, reader.units());
  notes->push_back("runout: " + std::to_string(runout.stop_points.size()) +
                   " stop points; distances from " + FormatPoint(runout.from * to_file) + " " +
                   sites::LengthUnit(reader.units()) + " (" + from_note +
                   ") along " + FormatPoint(runout.direction) + " (" + direction_note +
                   "), lateral offsets positive to the left");
  return runout;
}

Runout ReadRunout(const Reader& reader, const JsonNode& node, std::vector<std::string>* notes) {
  Runout runout = ReadRunoutPositions(reader, node, notes);
  const int n = static_cast<int>(runout.distances.size());
  runout.observed_rocks = n;
  if (const auto r = node.Find("observed_rocks")) {
    runout.observed_rocks = static_cast<int>(r->Integer(n, 100'000'000));
  }
  if (const auto f = node.Find("stopped_fraction")) {
    runout.stopped_fraction = f->Number(0.0, 1.0);
    if (!(runout.stopped_fraction > 0))
      f->Fail("expected a fraction in (0, 1]: some rocks stopped");
  }
  if (const auto m = node.Find("masses")) {
    const std::vector<JsonNode> items = m->Array(1);
    if (static_cast<int>(items.size()) != n) {
      m->Fail("holds " + std::to_string(items.size()) + " masses; expected one per stop (" +
              std::to_string(n) + ")");
    }
    const double unit = reader.units() == Units::kSI ? 1.0 : 0.45359237;  // kg or lb
    for (const JsonNode& item : items) {
      const double mass = item.Number() * unit;
      if (!(mass > 0 && mass <= 1e8)) item.Fail("expected a block mass > 0 and at most 1e8 kg");
      runout.masses.push_back(mass);
    }
    runout.mass_classes = std::min(4, n / 4);
    if (runout.mass_classes < 2) runout.mass_classes = 0;
  }
  if (const auto c = node.Find("mass_classes")) {
    if (runout.masses.empty()) c->Fail("goes with 'masses' (the mass of each stopped block)");
    runout.mass_classes = static_cast<int>(c->Integer(0, std::max(0, n / 2)));
    if (runout.mass_classes == 1) c->Fail("expected 0 (off) or at least 2 classes");
  }
  if (runout.mass_classes >= 2) {
    std::string bounds;
    for (double b : runout.MassClassBounds())
      bounds += (bounds.empty() ? "" : ", ") + sites::MassText(b, reader.units());
    notes->push_back("runout: also compared in " + std::to_string(runout.mass_classes) +
                     " mass classes split at " + bounds);
  }
  return runout;
}

void Read(const Reader& reader, const JsonNode& root, Observations* obs) {
  CheckOneRunoutForm(root);
  if (const auto runout = root.Find("runout"))
    obs->runout = ReadRunout(reader, *runout, &obs->notes);
}

// The runout error, which the tracked runs (runs.cc) take too.
void ReadError(const Reader& reader, const JsonNode& error, Observations* obs) {
  if (const auto r = error.Find("runout")) {
    obs->error.runout =
        sites::NumberInRange(*r, reader.Length(r->Positive()), 0.0, core::kMaxObservationError,
                             "runout error", sites::Quantity::kLength, reader.units());
  }
}

std::string MissingError(const Observations& obs, const JsonNode* error) {
  if (!obs.runout || (error != nullptr && error->Has("runout"))) return "";
  return "missing required key 'runout' (the one-sigma error of stop positions, in the file's "
         "units; needed by 'runout')";
}

// ---------------------------------------------------------------------------
// Misfit

// The runout: where rocks stopped against the observed stops, pooled and per
// mass class, and the share of rocks that stopped. A rock that left the
// terrain or was still moving at the time limit is right-censored: it
// travelled at least to where it was last seen, so it enters the distances
// at D, at or beyond every stopped, observed and last-seen distance (the
// upper tail), never as a missing value, when every observed rock stopped.
// Losing rocks thus raises the upper quantiles and lowers the stopped share:
// it never lowers the misfit. When some observed rocks did not stop either
// (stopped_fraction < 1), the observed distances are those of the rocks that
// stopped, and the simulated ones are compared in kind: the stopped rocks'
// (the runout given stopping), with the share compared on its own.
void CompareRunout(const Runout& runout, double error, const core::SimulationResult& result,
                   const Comparer& compare) {
  struct Rock {
    double mass, distance;
  };
  std::vector<Rock> rocks;
  std::vector<double> lateral;
  double farthest = *std::max_element(runout.distances.begin(), runout.distances.end());
  int stopped = 0;
  for (const core::RockRecord& rock : result.rocks) {
    if (rock.outcome != core::Outcome::kStopped) continue;
    const Eigen::Vector2d p = rock.stop.head<2>();
    rocks.push_back({rock.mass, runout.Distance(p)});
    lateral.push_back(runout.Lateral(p));
    farthest = std::max(farthest, rocks.back().distance);
    ++stopped;
  }
  for (const core::RockRecord& rock : result.rocks)
    if (rock.outcome != core::Outcome::kStopped)
      farthest = std::max(farthest, runout.Distance(rock.stop.head<2>()));
  const bool all_stopped = runout.stopped_fraction >= 1.0;
  for (const core::RockRecord& rock : result.rocks)
    if (all_stopped && rock.outcome != core::Outcome::kStopped)
      rocks.push_back({rock.mass, farthest});
  std::vector<double> distance;
  for (const Rock& r : rocks) distance.push_back(r.distance);
  compare.Distributions(ResidualId::Of(ObservationKind::kRunoutDistance), std::move(distance),
                        runout.distances, error);
  if (runout.has_lateral())
    compare.Distributions(ResidualId::Of(ObservationKind::kRunoutLateral), std::move(lateral),
                          runout.lateral, error);
  const int observed_rocks =
      runout.observed_rocks > 0 ? runout.observed_rocks : static_cast<int>(runout.distances.size());
  compare.Share(ResidualId::Of(ObservationKind::kRunoutStopped), stopped,
                static_cast<int>(result.rocks.size()), runout.stopped_fraction, observed_rocks);
  if (runout.mass_classes < 2) return;
  const std::vector<double> bounds = runout.MassClassBounds();
  auto class_of = [&](double mass) {
    return static_cast<int>(std::upper_bound(bounds.begin(), bounds.end(), mass) - bounds.begin());
  };
  for (int c = 0; c < runout.mass_classes; ++c) {
    std::vector<double> sim, obs;
    for (const Rock& r : rocks)
      if (class_of(r.mass) == c) sim.push_back(r.distance);
    for (std::size_t k = 0; k < runout.masses.size(); ++k)
      if (class_of(runout.masses[k]) == c) obs.push_back(runout.distances[k]);
    if (obs.empty()) continue;  // ties at a bound can empty a class
    const std::string range =
        c == 0 ? "< " + FormatNumber(std::round(bounds[0]), "%.6g")
        : c + 1 == runout.mass_classes
            ? ">= " + FormatNumber(std::round(bounds[static_cast<std::size_t>(c - 1)]), "%.6g")
            : FormatNumber(std::round(bounds[static_cast<std::size_t>(c - 1)]), "%.6g") + "-" +
                  FormatNumber(std::round(bounds[static_cast<std::size_t>(c)]), "%.6g");
    compare.Quantiles(ResidualId::Of(ObservationKind::kRunoutMassClass, c, range), std::move(sim),
                      std::move(obs), error, {0.5}, false);
  }
}

void AddResiduals(const Observations& obs, const MisfitTerms& terms) {
  if (obs.runout && !obs.runout->has_runs())
    CompareRunout(*obs.runout, obs.error.runout, terms.result, terms.compare);
}

std::string Text(const ResidualId& id) {
  switch (id.kind) {
    case ObservationKind::kRunoutDistance:
      return "runout distance";
    case ObservationKind::kRunoutMassClass:
      return "runout distance, mass " + id.name + " kg";
    case ObservationKind::kRunoutLateral:
      return "runout lateral";
    case ObservationKind::kRunoutStopped:
      return "runout stopped";
    default:
      return "";
  }
}

std::optional<ResidualId> ParseText(const std::string& text) {
  const std::string mass = "runout distance, mass ", kg = " kg";
  if (text == "runout distance") return ResidualId::Of(ObservationKind::kRunoutDistance);
  if (text == "runout lateral") return ResidualId::Of(ObservationKind::kRunoutLateral);
  if (text == "runout stopped") return ResidualId::Of(ObservationKind::kRunoutStopped);
  if (const auto rest = After(text, mass);
      rest && rest->size() > kg.size() &&
      rest->compare(rest->size() - kg.size(), kg.size(), kg) == 0)
    return ResidualId::Of(ObservationKind::kRunoutMassClass, -1,
                          rest->substr(0, rest->size() - kg.size()));
  return std::nullopt;
}

// ---------------------------------------------------------------------------
// Folds: the runout values, pooled or tracked runs alike (both fill
// Observations::runout), dealt after the other kinds' in table order.

void DealFolds(const Observations& obs, int k, std::mt19937_64* rng,
               std::vector<observations::Fold>* folds) {
  if (!obs.runout) return;
  const std::size_t n = obs.runout->distances.size();
  if (n < static_cast<std::size_t>(k))
    throw InputError(obs.path, "runout: " + std::to_string(n) + " stop points, fewer than the " +
                                   std::to_string(k) + " folds of --holdout");
  const auto dealt = Deal(n, k, rng);
  for (int f = 0; f < k; ++f)
    (*folds)[static_cast<std::size_t>(f)].runout = dealt[static_cast<std::size_t>(f)];
}

// A runout left without values is dropped.
void KeepFold(const Observations& observations, const observations::Fold& fold, bool held_out,
              Observations* out) {
  if (!observations.runout) return;
  const Runout& r = *observations.runout;
  Runout kept = r;
  kept.distances.clear();
  kept.stop_points.clear();
  kept.lateral.clear();
  kept.masses.clear();
  kept.run_ids.clear();
  kept.run_groups.clear();
  kept.run_origins.clear();
  for (std::size_t i = 0; i < r.distances.size(); ++i) {
    if (!Keep(fold.runout, i, held_out)) continue;
    kept.distances.push_back(r.distances[i]);
    if (i < r.stop_points.size()) kept.stop_points.push_back(r.stop_points[i]);
    if (i < r.lateral.size()) kept.lateral.push_back(r.lateral[i]);
    if (i < r.masses.size()) kept.masses.push_back(r.masses[i]);
    if (i < r.run_ids.size()) {
      kept.run_ids.push_back(r.run_ids[i]);
      kept.run_groups.push_back(r.run_groups[i]);
      kept.run_origins.push_back(r.run_origins[i]);
    }
  }
  // The observed share stands for the kept rocks as for all of them; the
  // mass classes keep at least four blocks each (none below two classes).
  const int n = static_cast<int>(kept.distances.size());
  const int all = static_cast<int>(r.distances.size());
  kept.observed_rocks =
      r.observed_rocks > all ? static_cast<int>(std::lround(1.0 * r.observed_rocks * n / all)) : n;
  kept.mass_classes = std::min(r.mass_classes, n / 4);
  if (kept.mass_classes < 2) kept.mass_classes = 0;
  if (kept.distances.empty())
    out->runout.reset();
  else
    out->runout = std::move(kept);
}

}  // namespace

void CheckOneRunoutForm(const JsonNode& root) {
  const int forms = root.Has("runout") + root.Has("runs") + root.Has("runs_file");
  if (forms > 1)
    throw InputError(root.where(),
                     "expected at most one of 'runout' (stop points pooled about "
                     "one origin), 'runs' and 'runs_file' (tracked runs)");
}

Kind RunoutKind() {
  Kind kind;
  kind.name = "runout";
  kind.root_keys = {"runout"};
  kind.objects = {
      {"$.runout",
       {"stop_points", "stop_points_file", "distances", "distances_file", "from", "direction",
        "masses", "mass_classes", "stopped_fraction", "observed_rocks"}},
  };
  kind.error_keys = {"runout"};
  kind.residual_kinds = {ObservationKind::kRunoutDistance, ObservationKind::kRunoutMassClass,
                         ObservationKind::kRunoutLateral, ObservationKind::kRunoutStopped};
  kind.observation_text = Text;
  kind.parse_text = ParseText;
  kind.read = Read;
  kind.read_error = ReadError;
  kind.missing_error = MissingError;
  kind.misfit = AddResiduals;
  kind.fold = DealFolds;
  kind.subset = KeepFold;
  return kind;
}

}  // namespace kinds
}  // namespace rockcal::observations
