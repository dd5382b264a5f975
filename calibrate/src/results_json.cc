// to_json / from_json of calibrate's results as their files hold them:
// stability.json, convergence.json, sensitivity.json, reach.json and
// score.json. from_json reads back what to_json wrote (a number the file
// holds as null, being unknown, comes back as NaN or, for an error, +inf);
// what the files show besides the struct (counts, the rules in words,
// flags derived from indices) is written, not read.
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>

#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/core/material_field.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using nlohmann::json;
using text::JsonNum;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The number at `key` of `j`; `unknown` where the file holds null.
double Number(const json& j, const char* key, double unknown = kNaN) {
  const json& v = j.at(key);
  return v.is_null() ? unknown : v.get<double>();
}

// A list of numbers written with JsonNum.
json Numbers(const std::vector<double>& v) {
  json out = json::array();
  for (double x : v) out.push_back(JsonNum(x));
  return out;
}
std::vector<double> Numbers(const json& j) {
  std::vector<double> out;
  for (const json& v : j) out.push_back(v.is_null() ? kNaN : v.get<double>());
  return out;
}

// The verdict as score.json's fit (read back, it follows from the residuals).
json FitJson(const observations::FitVerdict& fit) {
  return {{"verdict", fit.poor ? "poor" : fit.fair ? "fair" : "good"},
          {"sentence", fit.Sentence()},
          {"count_chance", fit.count_chance},
          {"largest_chance", fit.largest_chance},
          {"outside_2_sigma", fit.outside}};
}

json Outcomes(int stopped, int left, int timeout) {
  return {{"stopped", stopped}, {"left", left}, {"timeout", timeout}};
}

// The parameter of `material` called `name` (a field's name, with
// "_offset" after it for an offset).
Parameter ParameterOf(const std::string& material, std::string name) {
  Parameter p;
  p.material = material;
  const std::string offset = "_offset";
  if (name.size() > offset.size() &&
      name.compare(name.size() - offset.size(), offset.size(), offset) == 0) {
    p.offset = true;
    name.resize(name.size() - offset.size());
  }
  const core::MaterialFieldInfo* field = core::FindMaterialField(name);
  if (!field) throw std::invalid_argument("unknown parameter name '" + name + "'");
  p.kind = field->field;
  return p;
}

// The identity of a residual from its texts, ResidualId::observation and
// ::quantity, as one site's misfit prints them (reach.json and score.json
// hold them so): the kind and name from the observation, the statistic and
// level from the quantity. A campaign's site prefix and offsets are not
// among them; an index the text does not carry (a mass class's, a run's)
// stays -1.
observations::ResidualId ResidualIdOf(const std::string& observation, const std::string& quantity) {
  using observations::ObservationKind;
  using observations::ResidualId;
  using observations::Statistic;
  auto starts = [&](const std::string& prefix) { return observation.rfind(prefix, 0) == 0; };
  // "tree_scars[2] <label>", "passing[0] <label>": the index in brackets.
  auto indexed = [&](ObservationKind kind) {
    return ResidualId::Of(kind, std::atoi(observation.c_str() + observation.find('[') + 1),
                          observation);
  };
  const std::string mass = "runout distance, mass ", kg = " kg";
  ResidualId id;
  if (observation == "runout distance") {
    id = ResidualId::Of(ObservationKind::kRunoutDistance);
  } else if (starts(mass) && observation.size() > mass.size() + kg.size()) {
    id = ResidualId::Of(
        ObservationKind::kRunoutMassClass, -1,
        observation.substr(mass.size(), observation.size() - mass.size() - kg.size()));
  } else if (observation == "runout lateral") {
    id = ResidualId::Of(ObservationKind::kRunoutLateral);
  } else if (observation == "runout stopped") {
    id = ResidualId::Of(ObservationKind::kRunoutStopped);
  } else if (starts("run ")) {
    id = ResidualId::Of(ObservationKind::kRun, -1, observation.substr(4));
  } else if (starts("tree_scars[")) {
    id = indexed(ObservationKind::kTreeScars);
  } else if (starts("passing[")) {
    id = indexed(ObservationKind::kPassing);
  } else if (!observation.empty()) {
    throw std::invalid_argument("unknown residual observation '" + observation + "'");
  }
  const std::pair<const char*, Statistic> named[] = {{"max", Statistic::kMax},
                                                     {"share", Statistic::kShare},
                                                     {"fraction", Statistic::kFraction},
                                                     {"runout", Statistic::kRunout}};
  for (const auto& [text, statistic] : named)
    if (quantity == text) return id.With(statistic);
  if (quantity.size() > 1 && quantity[0] == 'p')
    return id.With(Statistic::kQuantile, std::stod(quantity.substr(1)) / 100.0);
  if (!quantity.empty())
    throw std::invalid_argument("unknown residual quantity '" + quantity + "'");
  return id;
}

