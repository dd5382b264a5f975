// Reads the key tables of a file reference (docs/reference/site-file.md,
// observations-file.md): under a heading naming an object's JSON path in
// backticks ("## `$.materials[]`"), rows
// "| `key` | type | unit | range | default | example | meaning |" (the key
// in bold, "**`key`**", when it is required).
#ifndef ROCKCAL_TESTS_SITES_REFERENCE_TABLES_H_
#define ROCKCAL_TESTS_SITES_REFERENCE_TABLES_H_

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rockcal/sites/file_keys.h"

namespace rockcal::testing {

struct ReferenceRow {
  std::vector<std::string> cells;  // key (without backticks), type, unit, range, default, example, meaning
  int line = 0;
};

inline std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// Object path -> its rows, in the file's order.
inline std::map<std::string, std::vector<ReferenceRow>> ReadKeyTables(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, std::vector<ReferenceRow>> tables;
  std::string line, object;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("#", 0) == 0) {
      object.clear();
      const auto open = line.find("`$");
      if (open != std::string::npos) {
        const auto close = line.find('`', open + 1);
        object = line.substr(open + 1, close - open - 1);
        tables[object];
      }
      continue;
    }
    // A key row: "| `key` |" or, for a required key, "| **`key`** |".
    if (object.empty() || (line.rfind("| `", 0) != 0 && line.rfind("| **`", 0) != 0)) continue;
    ReferenceRow row;
    row.line = number;
    std::stringstream cells(line.substr(1));
    std::string cell;
    while (std::getline(cells, cell, '|')) row.cells.push_back(Trim(cell));
    if (!row.cells.empty() && row.cells.back().empty()) row.cells.pop_back();
    if (!row.cells.empty()) {
      std::string& key = row.cells[0];
      if (key.size() >= 4 && key.rfind("**", 0) == 0 && key.substr(key.size() - 2) == "**")
        key = key.substr(2, key.size() - 4);
      if (key.size() >= 2 && key.front() == '`' && key.back() == '`') key = key.substr(1, key.size() - 2);
    }
    tables[object].push_back(row);
  }
  return tables;
}

// Checks the tables of the reference `doc` (relative to the source tree)
// against `objects`.
inline void ExpectReferenceMatches(const std::string& doc,
                                   const std::vector<sites::FileObjectKeys>& objects) {
  const std::string file = std::string(ROCKCAL_SOURCE_DIR) + "/" + doc;
  const auto tables = ReadKeyTables(file);
  ASSERT_FALSE(tables.empty()) << "no key tables in " << file;
  std::set<std::string> paths;
  for (const sites::FileObjectKeys& o : objects) {
    paths.insert(o.path);
    const auto table = tables.find(o.path);
    if (table == tables.end()) {
      ADD_FAILURE() << doc << " has no table headed `" << o.path << "`";
      continue;
    }
    std::set<std::string> documented;
    for (const ReferenceRow& row : table->second) {
      const std::string& key = row.cells[0];
      documented.insert(key);
      EXPECT_EQ(row.cells.size(), 7u)
          << doc << ":" << row.line << ": `" << o.path << "` key '" << key
          << "': expected 7 cells (key, type, unit, range, default, example, meaning)";
      const char* names[] = {"key", "type", "unit", "range", "default", "example", "meaning"};
      for (std::size_t c = 1; c < row.cells.size() && c < 7; ++c)
        EXPECT_FALSE(row.cells[c].empty())
            << doc << ":" << row.line << ": `" << o.path << "` key '" << key << "' has no "
            << names[c];
    }
    std::set<std::string> accepted(o.keys.begin(), o.keys.end());
    for (const std::string& k : accepted)
      EXPECT_TRUE(documented.count(k))
          << "the reader accepts '" << k << "' in `" << o.path << "`, which " << doc
          << " does not list";
    for (const std::string& k : documented)
      EXPECT_TRUE(accepted.count(k)) << doc << " lists '" << k << "' in `" << o.path
                                     << "`, which the reader does not accept";
  }
  for (const auto& [path, rows] : tables)
    EXPECT_TRUE(paths.count(path)) << doc << " has a table for `" << path
                                   << "`, an object the reader does not know";
}

}  // namespace rockcal::testing

#endif  // ROCKCAL_TESTS_SITES_REFERENCE_TABLES_H_
