// to_json / from_json of ReachResult as reach.json holds it
// (results_json.cc says how the result files are read back).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "results_json_fields.h"
#include "rockcal/calibrate/reach.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using nlohmann::json;
using text::JsonNum;
using namespace json_fields;

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
  s.id = observations::ResidualId::Parse(j.at("observation").get<std::string>(), j.at("quantity").get<std::string>());
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
  return {{"unit", p.unit},
          {"physical", p.physical},
          {"misfit", JsonNum(p.misfit)},
          {"penalised", p.penalised},
          {"message", p.message},
          {"simulated", Numbers(p.simulated)},
          {"sigma", Numbers(p.sigma)},
          {"log_scale", JsonNum(p.log_scale)}};
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
  if (j.contains("log_scale")) p.log_scale = Number(j, "log_scale");  // absent: not known
  return p;
}

}  // namespace

void to_json(json& j, const ReachResult& r) {
  json params = json::array(), stats = json::array(), points = json::array();
  for (const Parameter& p : r.parameters)
    params.push_back({{"label", p.label()}, {"lower", p.lower}, {"upper", p.upper}});
  for (const ReachStatistic& s : r.statistics) stats.push_back(StatisticJson(s));
  for (const ReachPoint& p : r.points) points.push_back(PointJson(p));
  json design = {
      {"kind", DesignKindToString(r.design)}, {"points", r.points.size()}, {"seed", r.design_seed}};
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
  if (!StringToDesignKind(kind, &r.design))
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

}  // namespace rockcal::calibrate