// The parameter labelled "<material>.<name>" (Parameter::label).
Parameter ParameterOfLabel(const std::string& label) {
  const std::size_t dot = label.rfind('.');
  if (dot == std::string::npos)
    throw std::invalid_argument("parameter label '" + label + "' has no '.'");
  return ParameterOf(label.substr(0, dot), label.substr(dot + 1));
}

// The time steps and work of a run (RunFigures) as the stability cases and
// the convergence rows list them, and back.
void AddStepFigures(const core::RunFigures& f, json* j) {
  (*j)["dt_min_seconds"] = f.dt_min;
  (*j)["dt_max_seconds"] = f.dt_max;
  (*j)["rocks_with_step_shrunk"] = f.dt_shrunk;
  (*j)["steps"] = f.steps;
  (*j)["flights"] = f.flights;
}

void ReadStepFigures(const json& j, core::RunFigures* f) {
  f->dt_min = j.at("dt_min_seconds").get<double>();
  f->dt_max = j.at("dt_max_seconds").get<double>();
  f->dt_shrunk = j.at("rocks_with_step_shrunk").get<int>();
  f->steps = j.at("steps").get<long>();
  f->flights = j.at("flights").get<long>();
}

// ---- stability -------------------------------------------------------------------

constexpr const char* kStabilityCriteria =
    "PASS: no rock non-finite, no rock tunneled (centre below the terrain's floor by more "
    "than its radius), largest relative energy gain <= energy_tolerance, and for cases with "
    "must_stop every rock stopped. Penetration above penetration_limit is a warning only: "
    "it follows from the contact law (overlap ~ v t_c / pi whatever the rock size).";

json CaseJson(const StabilityCase& c) {
  const core::RunFigures& f = c.figures;
  json j = {{"name", c.name},
          {"description", c.description},
          {"rocks", f.rocks},
          {"max_time_seconds", c.max_time},
          {"dt_shrunk", f.dt_shrunk > 0},
          {"wall_seconds", c.wall_seconds},
          {"outcomes", Outcomes(c.stopped, c.left, c.timeout)},
          {"max_relative_energy_gain", JsonNum(f.max_relative_energy_gain)},
          {"max_penetration_over_radius", JsonNum(f.max_penetration)},
          {"non_finite_rocks", f.non_finite},
          {"tunneled_rocks", f.tunneled},
          {"must_stop", c.must_stop},
          {"result", c.pass ? "PASS" : "FAIL"},
          {"reason", c.reason},
          {"warning", c.warning}};
  AddStepFigures(f, &j);
  return j;
}

StabilityCase CaseOf(const json& j) {
  StabilityCase c;
  c.name = j.at("name").get<std::string>();
  c.description = j.at("description").get<std::string>();
  c.max_time = j.at("max_time_seconds").get<double>();
  core::RunFigures& f = c.figures;
  f.rocks = j.at("rocks").get<int>();
  ReadStepFigures(j, &f);
  f.max_relative_energy_gain = Number(j, "max_relative_energy_gain");
  f.max_penetration = Number(j, "max_penetration_over_radius");
  f.non_finite = j.at("non_finite_rocks").get<int>();
  f.tunneled = j.at("tunneled_rocks").get<int>();
  c.wall_seconds = j.at("wall_seconds").get<double>();
  const json& o = j.at("outcomes");
  c.stopped = o.at("stopped").get<int>();
  c.left = o.at("left").get<int>();
  c.timeout = o.at("timeout").get<int>();
  c.must_stop = j.at("must_stop").get<bool>();
  c.pass = j.at("result").get<std::string>() == "PASS";
  c.reason = j.at("reason").get<std::string>();
  c.warning = j.at("warning").get<std::string>();
  return c;
}

