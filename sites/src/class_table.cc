#include "rockcal/sites/class_table.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "rockcal/core/error.h"
#include "rockcal/core/material_field.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// The bytes of sites/tables/default.json (cmake/embed_text.cmake).
extern const unsigned char kDefaultTableBytes[];
extern const std::size_t kDefaultTableLength;

namespace {

// A number, or nullopt for JSON null.
std::optional<double> NumberOrNull(const JsonNode& node) {
  if (node.raw().is_null()) return std::nullopt;
  return node.Number();
}

ClassRow ReadRow(const JsonNode& row) {
  ClassRow r;
  r.parameter = row.Get("parameter").String();
  r.sites = static_cast<int>(row.Get("sites").Integer(0, 1000000));
  r.values = static_cast<int>(row.Get("values").Integer(0, 1000000));
  const std::optional<double> median = NumberOrNull(row.Get("median"));
  r.median = median.value_or(0.0);
  if (auto p = row.Find("posterior"); p && !p->raw().is_null()) {
    r.low = p->Get("p05").Number();
    r.high = p->Get("p95").Number();
    r.interval = "posterior envelope";
  } else if (median) {
    const double lo = row.Get("min").Number(), hi = row.Get("max").Number();
    if (hi > lo) {
      r.low = lo;
      r.high = hi;
      r.interval = "range of calibrated values";
    }
  }
  if (r.low && !(*r.low <= r.median && r.median <= *r.high)) {
    // A table whose medians are of search values (one made by hand, or by
    // rockcal before its rows pooled posterior medians) may have its median
    // outside the posteriors' envelope; the draws then span both.
    r.low = std::min(*r.low, r.median);
    r.high = std::max(*r.high, r.median);
  }
  if (auto entries = row.Find("entries")) {
    for (const JsonNode& e : entries->Array()) {
      if (auto s = e.Find("grid_spacing_m"); s && !s->raw().is_null()) {
        const double v = s->Positive();
        if (std::none_of(r.spacings_m.begin(), r.spacings_m.end(),
                         [&](double x) { return std::abs(x - v) <= 1e-9 * x; }))
          r.spacings_m.push_back(v);
      }
    }
  }
  return r;
}

ClassTable ReadTable(const nlohmann::json& json, const std::string& file) {
  const JsonNode root(&json, file, "$");
  if (!root.is_object()) root.Fail("expected a table.json of rockcal table (an object)");
  ClassTable table;
  table.file = file;
  for (const JsonNode& row : root.Get("rows").Array()) {
    const std::string name = row.Get("class").String();
    ClassRow r = ReadRow(row);
    const core::MaterialFieldInfo* f = core::FindMaterialField(r.parameter);
    if (!f) row.Get("parameter").Fail("expected a material field (" + core::MaterialFieldNames() + ")");
    if (f->forest || r.values == 0) continue;
    auto c = std::find_if(table.classes.begin(), table.classes.end(),
                          [&](const MaterialClass& m) { return m.name == name; });
    if (c == table.classes.end()) {
      table.classes.push_back(MaterialClass{name, "", {}});
      c = table.classes.end() - 1;
    }
    c->rows.push_back(std::move(r));
  }
  if (auto about = root.Find("about")) {
    if (auto classes = about->Find("classes")) {
      for (MaterialClass& c : table.classes)
        if (auto d = classes->Find(c.name.c_str())) c.description = d->Get("description").Text();
    }
  }
  return table;
}

}  // namespace

const ClassRow* MaterialClass::Find(const std::string& parameter) const {
  for (const ClassRow& r : rows)
    if (r.parameter == parameter) return &r;
  return nullptr;
}

const MaterialClass* ClassTable::Find(const std::string& name) const {
  for (const MaterialClass& c : classes)
    if (c.name == name) return &c;
  return nullptr;
}

std::string ClassTable::ClassNames() const {
  std::vector<std::string> names;
  for (const MaterialClass& c : classes) names.push_back(c.name);
  std::sort(names.begin(), names.end());
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? std::string("none") : s;
}

ClassTable ReadClassTable(const std::string& path) {
  std::error_code ec;
  const std::string file = std::filesystem::is_directory(path, ec)
                               ? (std::filesystem::path(path) / "table.json").string()
                               : path;
  const nlohmann::json json = ReadJsonFile(file);
  return ReadTable(json, file);
}

std::string BuiltInClassTableText() {
  return std::string(reinterpret_cast<const char*>(kDefaultTableBytes), kDefaultTableLength);
}

const ClassTable& BuiltInClassTable() {
  static const ClassTable table = [] {
    const nlohmann::json json = nlohmann::json::parse(BuiltInClassTableText());
    return ReadTable(json, kBuiltInTable);
  }();
  return table;
}

}  // namespace rockcal::sites
