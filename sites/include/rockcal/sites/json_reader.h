// Strict reading of JSON input: every access knows its file and JSON path, so
// every error names them, the value found and what was expected. Objects are
// checked for unknown keys; nothing is silently defaulted.
#ifndef ROCKCAL_SITES_JSON_READER_H_
#define ROCKCAL_SITES_JSON_READER_H_

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/material_field.h"

namespace rockcal::sites {

// Reads and parses a JSON file; a syntax error names the file, line and column.
nlohmann::json ReadJsonFile(const std::string& path);

// A view of one JSON value at a path ("$.rocks[0].size") inside a file.
class JsonNode final {
 public:
  JsonNode(const nlohmann::json* value, std::string file, std::string path);

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const nlohmann::json& raw() const { return *value_; }
  // "file: $.path" for error messages.
  std::string where() const;
  // Throws InputError at this node: "<file>: <path>: <what> (found <value>)".
  [[noreturn]] void Fail(const std::string& what) const;

  bool is_object() const { return value_->is_object(); }
  bool is_array() const { return value_->is_array(); }
  bool is_number() const { return value_->is_number(); }
  bool is_string() const { return value_->is_string(); }

  // Objects. Keys() rejects any key not in `allowed`, naming it and listing
  // the allowed ones.
  void Keys(std::initializer_list<const char*> allowed) const;
  void Keys(const std::vector<const char*>& allowed) const;
  bool Has(const char* key) const;
  JsonNode Get(const char* key) const;  // required
  std::optional<JsonNode> Find(const char* key) const;

  // Scalars (each fails unless the value has that type).
  double Number() const;                    // finite number
  double Number(double lo, double hi) const;  // in [lo, hi]
  double Positive() const;                  // > 0
  double NonNegative() const;               // >= 0
  long Integer(long lo, long hi) const;
  // A string without control characters (U+0000 to U+001F, U+007F): names,
  // ids and file names are written into CSV, Markdown, HTML and the console
  // as they are (docs/reference/site-file.md).
  std::string String() const;
  // A string that may also hold tabs and line breaks (a description, a CRS).
  std::string Text() const;
  bool Bool() const;

  // Arrays.
  std::vector<JsonNode> Array(std::size_t min_size = 0) const;
  // An array of exactly n numbers.
  std::vector<double> Numbers(std::size_t n) const;

 private:
  std::string StringAllowing(const char* allowed) const;
  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

// A number for messages: shortest form with up to 10 significant digits
// ("0.3048", "12", "1e-05").
using core::FormatNumber;

// Unit conversions of the site and observation files.
enum class Units { kUS, kSI };
// Reads "units": "us" | "si".
Units ReadUnits(const JsonNode& node);
// Length in the file's units -> metres.
double LengthToSI(double value, Units units);
// The files' length unit: "ft" or "m".
const char* LengthUnit(Units units);
// A length [m] as the files give it, with its unit: "12 ft", "3.6576 m"
// (`format` as FormatNumber's).
std::string LengthText(double metres, Units units, const char* format = "%.10g");
// A mass [kg] in the files' system, with its unit: "12 kg", "26.5 lb".
std::string MassText(double kg, Units units, const char* format = "%.10g");
// A unit weight [N/m^3] as the files give it: "26 kN/m^3", "165 lbf/ft^3".
std::string UnitWeightText(double n_per_m3, Units units);
// Unit weight in the file's units (lbf/ft^3 or kN/m^3) -> N/m^3.
double UnitWeightToSI(double value, Units units);
// Stress in the file's units (lbf/ft^2 or kPa) -> Pa.
double StressToSI(double value, Units units);
// The files' stress unit: "lbf/ft^2" or "kPa".
const char* StressUnit(Units units);
// A material field's value in the file's units -> SI, by the field's unit
// (core/material_field.h): lengths and stresses converted, the rest as given.
double FieldToSI(double value, core::FieldUnit unit, Units units);
// The file's unit of a material field (core/material_field.h): "" for a
// number, "ft" or "m", "s", "lbf/ft^2" or "kPa".
const char* FieldUnitText(core::FieldUnit unit, Units units);

// Physical plausibility (core/limits.h): fails at `node` unless lo <= value
// <= hi, all three in SI; `what` names the quantity and `kind` says how to
// show it in the file's units; `why`, if given, ends the message. The
// message names file, path, value and range.
enum class Quantity { kLength, kSpeed, kUnitWeight, kTime, kStress };
double NumberInRange(const JsonNode& node, double value, double lo, double hi, const char* what,
                     Quantity kind, Units units, const char* why = nullptr);
// A coordinate (file units) of a point -> SI, within +-kMaxCoordinate.
double CoordinateToSI(const JsonNode& node, Units units);
// The n coordinates of `node` (an array of n numbers) -> SI, each within
// +-kMaxCoordinate.
std::vector<double> CoordinatesToSI(const JsonNode& node, std::size_t n, Units units);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_JSON_READER_H_