// ---- convergence -----------------------------------------------------------------

constexpr const char* kConvergenceErrors =
    "relative to each quantity's value in the reference run (finest N_c, most rocks); "
    "total_error = |value - reference|; discretisation_error = |value - value at the "
    "finest N_c with the same rocks and seed|; discretisation_noise = half-width of the "
    "paired bootstrap interval of that difference (a discretisation_error below it is not "
    "resolved from the chaotic spread of single trajectories); mc_error = half-width of "
    "the bootstrap interval of the quantile (rocks resampled) at this rock count; "
    "estimate = the discretisation_error of this N_c at the largest rock count (where it "
    "is best resolved; it does not depend on the count) + mc_error, used for the "
    "recommendation; null = unknown";

json QuantityJson(const QuantityError& q) {
  return {{"name", q.name},
          {"value", JsonNum(q.value)},
          {"count", q.count},
          {"total_error", JsonNum(q.total_error)},
          {"mc_error", JsonNum(q.mc_error)},
          {"discretisation_error", JsonNum(q.discretisation_error)},
          {"discretisation_noise", JsonNum(q.discretisation_noise)},
          {"estimate", JsonNum(q.estimate)}};
}

QuantityError QuantityOf(const json& j) {
  QuantityError q;
  q.name = j.at("name").get<std::string>();
  q.value = Number(j, "value");
  q.count = j.at("count").get<int>();
  q.total_error = Number(j, "total_error", kInf);
  q.mc_error = Number(j, "mc_error", kInf);
  q.discretisation_error = Number(j, "discretisation_error", kInf);
  q.discretisation_noise = Number(j, "discretisation_noise", kInf);
  q.estimate = Number(j, "estimate", kInf);
  return q;
}

json RowJson(const ConvergenceRow& r) {
  json qs = json::array();
  for (const QuantityError& q : r.quantities) qs.push_back(QuantityJson(q));
  json j = {{"steps_per_contact", r.steps_per_contact},
          {"rocks", r.rocks},
          {"wall_seconds", r.wall_seconds},
          {"outcomes", Outcomes(r.stopped, r.left, r.timeout)},
          {"max_total_error", JsonNum(r.max_total_error)},
          {"max_mc_error", JsonNum(r.max_mc_error)},
          {"max_discretisation_error", JsonNum(r.max_discretisation_error)},
          {"max_discretisation_noise", JsonNum(r.max_discretisation_noise)},
          {"max_estimate", JsonNum(r.max_estimate)},
          {"meets_target", r.meets_target},
          {"quantities", qs}};
  AddStepFigures(r.figures, &j);
  return j;
}

ConvergenceRow RowOf(const json& j) {
  ConvergenceRow r;
  r.steps_per_contact = j.at("steps_per_contact").get<int>();
  r.rocks = j.at("rocks").get<int>();
  ReadStepFigures(j, &r.figures);
  r.wall_seconds = j.at("wall_seconds").get<double>();
  const json& o = j.at("outcomes");
  r.stopped = o.at("stopped").get<int>();
  r.left = o.at("left").get<int>();
  r.timeout = o.at("timeout").get<int>();
  for (const json& q : j.at("quantities")) r.quantities.push_back(QuantityOf(q));
  r.max_total_error = Number(j, "max_total_error", kInf);
  r.max_mc_error = Number(j, "max_mc_error", kInf);
  r.max_discretisation_error = Number(j, "max_discretisation_error", kInf);
  r.max_discretisation_noise = Number(j, "max_discretisation_noise", kInf);
  r.max_estimate = Number(j, "max_estimate", kInf);
  r.meets_target = j.at("meets_target").get<bool>();
  return r;
}

// ---- sensitivity -----------------------------------------------------------------

