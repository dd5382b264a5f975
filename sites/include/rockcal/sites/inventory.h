// Block inventories: the blocks of a field test, one per row, as a rock
// group's rocks (site file: "inventory" in a rock group).
#ifndef ROCKCAL_SITES_INVENTORY_H_
#define ROCKCAL_SITES_INVENTORY_H_

#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// Reads a block inventory: a header row naming the columns `mass`, `L1`,
// `L2`, `L3` and optionally `shape` (any order, case-insensitive), then one
// block per row, comma or blank separated; blank rows and rows starting with
// '#' are skipped. Mass in kg (units "si") or lb ("us"), sides in m or ft;
// the sides are sorted so that L1 >= L2 >= L3. `shape` is one of
// core::ShapeNames() (default "box": a box of the measured sides; a named
// shape takes L1 as its size). Every error names "file:LINE", the value and
// what was expected; an empty inventory is an error. With `shape_files`,
// a `shape` holding a '.' or a '/' is a shape file's name (core::Shape::kScanned,
// the name in (*shape_files)[row], "" for the other rows), for the caller to load.
std::vector<core::Block> ReadInventory(const std::string& path, Units units,
                                       std::vector<std::string>* shape_files = nullptr);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_INVENTORY_H_
