#include "rockcal/calibrate/default_table.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdlib>
#include <map>
#include <set>
#include <system_error>

#include "rockcal/core/error.h"
#include "rockcal/core/material_field.h"
#include "rockcal/core/statistics.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::calibrate {
namespace {

namespace fs = std::filesystem;
using sites::FormatNumber;
using sites::JsonNode;

// A parameter's place in the tables: core::MaterialFields() order.
int NameOrder(const std::string& name) {
  const core::MaterialFieldInfo* f = core::FindMaterialField(name);
  return f ? static_cast<int>(f->field) : static_cast<int>(core::MaterialFields().size());
}

// A bound of parameter `name` (a known field), checked against its valid
// range (SI, as the site reader checks it; the roughness limit of half the
// grid spacing is checked when the file gives the spacing).
double ReadBoundValue(const JsonNode& node, const std::string& name) {
  const core::MaterialFieldInfo& f = *core::FindMaterialField(name);
  return std::isinf(f.max) ? node.NonNegative() : node.Number(f.min, f.max);
}

std::string Quote(const std::string& s) { return "'" + s + "'"; }

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
        v.Fail("expected a value within the parameter's bounds [" + FormatNumber(out.lower) +
               ", " + FormatNumber(out.upper) + "]");
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

// The folder's absolute path with links and "..", "." and a trailing '/'
// resolved, so that two spellings of one folder compare equal.
std::string Canonical(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(fs::path(path), ec), ec);
  if (ec) return path;
  if (!p.has_filename()) p = p.parent_path();
  return p.string();
}

// Same calibration: same site, method, misfit, evaluations and values.
bool SameCalibration(const CalibratedSite& a, const CalibratedSite& b) {
  if (a.site != b.site || a.stage != b.stage || a.misfit != b.misfit ||
      a.evaluations != b.evaluations || a.parameters.size() != b.parameters.size())
    return false;
  for (std::size_t k = 0; k < a.parameters.size(); ++k) {
    const CalibratedParameter &p = a.parameters[k], &q = b.parameters[k];
    if (p.material != q.material || p.name != q.name || p.value != q.value) return false;
  }
  return true;
}

std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

}  // namespace

BoundPosition AtBound(double value, double lower, double upper, double fraction) {
  const double tolerance = fraction * (upper - lower);
  if (value - lower <= tolerance) return BoundPosition::kAtLower;
  if (upper - value <= tolerance) return BoundPosition::kAtUpper;
  return BoundPosition::kInside;
}

const char* BoundName(BoundPosition position) {
  switch (position) {
    case BoundPosition::kInside:
      return "";
    case BoundPosition::kAtLower:
      return "lower";
    case BoundPosition::kAtUpper:
      return "upper";
  }
  return "";
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
  root.Get("wall_seconds").NonNegative();
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
        params[k].Fail("no \"posterior\" where other parameters have one; expected one for "
                       "every parameter or for none");
  }
  if (auto s = root.Find("posterior_samples")) {
    if (with == 0) s->Fail("expected no posterior samples' file without a \"posterior\" per parameter");
    const std::string name = s->String();
    if (name.empty()) s->Fail("expected a file name (not empty)");
    out.samples_file = (fs::path(out.result_dir) / name).string();
  } else if (with != 0) {
    out.samples_file = (fs::path(out.result_dir) / "posterior.csv").string();
  }
  return out;
}

std::vector<std::vector<double>> ReadPosteriorSamples(const CalibratedSite& site) {
  const std::string& file = site.samples_file;
  if (file.empty())
    throw InputError(site.file, "no posterior (its parameters have no \"posterior\"); expected "
                                "the parameters.json of rockcal calibrate --posterior");
  sites::CheckInputFile(file);
  std::ifstream in(file);
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || !in)
    throw InputError(file, "no such file; expected the posterior samples (posterior.csv) that "
                           "rockcal calibrate --posterior writes beside " + site.file);
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
      const std::string field = line.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
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

bool DefaultTableOptions::IsValid(std::string* error) const {
  if (!(bound_fraction >= 0.0 && bound_fraction < 0.5)) {
    *error = "bound_fraction " + FormatNumber(bound_fraction) + " must lie in [0, 0.5)";
    return false;
  }
  return true;
}

ValueStatistics Statistics(const std::vector<double>& values,
                           const std::vector<std::string>& sites) {
  assert(values.size() == sites.size());
  ValueStatistics s;
  s.values = static_cast<int>(values.size());
  s.sites = static_cast<int>(std::set<std::string>(sites.begin(), sites.end()).size());
  if (values.empty()) return s;
  s.median = core::Median(values);
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  return s;
}