constexpr const char* kMorrisDefinitions =
    "Morris elementary effects on a grid of `levels` levels with step delta (unit "
    "box): effect = change of the output / change of the parameter as a fraction of "
    "its range (output units per full range). mu: mean effect; mu_star: mean |effect|; "
    "sigma: standard deviation of the effects (interactions and curvature). noise: "
    "bootstrap standard error of the output over the rocks of one run at the current "
    "parameters; effect_noise = sqrt(2) noise / delta, the spread one elementary "
    "effect would have from independent noise; effect_over_noise = mu_star / "
    "effect_noise (pure noise gives about 0.8). null: unknown.";
constexpr const char* kSobolDefinitions =
    "Sobol indices from Saltelli sampling: first = S_i (Saltelli 2010 estimator), the "
    "share of the output's variance over the parameter box due to the parameter "
    "alone; total = ST_i (Jansen estimator), including its interactions; *_low and "
    "*_high: bootstrap percentile interval over the rows. variance: of the output over "
    "the box. noise: bootstrap standard error of the output over the rocks of one run "
    "at the current parameters; effect_over_noise = sqrt(max(first, 0) variance) / "
    "noise. null: unknown.";

bool IsMorris(const SensitivityResult& r) { return r.method == SensitivityMethod::kMorris; }

json DesignJson(const SensitivityResult& r) {
  if (IsMorris(r))
    return {{"trajectories", r.morris.trajectories},
            {"levels", r.morris.levels},
            {"delta", r.morris.delta},
            {"evaluations", r.morris.evaluations}};
  return {{"samples", r.sobol.samples},
          {"bootstrap", r.sobol.bootstrap},
          {"confidence", r.sobol.confidence},
          {"evaluations", r.sobol.evaluations},
          {"sampling", kSobolSampling}};
}

json OutputJson(const SensitivityResult& r, std::size_t o) {
  const SensitivityOutputInfo& out = r.outputs[o];
  json j = {{"name", out.name},
            {"unit", out.unit},
            {"description", out.description},
            {"value", JsonNum(out.value)},
            {"noise", JsonNum(out.noise)}};
  if (IsMorris(r)) {
    j["effect_noise"] = JsonNum(r.EffectNoise(o));
  } else {
    j["variance"] = JsonNum(r.sobol.variance[o]);
    j["rows"] = r.sobol.rows[o];
  }
  return j;
}

json EntryJson(const SensitivityResult& r, const SensitivityEntry& e) {
  json j = {{"parameter", r.parameters[static_cast<std::size_t>(e.parameter)].label()},
            {"output", r.outputs[static_cast<std::size_t>(e.output)].name}};
  if (IsMorris(r)) {
    j["mu"] = JsonNum(e.morris.mu);
    j["mu_star"] = JsonNum(e.morris.mu_star);
    j["sigma"] = JsonNum(e.morris.sigma);
    j["effects"] = e.morris.effects;
  } else {
    j["first"] = JsonNum(e.sobol.first);
    j["first_low"] = JsonNum(e.sobol.first_low);
    j["first_high"] = JsonNum(e.sobol.first_high);
    j["total"] = JsonNum(e.sobol.total);
    j["total_low"] = JsonNum(e.sobol.total_low);
    j["total_high"] = JsonNum(e.sobol.total_high);
  }
  j["effect_over_noise"] = JsonNum(e.effect_over_noise);
  return j;
}

// The design's settings and the sizes of the per-output tables.
void ReadDesign(const json& design, int outputs, SensitivityResult* r) {
  const int k = static_cast<int>(r->parameters.size());
  if (IsMorris(*r)) {
    MorrisResult& m = r->morris;
    m.parameters = k, m.outputs = outputs;
    m.trajectories = design.at("trajectories").get<int>();
    m.levels = design.at("levels").get<int>();
    m.delta = design.at("delta").get<double>();
    m.evaluations = design.at("evaluations").get<int>();
    m.index.assign(static_cast<std::size_t>(outputs), std::vector<MorrisIndex>(k));
  } else {
    SobolResult& s = r->sobol;
    s.parameters = k, s.outputs = outputs;
    s.samples = design.at("samples").get<int>();
    s.bootstrap = design.at("bootstrap").get<int>();
    s.confidence = design.at("confidence").get<double>();
    s.evaluations = design.at("evaluations").get<int>();
    s.index.assign(static_cast<std::size_t>(outputs), std::vector<SobolIndex>(k));
  }
}

