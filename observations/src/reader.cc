#include "reader.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <utility>

#include "kinds/kinds.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/observations/file_keys.h"
#include "rockcal/sites/input_file.h"

namespace rockcal::observations {

using sites::FormatNumber;
using sites::JsonNode;

std::string FormatPoint(const Eigen::Vector2d& p) {
  return "(" + FormatNumber(p.x()) + ", " + FormatNumber(p.y()) + ")";
}

namespace {

std::string QuotedList(std::initializer_list<const char*> keys) {
  std::string out;
  for (const char* k : keys) out += std::string(out.empty() ? "'" : ", '") + k + "'";
  return out;
}

bool LooksLikeHeader(const std::vector<std::string>& fields) {
  for (const std::string& f : fields) {
    if (f.empty()) return false;
    const unsigned char c = static_cast<unsigned char>(f[0]);
    if (!std::isalpha(c) && c != '_') return false;
  }
  return true;
}

std::string ColumnList(std::initializer_list<const char*> columns) {
  std::string out;
  for (const char* c : columns) out += std::string(out.empty() ? "" : ", ") + c;
  return out;
}

}  // namespace

std::string OneOf(const JsonNode& node, std::initializer_list<const char*> keys) {
  std::vector<std::string> present;
  for (const char* k : keys) {
    if (node.Has(k)) present.emplace_back(k);
  }
  if (present.empty()) {
    throw InputError(node.where(),
                     "missing required key (expected exactly one of " + QuotedList(keys) + ")");
  }
  if (present.size() > 1) {
    throw InputError(node.where(), "keys '" + present[0] + "' and '" + present[1] +
                                       "' both given (expected exactly one of " + QuotedList(keys) +
                                       ")");
  }
  return present[0];
}

bool NextCsvRow(sites::LineReader* in, CsvRow* row, std::string* text) {
  std::string line;
  while (in->Next(&line)) {
    if (in->line() == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (sites::IsBlank(line)) continue;
    *text = line.substr(line.find_first_not_of(" \t"));
    if ((*text)[0] == '#') continue;
    *row = CsvRow{in->line(), sites::SplitFields(*text)};
    for (std::string& f : row->fields)
      if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    return true;
  }
  return false;
}

void CsvFail(const CsvTable& table, const CsvRow& row, const std::string& what) {
  throw InputError(table.file + ":" + std::to_string(row.line), what);
}

double CsvNumber(const CsvTable& table, const CsvRow& row, std::size_t i, const char* column) {
  double v = 0.0;
  if (!sites::ParseNumber(row.fields[i], &v)) {
    CsvFail(table, row,
            std::string("expected a number for '") + column + "' (found " +
                sites::Excerpt(row.fields[i]) + ")");
  }
  if (!(std::abs(v) <= core::kMaxCoordinate)) {
    CsvFail(table, row,
            std::string("'") + column + "' " + sites::Excerpt(row.fields[i]) +
                " is outside the physically sensible range; expected within +-" +
                FormatNumber(core::kMaxCoordinate));
  }
  return v;
}

double CsvNonNegative(const CsvTable& table, const CsvRow& row, std::size_t i, const char* column) {
  const double v = CsvNumber(table, row, i, column);
  if (v < 0) {
    CsvFail(table, row,
            std::string("expected '") + column + "' >= 0 (found " + row.fields[i] + ")");
  }
  return v;
}

std::string Reader::Resolve(const std::string& file) const {
  const std::filesystem::path p(file);
  if (p.is_absolute()) return file;
  const std::filesystem::path base = std::filesystem::path(path_).parent_path();
  return base.empty() ? file : (base / p).string();
}

std::string Reader::CsvFile(const JsonNode& ref) const {
  const std::string name = ref.String();
  if (name.empty()) ref.Fail("expected a CSV file name");
  const std::string file = Resolve(name);
  if (const std::string problem = sites::InputFileProblem(file, "CSV file"); !problem.empty())
    ref.Fail(problem);
  csv_files_.push_back(file);
  return file;
}

CsvTable Reader::ReadCsv(const JsonNode& ref, std::initializer_list<const char*> columns) const {
  CsvTable table;
  table.file = CsvFile(ref);
  sites::LineReader in(table.file);
  CsvRow row;
  std::string text;
  bool first = true;
  while (NextCsvRow(&in, &row, &text)) {
    if (first) {
      first = false;
      if (LooksLikeHeader(row.fields)) continue;
    }
    if (row.fields.size() != columns.size()) {
      CsvFail(table, row,
              "expected " + std::to_string(columns.size()) + " value" +
                  (columns.size() == 1 ? "" : "s") + " per row (" + ColumnList(columns) +
                  "), found " + std::to_string(row.fields.size()) + " in " + sites::Excerpt(text));
    }
    table.rows.push_back(std::move(row));
  }
  if (table.rows.empty()) {
    throw InputError(table.file, "no data rows (expected rows of " + ColumnList(columns) +
                                     "; referenced at " + ref.where() + ")");
  }
  return table;
}

std::string Reader::PartitionIds() const {
  if (scene_.partitions.empty()) return "the site has no partitions";
  std::string ids;
  for (const core::Partition& p : scene_.partitions) ids += (ids.empty() ? "" : ", ") + p.id;
  return "partitions of the site: " + ids;
}

int Reader::FindPartition(const std::string& id) const {
  for (std::size_t i = 0; i < scene_.partitions.size(); ++i) {
    if (scene_.partitions[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

int Reader::FindPartition(const JsonNode& node) const {
  const int index = FindPartition(node.String());
  if (index < 0) node.Fail("unknown partition id (" + PartitionIds() + ")");
  return index;
}

void Reader::ReadErrors(const JsonNode& root, Observations* obs) const {
  const auto error = root.Find("error");
  if (error) {
    error->Keys(ObservationsKeysAt("$.error"));
    for (const kinds::Kind& kind : kinds::Kinds())
      if (kind.read_error) kind.read_error(*this, *error, obs);
  }
  if (!error) {
    for (const kinds::Kind& kind : kinds::Kinds()) {
      if (kind.missing_error && !kind.missing_error(*obs, nullptr).empty()) {
        throw InputError(root.where(),
                         "missing required key 'error' (the one-sigma measurement errors in the "
                         "file's units: 'height' for tree_scars, 'runout' for runout)");
      }
    }
  }
  const std::string error_where = error ? error->where() : root.where();
  for (const kinds::Kind& kind : kinds::Kinds()) {
    if (!kind.missing_error) continue;
    const std::string missing = kind.missing_error(*obs, error ? &*error : nullptr);
    if (!missing.empty()) throw InputError(error_where, missing);
  }
}

Observations Reader::Load() {
  const nlohmann::json doc = sites::ReadJsonFile(path_);
  const JsonNode root(&doc, path_, "$");
  root.Keys(ObservationsKeysAt("$"));

  Observations obs;
  obs.path = path_;
  units_ = sites::ReadUnits(root.Get("units"));
  obs.units = units_;

  for (const kinds::Kind& kind : kinds::Kinds())
    if (kind.read) kind.read(*this, root, &obs);

  if (obs.empty()) {
    throw InputError(root.where(),
                     "no observations (expected at least one of 'tree_scars', 'runout', "
                     "'passing', 'passing_file')");
  }
  ReadErrors(root, &obs);

  obs.inputs.push_back(path_);
  obs.inputs.insert(obs.inputs.end(), csv_files_.begin(), csv_files_.end());
  return obs;
}

Observations LoadObservations(const std::string& path, const core::Scene& scene) {
  return Reader(path, scene).Load();
}

}  // namespace rockcal::observations
