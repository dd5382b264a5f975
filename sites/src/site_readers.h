// The site file's readers by job, beside LoadSite (site.cc): the plan
// polygons, and the rock groups with their release (rock_groups.cc).
// Internal to sites (site.cc; tests/sites/rock_groups_test.cc).
#ifndef ROCKCAL_SITES_SRC_SITE_READERS_H_
#define ROCKCAL_SITES_SRC_SITE_READERS_H_

#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/sites/geometry.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// A plan polygon in file units -> SI; at least 3 vertices, a non-zero area,
// no edge crossing another.
Polygon ReadPolygon(const JsonNode& node, Units units);

// A group's "release" (a zone, or a point with its spread; its height or
// drop elevation; its velocity and spread), checked on `grid`; *note
// describes it.
core::Release ReadRelease(const JsonNode& node, Units units, const core::HeightGrid& grid,
                          std::string* note);

// One entry of "rocks": an inventory's blocks, or a shape (or shape file)
// at a size; its files are added to *inputs (relative to base_dir), *note
// describes it.
core::RockGroup ReadGroup(const JsonNode& node, Units units, const core::HeightGrid& grid,
                          const std::string& base_dir, std::vector<std::string>* inputs,
                          std::string* note);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SRC_SITE_READERS_H_
