// One name table per enum, for parsing and printing (as Ceres' StringToX):
// a constant array of entries, each with the value `id`, its `name` and
// whatever else the table's owner keeps beside them (how a method runs, how
// a case's scene is made). These read any such table.
#ifndef ROCKCAL_CORE_NAME_TABLE_H_
#define ROCKCAL_CORE_NAME_TABLE_H_

#include <cstddef>
#include <string>
#include <vector>

namespace rockcal::core {

// The plain table entry: a value and its name.
template <typename Enum>
struct Named {
  Enum id;
  const char* name;
};

// The entry of `id` in `table`; null for a value not in it.
template <typename Entry, std::size_t N, typename Enum>
const Entry* FindEntry(const Entry (&table)[N], Enum id) {
  for (const Entry& e : table)
    if (e.id == id) return &e;
  return nullptr;
}

// The name of `id`; "" for a value not in the table.
template <typename Entry, std::size_t N, typename Enum>
const char* NameOf(const Entry (&table)[N], Enum id) {
  const Entry* e = FindEntry(table, id);
  return e ? e->name : "";
}

// Sets *id to the value named `name` and returns true; false (and *id left
// alone) for a name not in the table.
template <typename Entry, std::size_t N, typename Enum>
bool IdOf(const Entry (&table)[N], const std::string& name, Enum* id) {
  for (const Entry& e : table)
    if (name == e.name) {
      *id = e.id;
      return true;
    }
  return false;
}

// The names, comma separated, in the table's order (for messages).
template <typename Entry, std::size_t N>
std::string NameList(const Entry (&table)[N]) {
  std::string s;
  for (const Entry& e : table) s += std::string(s.empty() ? "" : ", ") + e.name;
  return s;
}

// The values in the table's order.
template <typename Entry, std::size_t N>
auto IdList(const Entry (&table)[N]) {
  std::vector<decltype(table[0].id)> ids;
  for (const Entry& e : table) ids.push_back(e.id);
  return ids;
}

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_NAME_TABLE_H_