namespace {

// The same folder twice, or two folders holding one calibration, would
// count a calibration twice: an InputError.
void CheckEachCalibrationOnce(const std::vector<CalibratedSite>& sites) {
  for (std::size_t a = 0; a < sites.size(); ++a) {
    for (std::size_t b = 0; b < a; ++b) {
      if (Canonical(sites[a].result_dir) == Canonical(sites[b].result_dir)) {
        throw InputError(sites[a].result_dir, "result folder given twice (also as " +
                                                  sites[b].result_dir +
                                                  "); expected each calibration once");
      }
      if (SameCalibration(sites[a], sites[b])) {
        throw InputError(sites[a].file,
                         "holds the same calibration as " + sites[b].file +
                             " (same site, method, misfit, evaluations and values); expected "
                             "each calibration once");
      }
    }
  }
}

// Notes on the inputs: materials without a class, sites from several folders.
void AddInputNotes(const std::vector<CalibratedSite>& sites, DefaultTable* table_out) {
  DefaultTable& table = *table_out;
  std::map<std::string, std::vector<std::string>> folders_of_site;
  for (const CalibratedSite& s : sites) {
    folders_of_site[s.site].push_back(s.result_dir);
    std::vector<std::string> fallback;
    for (const CalibratedParameter& p : s.parameters)
      if (!p.class_given &&
          std::find(fallback.begin(), fallback.end(), p.material) == fallback.end())
        fallback.push_back(p.material);
    if (!fallback.empty()) {
      table.notes.push_back(s.file + ": no \"class\" on " + Join(fallback) +
                            " (a file written before material classes); each material id stands "
                            "for its class");
    }
  }
  for (const auto& [site, folders] : folders_of_site) {
    if (folders.size() > 1) {
      table.notes.push_back("site " + Quote(site) + " comes from " +
                            std::to_string(folders.size()) + " result folders (" + Join(folders) +
                            "): each of its values is listed and enters the median, but the "
                            "site counts once in \"sites\"");
    }
  }
}

// One row per material class and parameter name, holding every site's value.
std::map<std::pair<std::string, int>, TableRow> CollectRows(
    const std::vector<CalibratedSite>& sites, const DefaultTableOptions& options) {
  std::map<std::pair<std::string, int>, TableRow> rows;
  for (const CalibratedSite& s : sites) {
    for (const CalibratedParameter& p : s.parameters) {
      TableRow& row = rows[{p.material_class, NameOrder(p.name)}];
      row.material_class = p.material_class;
      row.name = p.name;
      TableValue v;
      v.site = s.site;
      v.result_dir = s.result_dir;
      v.material = p.material;
      v.value = p.value;
      v.lower = p.lower;
      v.upper = p.upper;
      v.std_error = p.std_error;
      v.grid_spacing_m = s.grid_spacing_m;
      v.posterior = p.posterior;
      v.bound = AtBound(p.value, p.lower, p.upper, options.bound_fraction);
      v.counted = options.include_at_bound || v.bound == BoundPosition::kInside;
      row.values.push_back(v);
    }
  }
  return rows;
}

// A row's statistics (all values, and the counted ones), with notes on values
// at a bound and on roughness from sites whose virtual spheres are spaced
// differently.
void SummariseRow(TableRow* row_out, DefaultTable* table_out) {
  TableRow& row = *row_out;
  DefaultTable& table = *table_out;
  std::vector<double> all, counted;
  std::vector<std::string> all_sites, counted_sites;
  std::set<double> spacings;
  bool spacing_unknown = false;
  for (const TableValue& v : row.values) {
    all.push_back(v.value);
    all_sites.push_back(v.site);
    if (v.counted) {
      counted.push_back(v.value);
      counted_sites.push_back(v.site);
    }
    if (v.bound != BoundPosition::kInside) {
      ++row.at_bound;
      table.notes.push_back(
          row.material_class + " " + row.name + ": " + v.site + " (" + v.result_dir +
          ", material " + v.material + ") is at its " + BoundName(v.bound) + " bound (" +
          FormatNumber(v.value) + " in [" + FormatNumber(v.lower) + ", " + FormatNumber(v.upper) +
          "]); " + (v.counted ? "counted (--include-at-bound)" : "left out of the statistics"));
    }
    if (!v.grid_spacing_m) {
      spacing_unknown = true;
    } else if (std::none_of(spacings.begin(), spacings.end(), [&](double s) {
                 return std::abs(s - *v.grid_spacing_m) <= 1e-9 * s;  // 12 ft in m, rounded
               })) {
      spacings.insert(*v.grid_spacing_m);
    }
  }
  row.all = Statistics(all, all_sites);
  row.headline = Statistics(counted, counted_sites);
  // The envelope of the counted values' posterior intervals.
  int with = 0, counted_values = 0;
  for (const TableValue& v : row.values) {
    if (!v.counted) continue;
    ++counted_values;
    if (!v.posterior) continue;
    table.any_posterior = true;
    row.posterior_p05 = with ? std::min(*row.posterior_p05, v.posterior->p05) : v.posterior->p05;
    row.posterior_p95 = with ? std::max(*row.posterior_p95, v.posterior->p95) : v.posterior->p95;
    ++with;
  }
  for (const TableValue& v : row.values) table.any_posterior = table.any_posterior || v.posterior;
  row.posterior_values = with;
  if (with == 0 || with != counted_values) {
    if (with > 0)
      table.notes.push_back(row.material_class + " " + row.name + ": " + std::to_string(with) +
                            " of " + std::to_string(counted_values) +
                            " counted values have a posterior; no interval for the row (run "
                            "every calibration with --posterior)");
    row.posterior_p05.reset();
    row.posterior_p95.reset();
  }
  if (row.name == "roughness" && row.values.size() > 1 &&
      (spacings.size() > 1 || spacing_unknown)) {
    std::vector<std::string> list;
    for (double s : spacings) list.push_back(FormatNumber(s) + " m");
    table.notes.push_back(
        row.material_class + " roughness: the values come from virtual spheres of " +
        (spacings.size() > 1 ? "different spacings (" + Join(list) + ")"
                             : std::string("unknown spacing (files without grid_spacing_m)")) +
        "; a roughness means the same ground only at the same sphere spacing (a site's "
        "surface.sphere_spacing, 12 ft unless it sets one, whatever its resolution)");
  }
}

}  // namespace

DefaultTable BuildDefaultTable(const std::vector<CalibratedSite>& sites,
                               const DefaultTableOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("table options", error);
  DefaultTable table;
  table.options = options;
  table.sites = sites;
  CheckEachCalibrationOnce(sites);
  AddInputNotes(sites, &table);
  for (auto& [key, row] : CollectRows(sites, options)) {
    SummariseRow(&row, &table);
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace rockcal::calibrate
