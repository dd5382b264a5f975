#include "rockcal/reports/default_table_outputs.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "rockcal/core/format.h"
#include "rockcal/core/scene.h"

namespace rockcal::reports {
namespace {

using core::CsvField;
using core::FormatNumber;
using core::kFoot;

using calibrate::BoundPosition;
using calibrate::DefaultTable;
using calibrate::TableRow;
using calibrate::TableValue;
using calibrate::ValueStatistics;

// The unit of a table row's field (core/material_field.h, the one list of
// the fields' names, labels and units); kNone for a name it does not hold.
core::FieldUnit UnitOf(const std::string& name) {
  const core::MaterialFieldInfo* f = core::FindMaterialField(name);
  return f ? f->unit : core::FieldUnit::kNone;
}

const char* SiUnit(const std::string& name) { return core::SiUnitName(UnitOf(name)); }

std::string Label(const std::string& name) {
  const core::MaterialFieldInfo* f = core::FindMaterialField(name);
  return f ? f->label : name;
}

// A value for reading: lengths in m, times in ms, stresses in kPa.
std::string Show(const std::string& name, double v) {
  const core::FieldUnit unit = UnitOf(name);
  const double scale = unit == core::FieldUnit::kTime     ? 1e3
                       : unit == core::FieldUnit::kStress ? 1e-3
                                                          : 1.0;
  return FormatNumber(v * scale, "%.3g");
}
std::string Unit(const std::string& name) {
  switch (UnitOf(name)) {
    case core::FieldUnit::kLength:
      return " m";
    case core::FieldUnit::kTime:
      return " ms";
    case core::FieldUnit::kStress:
      return " kPa";
    case core::FieldUnit::kNone:
      break;
  }
  return "";
}
// A length in feet too, " (0.69 ft)"; "" for other fields.
std::string InFeet(const std::string& name, double v) {
  if (UnitOf(name) != core::FieldUnit::kLength) return "";
  return " (" + FormatNumber(v / kFoot, "%.3g") + " ft)";
}
// "0.21 m (0.69 ft)", "0.4", "5 ms".
std::string ShowOne(const std::string& name, double v) {
  return Show(name, v) + Unit(name) + InFeet(name, v);
}
// "0.15 – 0.3 m (0.49 – 0.98 ft)".
std::string ShowRange(const std::string& name, double lo, double hi) {
  std::string s = Show(name, lo) + " – " + Show(name, hi) + Unit(name);
  if (UnitOf(name) == core::FieldUnit::kLength)
    s +=
        " (" + FormatNumber(lo / kFoot, "%.3g") + " – " + FormatNumber(hi / kFoot, "%.3g") + " ft)";
  return s;
}

// Markdown cell text: '|' would end the cell.
std::string Cell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

nlohmann::json StatsJson(const ValueStatistics& s) {
  const bool any = s.values > 0;
  return {{"sites", s.sites},
          {"values", s.values},
          {"median", any ? nlohmann::json(s.median) : nlohmann::json(nullptr)},
          {"min", any ? nlohmann::json(s.min) : nlohmann::json(nullptr)},
          {"max", any ? nlohmann::json(s.max) : nlohmann::json(nullptr)}};
}

std::string StatsCsv(const ValueStatistics& s) {
  const bool any = s.values > 0;
  return std::to_string(s.sites) + ',' + std::to_string(s.values) + ',' +
         (any ? FormatNumber(s.median) : "") + ',' + (any ? FormatNumber(s.min) : "") + ',' +
         (any ? FormatNumber(s.max) : "");
}

nlohmann::json Optional(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string Percent(double fraction) { return FormatNumber(fraction * 100, "%.3g") + " %"; }

// The Markdown summary table of `stats` (headline or all) per row.
void SummaryTable(const DefaultTable& table, bool headline, std::ostringstream& out) {
  // The posterior envelope is of the counted values: in the headline table only.
  const bool post = headline && table.any_posterior;
  out << "| class | parameter | sites | values | median | min – max |"
      << (post ? " posterior 5 % – 95 % |" : "") << " at a bound |\n"
      << "|---|---|---|---|---|---|" << (post ? "---|" : "") << "---|\n";
  for (const TableRow& row : table.rows) {
    const ValueStatistics& s = headline ? row.headline : row.all;
    out << "| " << Cell(row.material_class) << " | " << Label(row.name) << " | " << s.sites << " | "
        << s.values << " | " << (s.values > 0 ? ShowOne(row.name, s.median) : std::string("–"))
        << " | " << (s.values > 0 ? ShowRange(row.name, s.min, s.max) : std::string("–")) << " | ";
    if (post)
      out << (row.posterior_p05 ? ShowRange(row.name, *row.posterior_p05, *row.posterior_p95)
                                : std::string("–"))
          << " | ";
    out << row.at_bound << " of " << row.values.size() << " |\n";
  }
}

// The distinct sites of a class's counted values, in the order first met.
std::vector<std::string> SitesOfClass(const DefaultTable& table, const std::string& name) {
  std::vector<std::string> out;
  for (const TableRow& row : table.rows)
    if (row.material_class == name)
      for (const TableValue& v : row.values)
        if (v.counted && std::find(out.begin(), out.end(), v.site) == out.end())
          out.push_back(v.site);
  return out;
}

// The observations behind a class: the sum over its sites.
int ObservationsOfClass(const DefaultTable& table, const std::string& name) {
  int n = 0;
  for (const std::string& site : SitesOfClass(table, name)) n += table.about->sites.at(site).observations;
  return n;
}

// table.json's "about": the about file's classes (with the sites and
// observations behind each) and sites.
nlohmann::json AboutJson(const DefaultTable& table) {
  const calibrate::TableAbout& about = *table.about;
  nlohmann::json classes = nlohmann::json::object();
  for (const auto& [name, c] : about.classes) {
    classes[name] = {{"description", c.description},
                     {"surface_cover", c.surface_cover},
                     {"grain_size", c.grain_size},
                     {"vegetation", c.vegetation},
                     {"references", c.references},
                     {"sites", SitesOfClass(table, name)},
                     {"observations", ObservationsOfClass(table, name)}};
  }
  nlohmann::json sites = nlohmann::json::object();
  for (const auto& [name, s] : about.sites) {
    sites[name] = {{"data", s.data},
                   {"licence", s.licence},
                   {"command", s.command},
                   {"observed", s.observed},
                   {"observations", s.observations},
                   {"rockcal_version", s.rockcal_version}};
  }
  return {{"title", about.title}, {"classes", classes}, {"sites", sites}};
}

// table.md's classes and provenance.
void AboutMarkdown(const DefaultTable& table, std::ostringstream& out) {
  const calibrate::TableAbout& about = *table.about;
  out << "\n### Classes\n\n"
      << "| class | what ground | surface cover | grain size | vegetation | sites | observations "
         "| descriptive tables |\n"
      << "|---|---|---|---|---|---|---|---|\n";
  for (const auto& [name, c] : about.classes) {
    std::string sites, refs;
    for (const std::string& s : SitesOfClass(table, name)) sites += (sites.empty() ? "" : ", ") + s;
    for (const std::string& r : c.references) refs += (refs.empty() ? "" : "; ") + r;
    out << "| " << Cell(name) << " | " << Cell(c.description) << " | " << Cell(c.surface_cover)
        << " | " << Cell(c.grain_size) << " | " << Cell(c.vegetation) << " | "
        << Cell(sites.empty() ? "-" : sites) << " | " << ObservationsOfClass(table, name) << " | "
        << Cell(refs) << " |\n";
  }
  out << "\n### Provenance\n\n"
      << "| site | data | licence | observed | calibration | rockcal |\n"
      << "|---|---|---|---|---|---|\n";
  for (const auto& [name, s] : about.sites)
    out << "| " << Cell(name) << " | " << Cell(s.data) << " | " << Cell(s.licence) << " | "
        << Cell(s.observed) << " | `" << Cell(s.command) << "` | " << Cell(s.rockcal_version)
        << " |\n";
}

}  // namespace

nlohmann::json DefaultTableJson(const DefaultTable& table) {
  nlohmann::json folders = nlohmann::json::array();
  for (const calibrate::CalibratedSite& s : table.sites) {
    folders.push_back({{"folder", s.result_dir},
                       {"file", s.file},
                       {"site", s.site},
                       {"method", s.stage.name()},
                       {"misfit", s.misfit},
                       {"evaluations", s.evaluations},
                       {"grid_spacing_m", Optional(s.grid_spacing_m)}});
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const TableRow& row : table.rows) {
    nlohmann::json values = nlohmann::json::array();
    for (const TableValue& v : row.values) {
      values.push_back({{"site", v.site},
                        {"folder", v.result_dir},
                        {"material", v.material},
                        {"value", v.value},
                        {"pooled", v.pooled()},
                        {"lower", v.lower},
                        {"upper", v.upper},
                        {"std_error", Optional(v.std_error)},
                        {"grid_spacing_m", Optional(v.grid_spacing_m)},
                        {"at_bound", v.bound == BoundPosition::kInside
                                         ? nlohmann::json(nullptr)
                                         : nlohmann::json(calibrate::BoundName(v.bound))},
                        {"counted", v.counted}});
      if (table.any_posterior)
        values.back()["posterior"] = v.posterior
                                         ? nlohmann::json{{"median", v.posterior->median},
                                                          {"p05", v.posterior->p05},
                                                          {"p95", v.posterior->p95},
                                                          {"determined", v.posterior->determined}}
                                         : nlohmann::json(nullptr);
    }
    nlohmann::json j = StatsJson(row.headline);
    j["class"] = row.material_class;
    j["parameter"] = row.name;
    j["unit"] = SiUnit(row.name);
    j["at_bound"] = row.at_bound;
    j["all"] = StatsJson(row.all);
    if (table.any_posterior)
      j["posterior"] = row.posterior_p05 ? nlohmann::json{{"p05", *row.posterior_p05},
                                                          {"p95", *row.posterior_p95},
                                                          {"values", row.posterior_values}}
                                         : nlohmann::json(nullptr);
    j["entries"] = values;
    rows.push_back(j);
  }
  nlohmann::json j = {{"bound_fraction", table.options.bound_fraction},
                      {"include_at_bound", table.options.include_at_bound},
                      {"result_folders", folders},
                      {"rows", rows},
                      {"notes", table.notes}};
  if (table.about) j["about"] = AboutJson(table);
  return j;
}

std::string DefaultTableCsv(const DefaultTable& table) {
  std::ostringstream out;
  out << "class,parameter,unit,sites,values,median,min,max,at_bound,"
         "sites_all,values_all,median_all,min_all,max_all"
      << (table.any_posterior ? ",posterior_p05,posterior_p95" : "") << "\n";
  for (const TableRow& row : table.rows) {
    out << CsvField(row.material_class) << ',' << row.name << ',' << SiUnit(row.name) << ','
        << StatsCsv(row.headline) << ',' << row.at_bound << ',' << StatsCsv(row.all);
    if (table.any_posterior)
      out << ',' << (row.posterior_p05 ? FormatNumber(*row.posterior_p05) : "") << ','
          << (row.posterior_p95 ? FormatNumber(*row.posterior_p95) : "");
    out << '\n';
  }
  return out.str();
}

std::string DefaultTableValuesCsv(const DefaultTable& table) {
  std::ostringstream out;
  out << "class,parameter,unit,site,folder,material,value,pooled,lower,upper,std_error,at_bound,"
         "counted"
      << (table.any_posterior ? ",posterior_median,posterior_p05,posterior_p95,determined" : "")
      << "\n";
  for (const TableRow& row : table.rows) {
    for (const TableValue& v : row.values) {
      out << CsvField(row.material_class) << ',' << row.name << ',' << SiUnit(row.name) << ','
          << CsvField(v.site) << ',' << CsvField(v.result_dir) << ',' << CsvField(v.material) << ','
          << FormatNumber(v.value) << ',' << FormatNumber(v.pooled()) << ','
          << FormatNumber(v.lower) << ',' << FormatNumber(v.upper) << ','
          << (v.std_error ? FormatNumber(*v.std_error) : "") << ',' << calibrate::BoundName(v.bound)
          << ',' << (v.counted ? 1 : 0);
      if (table.any_posterior) {
        if (v.posterior)
          out << ',' << FormatNumber(v.posterior->median) << ',' << FormatNumber(v.posterior->p05)
              << ',' << FormatNumber(v.posterior->p95) << ','
              << (v.posterior->determined ? "yes" : "no");
        else
          out << ",,,,";
      }
      out << '\n';
    }
  }
  return out.str();
}

std::string DefaultTableMarkdown(const DefaultTable& table) {
  std::ostringstream out;
  out << "## Default parameters per material class\n\n";
  SummaryTable(table, true, out);
  const std::string tolerance = Percent(table.options.bound_fraction);
  out << "\nMedian, min and max over the calibrated values of " << table.sites.size()
      << " result folder" << (table.sites.size() == 1 ? "" : "s")
      << "; \"sites\" counts distinct sites, \"values\" the values counted. "
      << (table.any_posterior ? "A calibration with a posterior enters with its posterior median "
                                "(\"pooled\" below), one without with its search value. "
                              : "");
  if (table.options.include_at_bound) {
    out << "Values within " << tolerance
        << " of the range of a calibration bound are counted (--include-at-bound).\n";
  } else {
    out << "Values within " << tolerance
        << " of the range of a calibration bound were stopped by the bound, not by the data, "
           "and are left out (--include-at-bound counts them).\n";
  }
  bool any_left_out = false;
  for (const TableRow& row : table.rows)
    any_left_out = any_left_out || row.headline.values != row.all.values;
  if (any_left_out) {
    out << "\n### With the values at a bound\n\n";
    SummaryTable(table, false, out);
  }
  if (table.any_posterior)
    out << "\nPosterior 5 % – 95 %: the envelope of the counted values' posterior intervals (the "
           "lowest 5 % and the highest 95 % quantile; rockcal calibrate --posterior), given when "
           "every counted value has one.\n";
  out << "\n### Values\n\n"
      << "| class | parameter | site | folder | material | search value | std. error |"
      << (table.any_posterior ? " posterior 5 % – 95 % | pooled |" : "")
      << " bounds | at a bound |\n"
      << "|---|---|---|---|---|---|---|" << (table.any_posterior ? "---|---|" : "") << "---|---|\n";
  for (const TableRow& row : table.rows) {
    for (const TableValue& v : row.values) {
      out << "| " << Cell(row.material_class) << " | " << Label(row.name) << " | " << Cell(v.site)
          << " | " << Cell(v.result_dir) << " | " << Cell(v.material) << " | "
          << ShowOne(row.name, v.value) << " | "
          << (v.std_error ? ShowOne(row.name, *v.std_error) : std::string("-"))
          << (table.any_posterior
                  ? " | " +
                        (v.posterior ? ShowRange(row.name, v.posterior->p05, v.posterior->p95) +
                                           (v.posterior->determined ? "" : " (not determined)")
                                     : std::string("-")) +
                        " | " + ShowOne(row.name, v.pooled())
                  : std::string(""))
          << " | [" << Show(row.name, v.lower) << ", " << Show(row.name, v.upper) << "]"
          << Unit(row.name) << " | "
          << (v.bound == BoundPosition::kInside
                  ? std::string("")
                  : std::string(calibrate::BoundName(v.bound)) + (v.counted ? "" : ", left out"))
          << " |\n";
    }
  }
  out << "\n### Result folders\n\n"
      << "| folder | site | method | evaluations | misfit | sphere spacing |\n"
      << "|---|---|---|---|---|---|\n";
  for (const calibrate::CalibratedSite& s : table.sites) {
    out << "| " << Cell(s.result_dir) << " | " << Cell(s.site) << " | " << Cell(s.stage.name())
        << " | " << s.evaluations << " | " << FormatNumber(s.misfit, "%.4g") << " | "
        << (s.grid_spacing_m ? FormatNumber(*s.grid_spacing_m, "%.4g") + " m" : std::string("-"))
        << " |\n";
  }
  if (table.about) AboutMarkdown(table, out);
  if (!table.notes.empty()) {
    out << "\n### Notes\n\n";
    for (const std::string& n : table.notes) out << "- " << n << "\n";
  }
  return out.str();
}

}  // namespace rockcal::reports
