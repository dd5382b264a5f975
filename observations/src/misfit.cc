#include "rockcal/observations/misfit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "compare.h"
#include "kinds/kinds.h"
#include "rockcal/core/format.h"
#include "rockcal/core/name_table.h"

namespace rockcal::observations {
namespace {

using core::FormatNumber;

bool Finite(const core::Crossing& c) {
  return std::isfinite(c.height) && std::isfinite(c.speed) && std::isfinite(c.energy) &&
         c.point.allFinite();
}

// Number of rocks with a non-finite value in a record the misfit may read.
int CountNonFiniteRecords(const core::SimulationResult& result) {
  int count = 0;
  for (const core::RockRecord& rock : result.rocks) {
    bool ok = rock.start.allFinite() && rock.stop.allFinite();
    for (const core::Crossing& c : rock.crossings) ok = ok && (!c.crossed || Finite(c));
    for (const core::Crossing& c : rock.trees) ok = ok && (!c.crossed || Finite(c));
    if (!ok) ++count;
  }
  return count;
}

}  // namespace

namespace {
constexpr core::Named<RunTerms> kRunTerms[] = {
    {RunTerms::kPooled, "pooled"}, {RunTerms::kPerRun, "per_run"}, {RunTerms::kBoth, "both"}};
}  // namespace

const char* RunTermsToString(RunTerms terms) { return core::NameOf(kRunTerms, terms); }
bool StringToRunTerms(const std::string& name, RunTerms* terms) {
  return core::IdOf(kRunTerms, name, terms);
}

std::string ResidualId::observation() const {
  std::string text;
  if (kind == ObservationKind::kPrior) return "prior";
  for (const kinds::Kind& k : kinds::Kinds()) {
    const auto& own = k.residual_kinds;
    if (std::find(own.begin(), own.end(), kind) != own.end()) text = k.observation_text(*this);
  }
  return site.empty() ? text : site + ": " + text;
}

std::string ResidualId::quantity() const {
  switch (statistic) {
    case Statistic::kNone:
      return "";
    case Statistic::kQuantile:
      return LevelName(level);
    case Statistic::kMax:
      return "max";
    case Statistic::kShare:
      return "share";
    case Statistic::kFraction:
      return "fraction";
    case Statistic::kRunout:
      return "runout";
    case Statistic::kOffset:
      return site + ":" + name + "_offset";
    case Statistic::kNormalRatio:
      return "normal_ratio";
    case Statistic::kTangentialRatio:
      return "tangential_ratio";
  }
  return "";
}

ResidualId ResidualId::Parse(const std::string& observation, const std::string& quantity) {
  ResidualId id;
  if (!observation.empty()) {
    std::optional<ResidualId> found;
    for (const kinds::Kind& k : kinds::Kinds())
      if (!found && k.parse_text) found = k.parse_text(observation);
    if (!found) throw std::invalid_argument("unknown residual observation '" + observation + "'");
    id = *found;
  }
  for (const Statistic s :
       {Statistic::kMax, Statistic::kShare, Statistic::kFraction, Statistic::kRunout,
        Statistic::kNormalRatio, Statistic::kTangentialRatio})
    if (quantity == id.With(s).quantity()) return id.With(s);
  if (quantity.size() > 1 && quantity[0] == 'p')
    return id.With(Statistic::kQuantile, std::stod(quantity.substr(1)) / 100.0);
  if (!quantity.empty())
    throw std::invalid_argument("unknown residual quantity '" + quantity + "'");
  return id;
}

ResidualId ResidualId::Of(ObservationKind kind, int index, std::string name) {
  ResidualId id;
  id.kind = kind;
  id.index = index;
  id.name = std::move(name);
  return id;
}

ResidualId ResidualId::With(Statistic what, double at) const {
  ResidualId id = *this;
  id.statistic = what;
  id.level = at;
  return id;
}

ResidualId ResidualId::observation_id() const { return With(Statistic::kNone); }

bool ResidualId::operator==(const ResidualId& o) const {
  return kind == o.kind && index == o.index && name == o.name && statistic == o.statistic &&
         level == o.level && site == o.site;
}

bool ResidualId::operator<(const ResidualId& o) const {
  return std::tie(site, kind, index, name, statistic, level) <
         std::tie(o.site, o.kind, o.index, o.name, o.statistic, o.level);
}

std::vector<double> MisfitOptions::DefaultLevels() {
  return {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
}

bool MisfitOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (levels.empty() && !include_max) {
    return fail(
        "levels is empty and include_max is false (expected at least one quantity to "
        "compare)");
  }
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (!(levels[i] >= 0.0 && levels[i] <= 1.0)) {
      return fail("levels[" + std::to_string(i) + "] = " + FormatNumber(levels[i], "%.6g") +
                  " (expected a level in [0, 1])");
    }
  }
  if (!(std::isfinite(penalty) && penalty > 0.0)) {
    return fail("penalty = " + FormatNumber(penalty, "%.6g") + " (expected a finite number > 0)");
  }
  if (!(std::isfinite(run_spread_prior) && run_spread_prior >= 0.0)) {
    return fail("run_spread_prior = " + FormatNumber(run_spread_prior, "%.6g") +
                " (expected a finite number >= 0)");
  }
  if (!(sigma_floor > 0.0 && sigma_floor <= 1.0)) {
    return fail("sigma_floor = " + FormatNumber(sigma_floor, "%.6g") +
                " (expected a number in (0, 1])");
  }
  return true;
}

