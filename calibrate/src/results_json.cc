// to_json / from_json of calibrate's results as their files hold them:
// stability.json, convergence.json, sensitivity.json, reach.json and
// score.json. from_json reads back what to_json wrote (a number the file
// holds as null, being unknown, comes back as NaN or, for an error, +inf);
// what the files show besides the struct (counts, the rules in words,
// flags derived from indices) is written, not read.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <utility>

#include "results_json_fields.h"
#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/core/material_field.h"
#include "rockcal/core/numbers.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace json_fields {

using nlohmann::json;
using text::JsonNum;

using core::kInf;
using core::kNaN;

// The number at `key` of `j`; `unknown` where the file holds null.
double Number(const json& j, const char* key, double unknown) {
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
  return {{"verdict", fit.poor   ? "poor"
                      : fit.fair ? "fair"
                                 : "good"},
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

}  // namespace json_fields

namespace {

using namespace json_fields;

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

namespace {

json Vector3(const Eigen::Vector3d& v) {
  return json::array({JsonNum(v.x()), JsonNum(v.y()), JsonNum(v.z())});
}

Eigen::Vector3d Vector3Of(const json& j) {
  const std::vector<double> v = Numbers(j);
  if (v.size() != 3)
    throw std::invalid_argument("an impact's vector has " + std::to_string(v.size()) +
                                " components; expected 3");
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

// One impact's fit read back from ImpactsJson's per_impact entry; its group
// is the index of its name in *groups (added when new).
observations::ImpactFit ImpactFitOf(const json& j, std::vector<std::string>* groups) {
  observations::ImpactFit f;
  f.id = j.at("id").get<std::string>();
  const std::string group = j.at("group").get<std::string>();
  const auto at = std::find(groups->begin(), groups->end(), group);
  f.group = static_cast<int>(at - groups->begin());
  if (at == groups->end()) groups->push_back(group);
  f.incidence_deg = Number(j, "incidence_deg", kNaN);
  f.normal = Vector3Of(j.at("normal"));
  f.observed = Vector3Of(j.at("observed_mps"));
  f.simulated = Vector3Of(j.at("simulated_median_mps"));
  f.speed_sd = Number(j, "speed_sd_mps", kNaN);
  f.draws = j.at("draws").get<int>();
  f.left = j.at("left").get<int>();
  const json& n = j.at("normal_ratio");
  f.normal_observed = Number(n, "observed", kNaN);
  f.normal_simulated = Number(n, "simulated", kNaN);
  f.normal_spread = Number(n, "spread", kNaN);
  f.normal_sigma = Number(n, "sigma", kNaN);
  const json& t = j.at("tangential_ratio");
  f.tangential_observed = Number(t, "observed", kNaN);
  f.tangential_simulated = Number(t, "simulated", kNaN);
  f.tangential_spread = Number(t, "spread", kNaN);
  f.tangential_sigma = Number(t, "sigma", kNaN);
  return f;
}

}  // namespace

std::vector<std::string> GroupIds(const core::Scene& scene) {
  std::vector<std::string> ids;
  for (const core::RockGroup& g : scene.groups) ids.push_back(g.id);
  return ids;
}

json ImpactsJson(const observations::Misfit& misfit, const std::vector<std::string>& group_ids) {
  json per = json::array();
  for (const observations::ImpactFit& f : misfit.impacts) {
    const std::size_t g = static_cast<std::size_t>(f.group);
    const std::string group =
        g < group_ids.size() && !group_ids[g].empty() ? group_ids[g] : std::to_string(f.group);
    // A near-normal impact has no tangential residual (ImpactFit).
    const bool tangential = std::isfinite(f.tangential_observed) && f.tangential_sigma > 0;
    const json none = nullptr;
    per.push_back({{"id", f.id},
                   {"group", group},
                   {"incidence_deg", JsonNum(f.incidence_deg)},
                   {"normal", Vector3(f.normal)},
                   {"observed_mps", Vector3(f.observed)},
                   {"simulated_median_mps", Vector3(f.simulated)},
                   {"speed_sd_mps", JsonNum(f.speed_sd)},
                   {"draws", f.draws},
                   {"left", f.left},
                   {"normal_ratio",
                    {{"observed", JsonNum(f.normal_observed)},
                     {"simulated", JsonNum(f.normal_simulated)},
                     {"spread", JsonNum(f.normal_spread)},
                     {"sigma", JsonNum(f.normal_sigma)}}},
                   {"tangential_ratio",
                    {{"observed", JsonNum(f.tangential_observed)},
                     {"simulated", tangential ? JsonNum(f.tangential_simulated) : none},
                     {"spread", tangential ? JsonNum(f.tangential_spread) : none},
                     {"sigma", tangential ? JsonNum(f.tangential_sigma) : none}}}});
  }
  return {{"verdict", observations::ImpactVerdict(misfit)}, {"per_impact", per}};
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
  if (!s.misfit.impacts.empty()) j["impacts"] = ImpactsJson(s.misfit, s.groups);
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
        observations::ResidualId::Parse(r.at("observation").get<std::string>(), r.at("quantity").get<std::string>());
    res.simulated = r.at("simulated").get<double>();
    res.observed = r.at("observed").get<double>();
    res.sigma = r.at("sigma").get<double>();
    res.value = r.at("residual").get<double>();
    s.misfit.residuals.push_back(res);
  }
  if (const auto impacts = j.find("impacts"); impacts != j.end())
    for (const json& f : impacts->at("per_impact"))
      s.misfit.impacts.push_back(ImpactFitOf(f, &s.groups));
}

}  // namespace rockcal::calibrate
