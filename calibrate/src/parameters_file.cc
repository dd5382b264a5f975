// parameters.json and posterior.csv: the calibrated values of a calibration
// folder, built, written and read back in one place (parameters_file.h).
#include "rockcal/calibrate/parameters_file.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "results_json_fields.h"
#include "rockcal/calibrate/campaign.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/core/error.h"
#include "rockcal/core/material_field.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/json_reader.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

namespace fs = std::filesystem;
using sites::FormatNumber;
using sites::JsonNode;

// A bound of parameter `name` (a known field), checked against its valid
// range (SI, as the site reader checks it; the roughness limit of half the
// grid spacing is checked when the file gives the spacing).
double ReadBoundValue(const JsonNode& node, const std::string& name) {
  const core::MaterialFieldInfo& f = *core::FindMaterialField(name);
  return std::isinf(f.max) ? node.NonNegative() : node.Number(f.min, f.max);
}

CalibratedParameter ReadParameter(const JsonNode& p) {
  p.Keys({"material", "class", "name", "value", "lower", "upper", "std_error", "posterior"});
  CalibratedParameter out;
  {
    const JsonNode m = p.Get("material");
    out.material = m.String();
    if (out.material.empty()) m.Fail("expected a material id (not empty)");
  }
  if (auto c = p.Find("class")) {
    out.material_class = c->String();
    if (out.material_class.empty()) c->Fail("expected a class name (not empty)");
  } else {
    out.material_class = out.material;
    out.class_given = false;
  }
  const JsonNode name = p.Get("name");
  out.name = name.String();
  if (!core::FindMaterialField(out.name))
    name.Fail("unknown parameter name (allowed: " + core::MaterialFieldNames() + ")");
  out.lower = ReadBoundValue(p.Get("lower"), out.name);
  const JsonNode upper = p.Get("upper");
  out.upper = ReadBoundValue(upper, out.name);
  if (!(out.lower < out.upper))
    upper.Fail("expected upper > lower (lower is " + FormatNumber(out.lower) + ")");
  const JsonNode value = p.Get("value");
  out.value = value.Number();
  // The optimisers keep within the bounds; allow for the rounding of %.17g.
  const double slack = 1e-9 * (out.upper - out.lower);
  if (out.value < out.lower - slack || out.value > out.upper + slack)
    value.Fail("expected a value within its bounds [" + FormatNumber(out.lower) + ", " +
               FormatNumber(out.upper) + "]");
  const JsonNode se = p.Get("std_error");
  if (!se.raw().is_null()) {
    if (!se.is_number()) se.Fail("expected a standard error >= 0 or null (not computed)");
    out.std_error = se.NonNegative();
  }
  if (auto post = p.Find("posterior")) {
    post->Keys({"median", "p05", "p95", "determined"});
    CalibratedParameter::Interval q;
    const auto within = [&](const char* key) {
      const JsonNode v = post->Get(key);
      const double x = v.Number();
      if (x < out.lower - slack || x > out.upper + slack)
        v.Fail("expected a value within the parameter's bounds [" + FormatNumber(out.lower) + ", " +
               FormatNumber(out.upper) + "]");
      return x;
    };
    q.median = within("median");
    q.p05 = within("p05");
    q.p95 = within("p95");
    if (!(q.p05 <= q.median && q.median <= q.p95))
      post->Fail("expected p05 <= median <= p95 (p05 " + FormatNumber(q.p05) + ", median " +
                 FormatNumber(q.median) + ", p95 " + FormatNumber(q.p95) + ")");
    q.determined = post->Get("determined").Bool();
    out.posterior = q;
  }
  return out;
}

// Parameter `p` of a parameter space at `value`, with its standard error
// and posterior when given.
CalibratedParameter Calibrated(const Parameter& p, double value, const double* std_error,
                               const ParameterPosterior* posterior) {
  CalibratedParameter out;
  out.material = p.material;
  out.material_class = p.class_name();
  out.name = p.name();
  out.value = value;
  out.lower = p.lower;
  out.upper = p.upper;
  if (std_error) out.std_error = *std_error;
  if (posterior)
    out.posterior = CalibratedParameter::Interval{posterior->median, posterior->p05, posterior->p95,
                                                  !posterior->undetermined};
  return out;
}

constexpr const char* kSamplesFile = "posterior.csv";

nlohmann::json ParameterJson(const CalibratedParameter& p) {
  nlohmann::json out = {
      {"material", p.material},
      {"class", p.material_class},
      {"name", p.name},
      {"value", p.value},
      {"lower", p.lower},
      {"upper", p.upper},
      {"std_error", p.std_error ? nlohmann::json(*p.std_error) : nlohmann::json()}};
  if (p.posterior)
    out["posterior"] = {{"median", p.posterior->median},
                        {"p05", p.posterior->p05},
                        {"p95", p.posterior->p95},
                        {"determined", p.posterior->determined}};
  return out;
}

}  // namespace

