// Material classes from a default table: a site's material may name a
// class ("class": "meadow") instead of giving its values, and takes them
// from a table that `rockcal table` wrote (its table.json): the shipped one,
// sites/tables/default.json, built into rockcal, or the site's own
// ("table": "path/to/table.json"). docs/reference/site-file.md#material-classes
// and docs/default-table.md give the rules and the format.
#ifndef ROCKCAL_SITES_CLASS_TABLE_H_
#define ROCKCAL_SITES_CLASS_TABLE_H_

#include <optional>
#include <string>
#include <vector>

namespace rockcal::sites {

// One (class, parameter) row of a table, SI.
struct ClassRow {
  std::string parameter;  // a ground material's field (core::MaterialFields())
  double median = 0.0;    // the row's headline median of the calibrated values
  // The spread a run draws from: the envelope of the sites' posterior 5-95 %
  // intervals ("posterior envelope"), else the min-max of the calibrated
  // values when they differ ("range of calibrated values"); none ("") when
  // neither is there (one value without a posterior).
  std::optional<double> low, high;
  std::string interval;
  int sites = 0, values = 0;        // supporting the row
  std::vector<double> spacings_m;  // the sphere spacings of its values (known ones)
};

struct MaterialClass {
  std::string name;
  std::string description;  // the table's "about".classes.<name>.description, or ""
  std::vector<ClassRow> rows;
  const ClassRow* Find(const std::string& parameter) const;
};

struct ClassTable {
  std::string file;  // the file read, or kBuiltInTable
  std::vector<MaterialClass> classes;
  const MaterialClass* Find(const std::string& name) const;
  std::string ClassNames() const;  // "bedrock, meadow, soil"
};

// How the built-in table is named in messages and outputs: the repository
// file it was built from.
inline constexpr const char* kBuiltInTable = "sites/tables/default.json (built into rockcal)";

// Reads a table.json of `rockcal table` (its "rows": class, parameter,
// median, min, max, sites, values, posterior, entries[].grid_spacing_m; and
// the optional "about".classes descriptions). A folder means its table.json.
// A missing file, bad JSON or a row whose keys have the wrong type is an
// InputError naming the file and JSON path. Rows of a forest field, and rows
// without a counted value (median null), are skipped.
ClassTable ReadClassTable(const std::string& path);
// The table rockcal carries (sites/tables/default.json at build time).
const ClassTable& BuiltInClassTable();
// The built-in table's bytes as they are (for tests and `rockcal table` checks).
std::string BuiltInClassTableText();

// A material whose values came (in part) from a class table.
struct ClassMaterial {
  std::string material;        // its id
  std::string material_class;  // its class
  std::string table;           // the table's file (ClassTable::file)
  std::string description;     // the class's description
  std::vector<ClassRow> from_table;         // the fields taken from the table (median set)
  std::vector<std::string> explicit_fields;  // the class's fields the site's own values override
  std::vector<std::string> notes;  // e.g. roughness from another sphere spacing, an interval cut
};

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_CLASS_TABLE_H_
