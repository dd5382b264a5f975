#include "rockcal/calibrate/default_table.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <system_error>

#include "rockcal/core/error.h"
#include "rockcal/core/material_field.h"
#include "rockcal/core/statistics.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::calibrate {
namespace {

namespace fs = std::filesystem;
using sites::FormatNumber;
using sites::Join;

std::string Quote(const std::string& s) { return "'" + s + "'"; }

// A parameter's place in the tables: core::MaterialFields() order.
int NameOrder(const std::string& name) {
  const core::MaterialFieldInfo* f = core::FindMaterialField(name);
  return f ? static_cast<int>(f->field) : static_cast<int>(core::MaterialFields().size());
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
      // The bound test is on the value pooled: a search's point stopped by
      // a bound is no calibrated value, but a posterior that holds such a
      // point still says where the data put the value (its median inside,
      // its interval reaching the bound).
      v.bound = AtBound(v.pooled(), p.lower, p.upper, options.bound_fraction);
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
    all.push_back(v.pooled());
    all_sites.push_back(v.site);
    if (v.counted) {
      counted.push_back(v.pooled());
      counted_sites.push_back(v.site);
    }
    if (v.bound != BoundPosition::kInside) {
      ++row.at_bound;
      table.notes.push_back(
          row.material_class + " " + row.name + ": " + v.site + " (" + v.result_dir +
          ", material " + v.material + ") is at its " + BoundName(v.bound) + " bound (" +
          FormatNumber(v.pooled()) + " in [" + FormatNumber(v.lower) + ", " +
          FormatNumber(v.upper) + "]); " +
          (v.counted ? "counted (--include-at-bound)" : "left out of the statistics"));
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

namespace {

std::vector<std::string> Strings(const sites::JsonNode& node) {
  std::vector<std::string> out;
  for (const sites::JsonNode& v : node.Array()) out.push_back(v.Text());
  return out;
}

}  // namespace

TableAbout ReadTableAbout(const std::string& file) {
  const nlohmann::json json = sites::ReadJsonFile(file);
  const sites::JsonNode root(&json, file, "$");
  root.Keys({"title", "classes", "sites"});
  TableAbout about;
  about.file = file;
  about.title = root.Get("title").Text();
  const sites::JsonNode classes = root.Get("classes");
  if (!classes.is_object()) classes.Fail("expected an object of classes by name");
  for (const auto& [name, value] : classes.raw().items()) {
    const sites::JsonNode c = classes.Get(name.c_str());
    c.Keys({"description", "surface_cover", "grain_size", "vegetation", "references"});
    ClassAbout a;
    a.description = c.Get("description").Text();
    a.surface_cover = c.Get("surface_cover").Text();
    a.grain_size = c.Get("grain_size").Text();
    a.vegetation = c.Get("vegetation").Text();
    a.references = Strings(c.Get("references"));
    about.classes[name] = a;
  }
  const sites::JsonNode site_list = root.Get("sites");
  if (!site_list.is_object()) site_list.Fail("expected an object of sites by name");
  for (const auto& [name, value] : site_list.raw().items()) {
    const sites::JsonNode c = site_list.Get(name.c_str());
    c.Keys({"data", "licence", "command", "observed", "observations", "rockcal_version"});
    SiteAbout a;
    a.data = c.Get("data").Text();
    a.licence = c.Get("licence").Text();
    a.command = c.Get("command").Text();
    a.observed = c.Get("observed").Text();
    a.observations = static_cast<int>(c.Get("observations").Integer(0, 100000000));
    a.rockcal_version = c.Get("rockcal_version").String();
    about.sites[name] = a;
  }
  return about;
}

DefaultTable BuildDefaultTable(const std::vector<CalibratedSite>& sites,
                               const DefaultTableOptions& options, const TableAbout& about) {
  DefaultTable table = BuildDefaultTable(sites, options);
  for (const TableRow& row : table.rows)
    if (!about.classes.count(row.material_class))
      throw InputError(about.file, "$.classes: no class '" + row.material_class +
                                       "'; expected a description of every class of the table");
  for (const CalibratedSite& s : sites)
    if (!about.sites.count(s.site))
      throw InputError(about.file, "$.sites: no site '" + s.site + "' (of " + s.file +
                                       "); expected the data of every site of the table");
  table.about = about;
  return table;
}

}  // namespace rockcal::calibrate