const char* SiUnitOf(const CalibratedParameter& parameter) {
  return core::SiUnitName(
      core::Info(json_fields::ParameterOf(parameter.material, parameter.name).kind).unit);
}

CalibratedSite CalibratedSiteOf(const CalibrationSummary& summary) {
  const MethodResult& best = summary.best_method();
  CalibratedSite out;
  out.site = summary.site;
  out.stage = best.stage;
  out.misfit = best.best_misfit;
  out.evaluations = best.evaluations;
  out.wall_seconds = best.wall_seconds;
  if (summary.grid_spacing_m > 0) out.grid_spacing_m = summary.grid_spacing_m;
  const Uncertainty& u = best.uncertainty;
  const auto& ps = summary.space.parameters();
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const bool se = u.computed && !u.rank_deficient && k < u.std_error.size();
    out.parameters.push_back(
        Calibrated(ps[k], best.best[k], se ? &u.std_error[k] : nullptr,
                   summary.posterior ? &summary.posterior->parameters[k] : nullptr));
  }
  if (summary.posterior) out.samples_file = kSamplesFile;
  return out;
}

CalibratedSite CalibratedSiteOf(const CampaignSummary& summary, std::size_t site) {
  const CampaignSiteFit& fit = summary.sites[site];
  const MethodResult& best = summary.calibration.best_method();
  CalibratedSite out;
  out.site = fit.name;
  out.stage = best.stage;
  out.misfit = fit.misfit_joint.value;
  out.evaluations = best.evaluations;
  out.wall_seconds = best.wall_seconds;
  if (fit.grid_spacing_m > 0) out.grid_spacing_m = fit.grid_spacing_m;
  const auto& ps = fit.space.parameters();
  for (std::size_t k = 0; k < ps.size(); ++k)
    out.parameters.push_back(Calibrated(ps[k], fit.calibrated[k], nullptr,
                                        fit.posterior ? &fit.posterior->parameters[k] : nullptr));
  if (fit.posterior) out.samples_file = kSamplesFile;
  return out;
}

nlohmann::json ParameterListJson(const CalibratedSite& site) {
  nlohmann::json list = nlohmann::json::array();
  for (const CalibratedParameter& p : site.parameters) list.push_back(ParameterJson(p));
  return list;
}

nlohmann::json ParametersFileJson(const CalibratedSite& site) {
  nlohmann::json out = {{"site", site.site},
                        {"method", site.stage.name()},
                        {"misfit", site.misfit},
                        {"evaluations", site.evaluations},
                        {"wall_seconds", site.wall_seconds}};
  if (site.grid_spacing_m) out["grid_spacing_m"] = *site.grid_spacing_m;
  out["parameters"] = ParameterListJson(site);
  // rockcal simulate --parameters draws from these (ReadPosteriorSamples).
  if (site.has_posterior())
    out["posterior_samples"] = fs::path(site.samples_file).filename().string();
  return out;
}

std::string PosteriorSamplesCsv(const std::vector<CalibratedParameter>& parameters,
                                const std::vector<std::vector<double>>& samples) {
  std::ostringstream out;
  for (std::size_t k = 0; k < parameters.size(); ++k)
    out << (k ? "," : "") << text::CsvField(parameters[k].material + "." + parameters[k].name);
  out << "\n";
  for (const auto& s : samples) {
    for (std::size_t k = 0; k < s.size(); ++k) out << (k ? "," : "") << text::Num(s[k], "%.8g");
    out << "\n";
  }
  return out.str();
}

CalibratedSite ReadCalibratedSite(const std::string& result_dir) {
  CalibratedSite out;
  out.result_dir = result_dir;
  std::error_code ec;
  if (!fs::is_directory(result_dir, ec))
    throw InputError(result_dir,
                     "no such result folder; expected the --out folder of a "
                     "rockcal calibrate run");
  const std::string file = (fs::path(result_dir) / "parameters.json").string();
  if (!fs::is_regular_file(file, ec))
    throw InputError(file,
                     "missing; expected the parameters.json that rockcal calibrate "
                     "writes (did the calibration finish?)");
  out = ReadParametersFile(file);
  out.result_dir = result_dir;
  return out;
}

