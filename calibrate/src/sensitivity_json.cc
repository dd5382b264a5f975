// to_json / from_json of SensitivityResult as sensitivity.json holds it
// (results_json.cc says how the result files are read back).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "results_json_fields.h"
#include "rockcal/calibrate/sensitivity.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using nlohmann::json;
using text::JsonNum;
using namespace json_fields;

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

}  // namespace

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
       {"method", SensitivityMethodToString(r.method)},
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
  if (!StringToSensitivityMethod(method, &r.method))
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

}  // namespace rockcal::calibrate
