#include "impacts.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <utility>

#include "../compare.h"
#include "../reader.h"
#include "rockcal/core/error.h"
#include "rockcal/core/impact_replay.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/file_keys.h"
#include "rockcal/sites/geometry.h"

namespace rockcal::observations::kinds {
namespace {

using sites::FormatNumber;
using sites::JsonNode;

using core::kPi;
constexpr double kMad = 1.4826;  // a normal sample's sigma per median absolute deviation
// Below this many impacts the pooled ratios are not compared (their
// quantiles would rest on too few values).
constexpr std::size_t kMinPooled = 5;

// ---------------------------------------------------------------------------
// Reader

std::string Vec(const Eigen::Vector3d& v) {
  return "(" + FormatNumber(v.x(), "%.4g") + ", " + FormatNumber(v.y(), "%.4g") + ", " +
         FormatNumber(v.z(), "%.4g") + ")";
}

// The upward unit normal of the grid's triangulated surface at (x, y), by
// central differences over one spacing (one-sided at an edge), as
// core::GroundNormal takes it from the terrain.
Eigen::Vector3d GridNormal(const core::HeightGrid& grid, double x, double y, double z) {
  const double h = grid.spacing;
  auto slope = [&](double dx, double dy) {
    const auto p = sites::ElevationAt(grid, x + dx, y + dy);
    const auto m = sites::ElevationAt(grid, x - dx, y - dy);
    if (p && m) return (*p - *m) / (2 * h);
    if (p) return (*p - z) / h;
    if (m) return (z - *m) / h;
    return 0.0;
  };
  return Eigen::Vector3d(-slope(h, 0), -slope(0, h), 1.0).normalized();
}

// Checks `impact` (its group given by id `group`), read at `where` (JSON
// path or file:line), and appends it.
void AddImpact(const Reader& reader, const std::string& where, const std::string& group,
               Impact impact, Observations* obs) {
  if (impact.id.empty()) impact.id = std::to_string(obs->impacts.size() + 1);
  for (const Impact& other : obs->impacts)
    if (other.id == impact.id)
      throw InputError(
          where, "column 'id': impact '" + impact.id + "' is given twice; expected each once");
  const auto& groups = reader.scene().groups;
  impact.group = -1;
  for (std::size_t g = 0; g < groups.size(); ++g)
    if (groups[g].id == group) impact.group = static_cast<int>(g);
  if (impact.group < 0) {
    std::string ids;
    for (const core::RockGroup& g : groups)
      if (!g.id.empty()) ids += (ids.empty() ? "" : ", ") + g.id;
    throw InputError(where, "column 'group': no rock group of the site has the id '" + group +
                                "' (expected the 'id' of the group of the tracked rock; " +
                                (ids.empty() ? "the site's groups have no ids" : "ids: " + ids) +
                                ")");
  }
  const core::HeightGrid& grid = reader.scene().grid;
  const Eigen::Vector3d& c = impact.centre;
  const auto ground = sites::ElevationAt(grid, c.x(), c.y());
  if (!sites::OnTerrain(grid, c.x(), c.y()) || !ground)
    throw InputError(where, "columns 'x', 'y': the impact at " +
                                FormatPoint(Eigen::Vector2d(c.x(), c.y())) +
                                " m is off the terrain (outside the grid or over a hole); "
                                "expected an impact on the terrain");
  // On rough ground a rock sinks below the surface between the virtual
  // spheres (docs/physics.md: a node's sphere sags R <= s/2 along the fall
  // line, more at a cell's centre), so its centre at an impact may lie below
  // the surface; one sphere spacing s below it is inside the terrain.
  const double depth = grid.spacing;
  if (c.z() < *ground - depth)
    throw InputError(where, "column 'z': the rock's centre " + FormatNumber(c.z(), "%.4g") +
                                " m is " + FormatNumber(*ground - c.z(), "%.4g") +
                                " m below the ground (" + FormatNumber(*ground, "%.4g") +
                                " m there): inside the terrain; expected the centre at the "
                                "impact, at most one sphere spacing (" +
                                FormatNumber(depth, "%.4g") + " m) below the ground");
  const Eigen::Vector3d n = GridNormal(grid, c.x(), c.y(), *ground);
  if (!(impact.velocity_in.dot(n) < 0.0))
    throw InputError(where, "columns 'vx_in', 'vy_in', 'vz_in': " + Vec(impact.velocity_in) +
                                " m/s does not approach the ground (normal " + Vec(n) +
                                "); expected the velocity before the impact");
  if (!(impact.velocity_out.dot(n) > 0.0))
    throw InputError(where, "columns 'vx_out', 'vy_out', 'vz_out': " + Vec(impact.velocity_out) +
                                " m/s does not leave the ground (normal " + Vec(n) +
                                "); expected the velocity after the impact");
  impact.normal = n;
  obs->impacts.push_back(std::move(impact));
}

Eigen::Vector3d Vector3(const JsonNode& node) {
  const std::vector<JsonNode> items = node.Array(3);
  if (items.size() != 3) node.Fail("expected an array of 3 numbers");
  return Eigen::Vector3d(items[0].Number(), items[1].Number(), items[2].Number());
}

// The "impacts" array.
void ReadImpacts(const Reader& reader, const JsonNode& node, Observations* obs) {
  for (const JsonNode& e : node.Array(1)) {
    e.Keys(ObservationsKeysAt("$.impacts[]"));
    Impact impact;
    if (e.Has("id")) impact.id = e.Get("id").String();
    const std::vector<double> c = sites::CoordinatesToSI(e.Get("centre"), 3, reader.units());
    impact.centre = Eigen::Vector3d(c[0], c[1], c[2]);
    const double to_si = reader.Length(1.0);
    impact.velocity_in = to_si * Vector3(e.Get("velocity_in"));
    impact.velocity_out = to_si * Vector3(e.Get("velocity_out"));
    if (e.Has("spin")) impact.spin = Vector3(e.Get("spin"));
    AddImpact(reader, e.where(), e.Get("group").String(), std::move(impact), obs);
  }
}

// The "impacts_file" CSV: a header naming its columns, in any order.
void ReadImpactsFile(const Reader& reader, const JsonNode& ref, Observations* obs) {
  static const char* const kRequired[] = {"group", "x",     "y",      "z",      "vx_in",
                                          "vy_in", "vz_in", "vx_out", "vy_out", "vz_out"};
  static const char* const kOptional[] = {"id", "wx", "wy", "wz"};
  const CsvTable table{reader.CsvFile(ref), {}};
  sites::LineReader in(table.file);
  CsvRow row;
  std::string text;
  std::vector<std::string> header;
  auto column = [&](const char* name) {
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == name) return static_cast<int>(c);
    return -1;
  };
  const std::size_t before = obs->impacts.size();
  while (NextCsvRow(&in, &row, &text)) {
    if (header.empty()) {
      header = row.fields;
      std::string expected =
          "expected a header naming the columns group,x,y,z,vx_in,vy_in,"
          "vz_in,vx_out,vy_out,vz_out (in any order; optionally id and "
          "wx,wy,wz) (found " +
          sites::Excerpt(text) + ")";
      for (const char* name : kRequired)
        if (column(name) < 0)
          CsvFail(table, row, "no column '" + std::string(name) + "': " + expected);
      for (std::size_t c = 0; c < header.size(); ++c) {
        bool known = false;
        for (const char* name : kRequired) known = known || header[c] == name;
        for (const char* name : kOptional) known = known || header[c] == name;
        if (!known || column(header[c].c_str()) != static_cast<int>(c))
          CsvFail(table, row,
                  "column " + std::to_string(c + 1) + " '" + header[c] + "' is " +
                      (known ? "given twice" : "unknown") + ": " + expected);
      }
      const int spins = (column("wx") >= 0) + (column("wy") >= 0) + (column("wz") >= 0);
      if (spins != 0 && spins != 3)
        CsvFail(table, row, "expected all of wx,wy,wz or none: " + expected);
      continue;
    }
    if (row.fields.size() != header.size())
      CsvFail(table, row,
              "expected " + std::to_string(header.size()) +
                  " values per row (as the header), found " + std::to_string(row.fields.size()) +
                  " in " + sites::Excerpt(text));
    auto number = [&](const char* name) {
      return CsvNumber(table, row, static_cast<std::size_t>(column(name)), name);
    };
    auto length = [&](const char* name) { return reader.Length(number(name)); };
    Impact impact;
    if (column("id") >= 0) impact.id = row.fields[static_cast<std::size_t>(column("id"))];
    impact.centre = Eigen::Vector3d(length("x"), length("y"), length("z"));
    impact.velocity_in = Eigen::Vector3d(length("vx_in"), length("vy_in"), length("vz_in"));
    impact.velocity_out = Eigen::Vector3d(length("vx_out"), length("vy_out"), length("vz_out"));
    if (column("wx") >= 0) impact.spin = Eigen::Vector3d(number("wx"), number("wy"), number("wz"));
    AddImpact(reader, table.file + ":" + std::to_string(row.line),
              row.fields[static_cast<std::size_t>(column("group"))], std::move(impact), obs);
  }
  if (obs->impacts.size() == before)
    throw InputError(table.file,
                     "no data rows (expected a header and one row per impact; "
                     "referenced at " +
                         ref.where() + ")");
}

void Read(const Reader& reader, const JsonNode& root, Observations* obs) {
  if (root.Has("impacts") && root.Has("impacts_file"))
    throw InputError(root.where(),
                     "keys 'impacts' and 'impacts_file' both given (expected at most one)");
  if (const auto draws = root.Find("impact_draws")) {
    if (!root.Has("impacts") && !root.Has("impacts_file"))
      draws->Fail("expected 'impact_draws' only with 'impacts' or 'impacts_file'");
    obs->impact_draws = static_cast<int>(draws->Integer(1, core::kMaxImpactDraws));
  }
  if (const auto impacts = root.Find("impacts")) ReadImpacts(reader, *impacts, obs);
  if (const auto impacts = root.Find("impacts_file")) ReadImpactsFile(reader, *impacts, obs);
  if (!obs->impacts.empty())
    obs->notes.push_back("impacts: " + std::to_string(obs->impacts.size()) +
                         " measured impacts, each replayed " + std::to_string(obs->impact_draws) +
                         " times (impact_draws)");
}

void ReadError(const Reader&, const JsonNode& error, Observations* obs) {
  if (const auto e = error.Find("rebound")) obs->error.rebound = e->Positive();
}

// ---------------------------------------------------------------------------
// Recording and misfit

void Record(const Observations& obs, core::RecordOptions* base, bool*) {
  base->impacts.clear();
  for (const Impact& impact : obs.impacts) {
    core::ImpactReplay replay;
    replay.group = impact.group;
    replay.centre = impact.centre;
    replay.velocity_in = impact.velocity_in;
    replay.spin = impact.spin;
    replay.draws = obs.impact_draws;
    base->impacts.push_back(replay);
  }
}

// The median of `values` and their robust spread, 1.4826 times the median
// absolute deviation (0 for fewer than 2).
std::pair<double, double> MedianSpread(std::vector<double> values) {
  if (values.empty()) return {0.0, 0.0};
  std::sort(values.begin(), values.end());
  const double median = core::Quantile(values, 0.5);
  std::vector<double> dev;
  for (double v : values) dev.push_back(std::abs(v - median));
  std::sort(dev.begin(), dev.end());
  return {median, values.size() < 2 ? 0.0 : kMad * core::Quantile(dev, 0.5)};
}

// One ratio's residual: the draws' median against the observed ratio, with
// sigma^2 = e^2 + s^2 (1 + pi / (2 n)) (the observed rebound one draw of
// the predictive distribution of spread s, the median's Monte Carlo error).
void CompareRatio(const MisfitTerms& terms, const ResidualId& id, Statistic statistic,
                  const std::vector<double>& draws, double observed, double error,
                  double* simulated, double* spread, double* sigma) {
  const auto [median, s] = MedianSpread(draws);
  *simulated = median;
  *spread = s;
  const double n = static_cast<double>(draws.size());
  const double fixed = std::max(error, terms.compare.SigmaFloor(error));
  *sigma = std::max(std::sqrt(error * error + s * s * (1.0 + kPi / (2.0 * n))), fixed);
  terms.compare.Residual(id, statistic, median, observed, *sigma, (median - observed) / *sigma,
                         fixed);
}

// The ratios are taken about the impact's own normal (read from the grid),
// so which residuals an impact has never depends on a simulation.
ImpactFit FitImpact(const Impact& impact, const core::ImpactRebound& rebound) {
  ImpactFit fit;
  fit.id = impact.id;
  fit.group = impact.group;
  fit.normal = impact.normal;
  fit.observed = impact.velocity_out;
  const Eigen::Vector3d& v = impact.velocity_in;
  fit.incidence_deg =
      std::acos(std::clamp(-v.dot(impact.normal) / v.norm(), -1.0, 1.0)) * 180.0 / kPi;
  const core::ReboundRatios observed = core::RatiosOf(v, impact.velocity_out, impact.normal);
  fit.normal_observed = observed.normal;
  fit.tangential_observed = observed.tangential;
  std::vector<double> component[3], speed;
  for (std::size_t d = 0; d < rebound.velocity.size(); ++d) {
    const Eigen::Vector3d& out = rebound.velocity[d];
    if (!out.allFinite()) continue;
    ++fit.draws;
    fit.left += rebound.left[d] ? 1 : 0;
    for (int k = 0; k < 3; ++k) component[k].push_back(out[k]);
    speed.push_back(out.norm());
    const core::ReboundRatios r = core::RatiosOf(v, out, impact.normal);
    fit.normal_draws.push_back(r.normal);
    if (std::isfinite(r.tangential)) fit.tangential_draws.push_back(r.tangential);
  }
  for (int k = 0; k < 3; ++k) fit.simulated[k] = MedianSpread(component[k]).first;
  fit.speed_sd = MedianSpread(speed).second;
  return fit;
}

// Each impact's normal and tangential ratios against its draws, then (with
// kMinPooled impacts or more) every impact's ratios pooled as distributions.
void AddResiduals(const Observations& obs, const MisfitTerms& terms) {
  if (obs.impacts.empty()) return;
  const auto& rebounds = terms.result.impacts;
  if (rebounds.size() != obs.impacts.size())
    throw std::invalid_argument("ComputeMisfit: the result replayed " +
                                std::to_string(rebounds.size()) + " impacts of the " +
                                std::to_string(obs.impacts.size()) +
                                " observed (simulate with RequiredRecording)");
  const double e = obs.error.rebound;
  std::vector<double> pooled_n, pooled_t, observed_n, observed_t;
  for (std::size_t i = 0; i < obs.impacts.size(); ++i) {
    ImpactFit fit = FitImpact(obs.impacts[i], rebounds[i]);
    const ResidualId id = ResidualId::Of(ObservationKind::kImpact, static_cast<int>(i), fit.id);
    const bool tangential = std::isfinite(fit.tangential_observed);
    observed_n.push_back(fit.normal_observed);
    if (tangential) observed_t.push_back(fit.tangential_observed);
    if (fit.draws == 0) {  // its residuals add up to the penalty
      const double value = std::sqrt(2.0 * terms.options.penalty / (tangential ? 2.0 : 1.0));
      terms.compare.Residual(id, Statistic::kNormalRatio, 0.0, fit.normal_observed, 1.0, value,
                             0.0);
      if (tangential)
        terms.compare.Residual(id, Statistic::kTangentialRatio, 0.0, fit.tangential_observed, 1.0,
                               value, 0.0);
      terms.misfit->penalised = true;
      terms.misfit->message += "impact " + fit.id + ": no replay ended with a finite velocity. ";
      terms.misfit->impacts.push_back(std::move(fit));
      continue;
    }
    CompareRatio(terms, id, Statistic::kNormalRatio, fit.normal_draws, fit.normal_observed, e,
                 &fit.normal_simulated, &fit.normal_spread, &fit.normal_sigma);
    if (tangential)  // then every draw's is defined too (RatiosOf: v_in and n alone decide)
      CompareRatio(terms, id, Statistic::kTangentialRatio, fit.tangential_draws,
                   fit.tangential_observed, e, &fit.tangential_simulated, &fit.tangential_spread,
                   &fit.tangential_sigma);
    pooled_n.insert(pooled_n.end(), fit.normal_draws.begin(), fit.normal_draws.end());
    pooled_t.insert(pooled_t.end(), fit.tangential_draws.begin(), fit.tangential_draws.end());
    terms.misfit->impacts.push_back(std::move(fit));
  }
  if (observed_n.size() >= kMinPooled)
    terms.compare.Distributions(ResidualId::Of(ObservationKind::kImpactsNormal), pooled_n,
                                observed_n, e);
  if (observed_t.size() >= kMinPooled)
    terms.compare.Distributions(ResidualId::Of(ObservationKind::kImpactsTangential), pooled_t,
                                observed_t, e);
}

std::string Text(const ResidualId& id) {
  switch (id.kind) {
    case ObservationKind::kImpact:
      return "impact " + id.name;
    case ObservationKind::kImpactsNormal:
      return "impacts normal ratio";
    case ObservationKind::kImpactsTangential:
      return "impacts tangential ratio";
    default:
      return "";
  }
}

std::optional<ResidualId> ParseText(const std::string& text) {
  if (text == "impacts normal ratio") return ResidualId::Of(ObservationKind::kImpactsNormal);
  if (text == "impacts tangential ratio")
    return ResidualId::Of(ObservationKind::kImpactsTangential);
  if (const auto id = After(text, "impact "))
    return ResidualId::Of(ObservationKind::kImpact, -1, *id);
  return std::nullopt;
}

// ---------------------------------------------------------------------------
// Folds: the impacts are dealt over the folds like the other values.

void DealFolds(const Observations& obs, int k, std::mt19937_64* rng, std::vector<Fold>* folds) {
  if (obs.impacts.empty()) return;
  const std::size_t n = obs.impacts.size();
  if (n < static_cast<std::size_t>(k))
    throw InputError(obs.path, "impacts: " + std::to_string(n) + " impacts, fewer than the " +
                                   std::to_string(k) + " folds of --holdout");
  const auto dealt = Deal(n, k, rng);
  for (int f = 0; f < k; ++f)
    (*folds)[static_cast<std::size_t>(f)].impacts = dealt[static_cast<std::size_t>(f)];
}

void KeepFold(const Observations& observations, const Fold& fold, bool held_out,
              Observations* out) {
  out->impacts.clear();
  for (std::size_t i = 0; i < observations.impacts.size(); ++i)
    if (Keep(fold.impacts, i, held_out)) out->impacts.push_back(observations.impacts[i]);
}

}  // namespace

Kind ImpactsKind() {
  Kind kind;
  kind.name = "impacts";
  kind.root_keys = {"impacts", "impacts_file", "impact_draws"};
  kind.objects = {
      {"$.impacts[]", {"id", "group", "centre", "velocity_in", "velocity_out", "spin"}}};
  kind.error_keys = {"rebound"};
  kind.residual_kinds = {ObservationKind::kImpact, ObservationKind::kImpactsNormal,
                         ObservationKind::kImpactsTangential};
  kind.observation_text = Text;
  kind.parse_text = ParseText;
  kind.read = Read;
  kind.read_error = ReadError;
  kind.record = Record;
  kind.misfit = AddResiduals;
  kind.fold = DealFolds;
  kind.subset = KeepFold;
  return kind;
}

}  // namespace rockcal::observations::kinds