CalibratedSite ReadParametersFile(const std::string& path) {
  CalibratedSite out;
  std::error_code ec;
  out.file = fs::is_directory(path, ec) ? (fs::path(path) / "parameters.json").string() : path;
  out.result_dir = fs::path(out.file).parent_path().string();
  sites::CheckInputFile(out.file);  // a FIFO, socket or device: named as such
  if (!fs::is_regular_file(out.file, ec))
    throw InputError(out.file,
                     "no such file; expected the parameters.json that rockcal "
                     "calibrate writes");
  const nlohmann::json json = sites::ReadJsonFile(out.file);
  const JsonNode root(&json, out.file, "$");
  root.Keys({"site", "method", "misfit", "evaluations", "wall_seconds", "grid_spacing_m",
             "parameters", "posterior_samples"});
  {
    const JsonNode site = root.Get("site");
    out.site = site.String();
    if (out.site.empty()) site.Fail("expected a site name (not empty)");
  }
  {
    const JsonNode method = root.Get("method");
    if (!Stage::FromName(method.String(), &out.stage))
      method.Fail("unknown method (expected one of " + MethodNames() +
                  ", with \" (N rocks)\" after it for a refining stage)");
  }
  out.misfit = root.Get("misfit").NonNegative();
  out.evaluations = static_cast<int>(root.Get("evaluations").Integer(0, 1'000'000'000));
  out.wall_seconds = root.Get("wall_seconds").NonNegative();
  if (auto s = root.Find("grid_spacing_m")) out.grid_spacing_m = s->Positive();
  const std::vector<JsonNode> params = root.Get("parameters").Array(1);
  for (const JsonNode& p : params) {
    CalibratedParameter param = ReadParameter(p);
    for (const CalibratedParameter& q : out.parameters) {
      if (q.material == param.material && q.name == param.name)
        p.Fail("parameter " + param.material + "." + param.name +
               " given twice; expected each material's parameter once");
    }
    if (param.name == "roughness" && out.grid_spacing_m &&
        param.upper > *out.grid_spacing_m / 2 * (1 + 1e-9))
      p.Get("upper").Fail("expected a roughness bound <= half the grid spacing (" +
                          FormatNumber(*out.grid_spacing_m / 2) + " m)");
    out.parameters.push_back(std::move(param));
  }
  // A posterior is of every calibrated value or of none.
  std::size_t with = 0;
  for (const CalibratedParameter& p : out.parameters) with += p.posterior.has_value();
  if (with != 0 && with != out.parameters.size()) {
    for (std::size_t k = 0; k < out.parameters.size(); ++k)
      if (!out.parameters[k].posterior)
        params[k].Fail(
            "no \"posterior\" where other parameters have one; expected one for "
            "every parameter or for none");
  }
  if (auto s = root.Find("posterior_samples")) {
    if (with == 0)
      s->Fail("expected no posterior samples' file without a \"posterior\" per parameter");
    const std::string name = s->String();
    if (name.empty()) s->Fail("expected a file name (not empty)");
    out.samples_file = (fs::path(out.result_dir) / name).string();
  } else if (with != 0) {
    out.samples_file = (fs::path(out.result_dir) / kSamplesFile).string();
  }
  return out;
}

std::vector<std::vector<double>> ReadPosteriorSamples(const CalibratedSite& site) {
  const std::string& file = site.samples_file;
  if (file.empty())
    throw InputError(site.file,
                     "no posterior (its parameters have no \"posterior\"); expected "
                     "the parameters.json of rockcal calibrate --posterior");
  sites::CheckInputFile(file);
  std::ifstream in(file);
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || !in)
    throw InputError(file,
                     "no such file; expected the posterior samples (posterior.csv) that "
                     "rockcal calibrate --posterior writes beside " +
                         site.file);
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::string expected;
  for (const CalibratedParameter& p : site.parameters)
    expected += (expected.empty() ? "" : ",") + p.material + "." + p.name;
  if (line != expected)
    throw InputError(file + ": line 1", "header '" + line + "'; expected '" + expected +
                                            "' (the parameters of " + site.file + ", in order)");
  std::vector<std::vector<double>> samples;
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<double> row;
    std::size_t at = 0;
    for (std::size_t k = 0; k < site.parameters.size(); ++k) {
      const std::size_t comma = line.find(',', at);
      const std::string field =
          line.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
      const std::string where = file + ": line " + std::to_string(number) + ", column " +
                                std::to_string(k + 1) + " (" + site.parameters[k].material + "." +
                                site.parameters[k].name + ")";
      char* end = nullptr;
      const double v = std::strtod(field.c_str(), &end);
      if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(v))
        throw InputError(where, "'" + field + "': expected a number");
      const CalibratedParameter& p = site.parameters[k];
      const double slack = 1e-6 * (p.upper - p.lower);
      if (v < p.lower - slack || v > p.upper + slack)
        throw InputError(where, FormatNumber(v) + ": expected a value within the bounds [" +
                                    FormatNumber(p.lower) + ", " + FormatNumber(p.upper) + "]");
      row.push_back(std::clamp(v, p.lower, p.upper));
      const bool last = k + 1 == site.parameters.size();
      if (last != (comma == std::string::npos))
        throw InputError(file + ": line " + std::to_string(number),
                         "expected " + std::to_string(site.parameters.size()) +
                             " comma-separated values (one per parameter)");
      at = comma + 1;
    }
    samples.push_back(std::move(row));
  }
  if (samples.empty())
    throw InputError(file, "no samples; expected a line of values per posterior sample");
  return samples;
}

}  // namespace rockcal::calibrate