void ReadOutput(const json& j, SensitivityResult* r) {
  SensitivityOutputInfo out;
  out.name = j.at("name").get<std::string>();
  out.unit = j.at("unit").get<std::string>();
  out.description = j.at("description").get<std::string>();
  out.value = Number(j, "value");
  out.noise = Number(j, "noise");
  r->outputs.push_back(out);
  if (!IsMorris(*r)) {
    r->sobol.variance.push_back(Number(j, "variance"));
    r->sobol.rows.push_back(j.at("rows").get<int>());
  }
}

// Entry e (parameter-major: e = p * outputs + o), into entries and the method's index.
void ReadEntry(const json& j, std::size_t e, SensitivityResult* r) {
  const std::size_t m = r->outputs.size();
  SensitivityEntry entry;
  entry.parameter = static_cast<int>(e / m);
  entry.output = static_cast<int>(e % m);
  if (IsMorris(*r)) {
    entry.morris = {Number(j, "mu"), Number(j, "mu_star"), Number(j, "sigma"),
                    j.at("effects").get<int>()};
    r->morris.index[e % m][e / m] = entry.morris;
  } else {
    entry.sobol = {Number(j, "first"), Number(j, "first_low"), Number(j, "first_high"),
                   Number(j, "total"), Number(j, "total_low"), Number(j, "total_high")};
    r->sobol.index[e % m][e / m] = entry.sobol;
  }
  entry.effect_over_noise = Number(j, "effect_over_noise");
  r->entries.push_back(entry);
}

// ---- reach -------------------------------------------------------------------------

constexpr const char* kReachRule =
    "A statistic is in reach when its observed value lies within [min - sigma, max + sigma], "
    "where min and max are the smallest and largest simulated values over the design points and "
    "sigma is the median over those points of the residual's sigma (measurement error, Monte "
    "Carlo error of the simulated value, sampling error of the observed one). Out of reach "
    "(below): the observed value is below min - sigma; (above): above max + sigma; (no value): "
    "no design point gave a value (each was penalised for it). at_edge: in reach only by the "
    "sigma allowance (the observed value lies outside [min, max]).";

json StatisticJson(const ReachStatistic& s) {
  return {{"name", s.name()},
          {"observation", s.id.observation()},
          {"quantity", s.id.quantity()},
          {"observed", JsonNum(s.observed)},
          {"sigma", JsonNum(s.sigma)},
          {"min", JsonNum(s.min)},
          {"max", JsonNum(s.max)},
          {"min_point", s.min_point},
          {"max_point", s.max_point},
          {"closest_point", s.closest_point},
          {"closest_simulated", JsonNum(s.closest_simulated)},
          {"closest_sigmas", JsonNum(s.closest_sigmas)},
          {"points_with_value", s.points_with_value},
          {"in_reach", s.in_reach()},
          {"at_edge", s.at_edge()},
          {"verdict", ReachVerdictText(s.verdict)}};
}

ReachVerdict VerdictOf(const std::string& text) {
  for (ReachVerdict v :
       {ReachVerdict::kInReach, ReachVerdict::kBelow, ReachVerdict::kAbove, ReachVerdict::kNoValue})
    if (text == ReachVerdictText(v)) return v;
  throw std::invalid_argument("unknown reach verdict '" + text + "'");
}

ReachStatistic StatisticOf(const json& j) {
  ReachStatistic s;
  s.id = ResidualIdOf(j.at("observation").get<std::string>(), j.at("quantity").get<std::string>());
  s.observed = Number(j, "observed");
  s.sigma = Number(j, "sigma");
  s.min = Number(j, "min");
  s.max = Number(j, "max");
  s.min_point = j.at("min_point").get<int>();
  s.max_point = j.at("max_point").get<int>();
  s.closest_point = j.at("closest_point").get<int>();
  s.closest_simulated = Number(j, "closest_simulated");
  s.closest_sigmas = Number(j, "closest_sigmas");
  s.points_with_value = j.at("points_with_value").get<int>();
  s.verdict = VerdictOf(j.at("verdict").get<std::string>());
  return s;
}