std::string Misfit::Report() const {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-28s %-9s %12s %12s %12s %10s\n", "observation", "quantity",
                "simulated", "observed", "sigma", "residual");
  out << line;
  for (const Residual& r : residuals) {
    std::snprintf(line, sizeof(line), "%-28s %-9s %12.5g %12.5g %12.5g %10.4g\n",
                  r.id.observation().c_str(), r.id.quantity().c_str(), r.simulated, r.observed,
                  r.sigma, r.value);
    out << line;
  }
  out << "misfit " << value << (penalised ? " (penalised)" : "") << "\n";
  if (!message.empty()) out << message << "\n";
  return out.str();
}

double Misfit::MeanRunError() const {
  if (runs.empty()) return 0.0;
  double sum = 0.0;
  for (const RunFit& r : runs) sum += std::abs(r.simulated - r.observed);
  return sum / static_cast<double>(runs.size());
}

int Misfit::StuckRocks() const {
  int n = 0;
  for (const RunFit& r : runs) n += r.stuck;
  return n;
}

Misfit ComputeMisfit(const Observations& observations, const core::Scene& scene,
                     const core::SimulationResult& result, const MisfitOptions& options) {
  std::string invalid;
  if (!options.IsValid(&invalid)) throw std::invalid_argument("MisfitOptions: " + invalid);

  Misfit misfit;
  const int non_finite = std::max(result.figures.non_finite, CountNonFiniteRecords(result));
  if (non_finite > 0) {
    misfit.value = options.penalty;
    misfit.penalised = true;
    misfit.message = "the simulation produced " + std::to_string(non_finite) +
                     " rock(s) with a non-finite state; misfit set to the penalty " +
                     FormatNumber(options.penalty, "%.6g") + ".";
    return misfit;
  }

  const Comparer compare(options, &misfit);
  const MisfitTerms terms{scene, result, options, compare, &misfit};
  for (const kinds::Kind& kind : kinds::Kinds())
    if (kind.misfit) kind.misfit(observations, terms);

  double sum = 0.0;
  for (const Residual& r : misfit.residuals) {
    sum += r.value * r.value;
    if (r.fixed_sigma > 0.0 && r.fixed_sigma <= r.sigma)
      misfit.log_scale += std::log(r.sigma / r.fixed_sigma);
  }
  misfit.value = 0.5 * sum;
  return misfit;
}

}  // namespace rockcal::observations
