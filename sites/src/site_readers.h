// The site file's readers by job, beside LoadSite (site.cc): the plan
// polygons, and the rock groups with their release (rock_groups.cc).
// Internal to sites (site.cc; tests/sites/rock_groups_test.cc).
#ifndef ROCKCAL_SITES_SRC_SITE_READERS_H_
#define ROCKCAL_SITES_SRC_SITE_READERS_H_

#include <functional>

#include <cstdint>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/sites/geometry.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/site.h"

namespace rockcal::sites {

// A plan polygon in file units -> SI; at least 3 vertices, a non-zero area,
// no edge crossing another.
Polygon ReadPolygon(const JsonNode& node, Units units);

// Reads a release's "zone_file" node: the polygon (SI) and its place in
// the file (ReadReleaseFile of zone_files.h, bound to the site).
using ZoneFileReader = std::function<Polygon(const JsonNode& node, std::string* where)>;

// A group's "release" (a zone, inline or from a file read by
// `read_zone_file`, or a point with its spread; its height or drop
// elevation; its velocity and spread), checked on `grid`; *note describes
// it. A "zone_file" without `read_zone_file` is refused.
core::Release ReadRelease(const JsonNode& node, Units units, const core::HeightGrid& grid,
                          std::string* note, const ZoneFileReader& read_zone_file = {});

// One entry of "rocks": an inventory's blocks, or a shape (or shape file)
// at a size; its files are added to *inputs (relative to base_dir), *note
// describes it.
core::RockGroup ReadGroup(const JsonNode& node, Units units, const core::HeightGrid& grid,
                          const std::string& base_dir, std::vector<std::string>* inputs,
                          std::string* note, const ZoneFileReader& read_zone_file = {});

// The forest's limits (docs/reference/site-file.md, `$.forest`).
inline constexpr double kMinDbhCm = 1.0;              // a tree file's or inline stem's
inline constexpr double kMinStandDbhCm = 5.0;         // a stand's draws are redrawn below it
inline constexpr double kMaxDbhCm = 300.0;            // larger is taken for a unit error
inline constexpr double kDefaultStemHeightM = 20.0;   // where a stem gives none
inline constexpr double kMaxStemHeightM = 120.0;
inline constexpr double kMaxStemsPerHa = 10000.0;
// Random streams of the stands' draws: stand k draws from (seed,
// kStandStreams + k), apart from every rock's (group << 32 | index).
inline constexpr std::uint64_t kStandStreams = std::uint64_t{1} << 62;

// [lo, hi] of a "calibrate" entry for field `name` of `material` (a
// material id, or core::kForestEntry), in the file's units (`to_si` to SI,
// `unit` after numbers in messages), checked against [min, max] (open at min
// with `open_min`) and the current value.
ParameterBound ReadBound(const JsonNode& node, const std::string& material,
                         const std::string& material_class, const char* name, double min,
                         double max, bool open_min, double value, double to_si,
                         const std::string& unit);

// "forest": a tree file, inline trees and stands (drawn from the seed of
// site->scene.options), checked on site->scene.grid, into
// site->scene.forest; sets site->drawn_stems_first and adds the tree file
// to site->inputs; its "calibrate" bounds go to site->calibrate, for the
// entry core::kForestEntry.
void ReadForest(const JsonNode& node, Units units, const std::string& base_dir, Site* site);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SRC_SITE_READERS_H_