json PointJson(const ReachPoint& p) {
  return {{"unit", p.unit},           {"physical", p.physical}, {"misfit", JsonNum(p.misfit)},
          {"penalised", p.penalised}, {"message", p.message},   {"simulated", Numbers(p.simulated)},
          {"sigma", Numbers(p.sigma)}};
}

ReachPoint PointOf(const json& j) {
  ReachPoint p;
  p.unit = j.at("unit").get<std::vector<double>>();
  p.physical = j.at("physical").get<std::vector<double>>();
  p.misfit = Number(j, "misfit");
  p.penalised = j.at("penalised").get<bool>();
  p.message = j.at("message").get<std::string>();
  p.simulated = Numbers(j.at("simulated"));
  p.sigma = Numbers(j.at("sigma"));
  return p;
}

}  // namespace

void to_json(json& j, const StabilityStudy& study) {
  json cases = json::array();
  for (const StabilityCase& c : study.cases) cases.push_back(CaseJson(c));
  const StabilityLimits& l = study.limits;
  j = {{"site", study.site},
       {"study", "stability"},
       {"limits",
        {{"energy_tolerance", l.energy_tolerance},
         {"penetration_limit_over_radius", l.penetration_limit},
         {"max_time_seconds", l.max_time},
         {"max_case_steps", l.max_case_steps},
         {"rocks_per_case", l.rocks}}},
       {"criteria", kStabilityCriteria},
       {"passed", study.passed()},
       {"failed", study.failed()},
       {"cases", cases}};
}

void from_json(const json& j, StabilityStudy& study) {
  study = StabilityStudy{};
  study.site = j.at("site").get<std::string>();
  const json& l = j.at("limits");
  study.limits.energy_tolerance = l.at("energy_tolerance").get<double>();
  study.limits.penetration_limit = l.at("penetration_limit_over_radius").get<double>();
  study.limits.max_time = l.at("max_time_seconds").get<double>();
  study.limits.max_case_steps = l.at("max_case_steps").get<long>();
  study.limits.rocks = l.at("rocks_per_case").get<int>();
  for (const json& c : j.at("cases")) study.cases.push_back(CaseOf(c));
}

void to_json(json& j, const ConvergenceResult& result) {
  json rows = json::array();
  for (std::size_t k = 0; k < result.rows.size(); ++k) {
    json row = RowJson(result.rows[k]);
    row["reference"] = static_cast<int>(k) == result.reference;
    row["recommended"] = static_cast<int>(k) == result.recommended;
    rows.push_back(row);
  }
  const ConvergenceRow& ref = result.rows.at(static_cast<std::size_t>(result.reference));
  json recommended;
  if (result.recommended >= 0) {
    const ConvergenceRow& r = result.rows[static_cast<std::size_t>(result.recommended)];
    recommended = {{"steps_per_contact", r.steps_per_contact},
                   {"rocks", r.rocks},
                   {"wall_seconds", r.wall_seconds},
                   {"max_estimate", JsonNum(r.max_estimate)}};
  }
  j = {{"site", result.site},
       {"study", "convergence"},
       {"target", result.target},
       {"bootstrap", result.bootstrap},
       {"confidence", result.confidence},
       {"seed", result.seed},
       {"threads", result.threads},
       {"reference", {{"steps_per_contact", ref.steps_per_contact}, {"rocks", ref.rocks}}},
       {"errors", kConvergenceErrors},
       {"quantities", result.quantities},
       {"notes", result.notes},
       {"recommended", recommended},
       {"recommendation", result.recommendation},
       {"rows", rows}};
}

void from_json(const json& j, ConvergenceResult& result) {
  result = ConvergenceResult{};
  result.site = j.at("site").get<std::string>();
  result.target = j.at("target").get<double>();
  result.bootstrap = j.at("bootstrap").get<int>();
  result.confidence = j.at("confidence").get<double>();
  result.seed = j.at("seed").get<std::uint64_t>();
  result.threads = j.at("threads").get<int>();
  result.quantities = j.at("quantities").get<std::vector<std::string>>();
  result.notes = j.at("notes").get<std::vector<std::string>>();
  result.recommendation = j.at("recommendation").get<std::string>();
  for (const json& row : j.at("rows")) {
    const int k = static_cast<int>(result.rows.size());
    if (row.at("reference").get<bool>()) result.reference = k;
    if (row.at("recommended").get<bool>()) result.recommended = k;
    result.rows.push_back(RowOf(row));
  }
}

