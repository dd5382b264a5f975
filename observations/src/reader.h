// The observations reader's common parts: the file's units, CSV tables,
// partition ids and the one-of-several-keys rule, shared by every kind's
// reader (kinds/); reader.cc reads the file, kind by kind as kinds/kinds.cc
// lists them, then the measurement errors. Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_READER_H_
#define ROCKCAL_OBSERVATIONS_SRC_READER_H_

#include <Eigen/Core>
#include <initializer_list>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::observations {

// "(x, y)".
std::string FormatPoint(const Eigen::Vector2d& p);

// Returns the one key of `keys` present in the object `node`; throws when none
// or more than one is present.
std::string OneOf(const sites::JsonNode& node, std::initializer_list<const char*> keys);

// CSV files: one row per line, fields separated by commas (or, on lines
// without a comma, by blanks); blank lines and lines starting with '#' are
// skipped; the first row is a header when every field starts with a letter.
struct CsvRow {
  int line = 0;
  std::vector<std::string> fields;
};

struct CsvTable {
  std::string file;  // resolved path
  std::vector<CsvRow> rows;
};

// The next row of `in` (skipping blank lines, '#' comments and a UTF-8 byte
// order mark; fields unquoted), with its text for messages; false at the end.
bool NextCsvRow(sites::LineReader* in, CsvRow* row, std::string* text);

[[noreturn]] void CsvFail(const CsvTable& table, const CsvRow& row, const std::string& what);
// Field `i` (named `column`) of `row` as a finite number.
double CsvNumber(const CsvTable& table, const CsvRow& row, std::size_t i, const char* column);
double CsvNonNegative(const CsvTable& table, const CsvRow& row, std::size_t i, const char* column);

class Reader final {
 public:
  Reader(const std::string& path, const core::Scene& scene) : path_(path), scene_(scene) {}

  Observations Load();

  const core::Scene& scene() const { return scene_; }
  sites::Units units() const { return units_; }
  // A length in the file's units, in m.
  double Length(double v) const { return sites::LengthToSI(v, units_); }
  // The CSV file named by the string at `ref`, resolved, checked to be a
  // file and noted as an input.
  std::string CsvFile(const sites::JsonNode& ref) const;
  // The rows of that file, each of exactly `columns` (a header row skipped);
  // throws when it has none.
  CsvTable ReadCsv(const sites::JsonNode& ref, std::initializer_list<const char*> columns) const;

  // Index of the partition named by the string at `node`, or throws listing the ids.
  int FindPartition(const sites::JsonNode& node) const;
  // Index of partition `id`, -1 when the site has none of that id.
  int FindPartition(const std::string& id) const;
  // "partitions of the site: BP-1, BP-2", for messages.
  std::string PartitionIds() const;

 private:
  std::string Resolve(const std::string& file) const;
  // The measurement errors ("error"), after every kind was read.
  void ReadErrors(const sites::JsonNode& root, Observations* obs) const;

  std::string path_;
  const core::Scene& scene_;
  sites::Units units_ = sites::Units::kUS;
  mutable std::vector<std::string> csv_files_;  // the CSV files read, in order
};

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_SRC_READER_H_