void to_json(json& j, const SensitivityResult& r) {
  json params = json::array();
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const Parameter& p = r.parameters[i];
    params.push_back({{"label", p.label()},
                      {"material", p.material},
                      {"name", p.name()},
                      {"lower", p.lower},
                      {"upper", p.upper},
                      {"current", r.current[i]}});
  }
  json outputs = json::array(), entries = json::array();
  for (std::size_t o = 0; o < r.outputs.size(); ++o) outputs.push_back(OutputJson(r, o));
  for (const SensitivityEntry& e : r.entries) entries.push_back(EntryJson(r, e));
  j = {{"site", r.site},
       {"study", "sensitivity"},
       {"method", SensitivityMethodName(r.method)},
       {"design", DesignJson(r)},
       {"seed", r.seed},
       {"rocks", r.rocks},
       {"threads", r.threads},
       {"simulations", r.simulations},
       {"wall_seconds", r.wall_seconds},
       {"simulation_seconds", r.simulation_seconds},
       {"simulations_per_second", r.SimulationsPerSecond()},
       {"non_finite_runs", r.non_finite_runs},
       {"resolved_ratio", kResolvedEffectOverNoise},
       {"definitions", IsMorris(r) ? kMorrisDefinitions : kSobolDefinitions},
       {"parameters", params},
       {"outputs", outputs},
       {"entries", entries},
       {"notes", r.notes},
       {"summary", r.summary}};
}

void from_json(const json& j, SensitivityResult& r) {
  r = SensitivityResult{};
  r.site = j.at("site").get<std::string>();
  const std::string method = j.at("method").get<std::string>();
  if (!ParseSensitivityMethod(method, &r.method))
    throw std::invalid_argument("unknown sensitivity method '" + method + "'");
  r.seed = j.at("seed").get<std::uint64_t>();
  r.rocks = j.at("rocks").get<int>();
  r.threads = j.at("threads").get<int>();
  r.simulations = j.at("simulations").get<int>();
  r.wall_seconds = j.at("wall_seconds").get<double>();
  r.simulation_seconds = j.at("simulation_seconds").get<double>();
  r.non_finite_runs = j.at("non_finite_runs").get<int>();
  for (const json& p : j.at("parameters")) {
    r.parameters.push_back(
        ParameterOf(p.at("material").get<std::string>(), p.at("name").get<std::string>()));
    r.parameters.back().lower = p.at("lower").get<double>();
    r.parameters.back().upper = p.at("upper").get<double>();
    r.current.push_back(p.at("current").get<double>());
  }
  const json& outputs = j.at("outputs");
  ReadDesign(j.at("design"), static_cast<int>(outputs.size()), &r);
  r.samples = IsMorris(r) ? r.morris.trajectories : r.sobol.samples;
  for (const json& o : outputs) ReadOutput(o, &r);
  const json& entries = j.at("entries");
  for (std::size_t e = 0; e < entries.size(); ++e) ReadEntry(entries[e], e, &r);
  r.notes = j.at("notes").get<std::vector<std::string>>();
  r.summary = j.at("summary").get<std::string>();
}

void to_json(json& j, const ReachResult& r) {
  json params = json::array(), stats = json::array(), points = json::array();
  for (const Parameter& p : r.parameters)
    params.push_back({{"label", p.label()}, {"lower", p.lower}, {"upper", p.upper}});
  for (const ReachStatistic& s : r.statistics) stats.push_back(StatisticJson(s));
  for (const ReachPoint& p : r.points) points.push_back(PointJson(p));
  json design = {
      {"kind", DesignKindName(r.design)}, {"points", r.points.size()}, {"seed", r.design_seed}};
  if (r.design == DesignKind::kLatinHypercube) design["candidates"] = r.candidates;
  j = {{"site", r.site},
       {"study", "reach"},
       {"design", design},
       {"simulation_seed", r.simulation_seed},
       {"rocks", r.rocks},
       {"wall_seconds", r.wall_seconds},
       {"rule", kReachRule},
       {"units", "SI (m, or a fraction)"},
       {"parameters", params},
       {"statistics", stats},
       {"in_reach", static_cast<int>(r.statistics.size()) - r.out_of_reach()},
       {"out_of_reach", r.out_of_reach()},
       {"best_point", r.best_point},
       {"points", points},
       {"warnings", OutOfReachWarnings(r)}};
}

void from_json(const json& j, ReachResult& r) {
  r = ReachResult{};
  r.site = j.at("site").get<std::string>();
  const json& design = j.at("design");
  const std::string kind = design.at("kind").get<std::string>();
  if (!ParseDesignKind(kind, &r.design))
    throw std::invalid_argument("unknown design kind '" + kind + "'");
  r.design_seed = design.at("seed").get<std::uint64_t>();
  if (r.design == DesignKind::kLatinHypercube) r.candidates = design.at("candidates").get<int>();
  r.simulation_seed = j.at("simulation_seed").get<std::uint64_t>();
  r.rocks = j.at("rocks").get<int>();
  r.wall_seconds = j.at("wall_seconds").get<double>();
  for (const json& p : j.at("parameters")) {
    r.parameters.push_back(ParameterOfLabel(p.at("label").get<std::string>()));
    r.parameters.back().lower = p.at("lower").get<double>();
    r.parameters.back().upper = p.at("upper").get<double>();
  }
  for (const json& s : j.at("statistics")) r.statistics.push_back(StatisticOf(s));
  r.best_point = j.at("best_point").get<int>();
  for (const json& p : j.at("points")) r.points.push_back(PointOf(p));
}

json ResidualsJson(const observations::Misfit& misfit) {
  json out = json::array();
  for (const observations::Residual& r : misfit.residuals)
    out.push_back({{"observation", r.id.observation()},
                   {"quantity", r.id.quantity()},
                   {"simulated", r.simulated},
                   {"observed", r.observed},
                   {"sigma", r.sigma},
                   {"residual", r.value}});
  return out;
}

void to_json(json& j, const ScoreResult& s) {
  j = {{"site", s.site},
       {"observations", s.observations_file},
       {"parameters", s.parameters_file.empty() ? json(nullptr) : json(s.parameters_file)},
       {"rocks", s.rocks},
       {"seed", s.seed},
       {"misfit", s.misfit.value},
       {"penalised", s.misfit.penalised},
       {"message", s.misfit.message},
       {"outcomes", Outcomes(s.stopped, s.left, s.timeout)},
       {"fit", FitJson(observations::AssessFit(s.misfit))},
       {"residuals", ResidualsJson(s.misfit)}};
}

void from_json(const json& j, ScoreResult& s) {
  s = ScoreResult{};
  s.site = j.at("site").get<std::string>();
  s.observations_file = j.at("observations").get<std::string>();
  const json& parameters = j.at("parameters");
  if (!parameters.is_null()) s.parameters_file = parameters.get<std::string>();
  s.rocks = j.at("rocks").get<int>();
  s.seed = j.at("seed").get<std::uint64_t>();
  s.misfit.value = j.at("misfit").get<double>();
  s.misfit.penalised = j.at("penalised").get<bool>();
  s.misfit.message = j.at("message").get<std::string>();
  const json& o = j.at("outcomes");
  s.stopped = o.at("stopped").get<int>();
  s.left = o.at("left").get<int>();
  s.timeout = o.at("timeout").get<int>();
  for (const json& r : j.at("residuals")) {
    observations::Residual res;
    res.id =
        ResidualIdOf(r.at("observation").get<std::string>(), r.at("quantity").get<std::string>());
    res.simulated = r.at("simulated").get<double>();
    res.observed = r.at("observed").get<double>();
    res.sigma = r.at("sigma").get<double>();
    res.value = r.at("residual").get<double>();
    s.misfit.residuals.push_back(res);
  }
}

}  // namespace rockcal::calibrate
