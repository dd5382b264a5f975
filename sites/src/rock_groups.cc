// The site file's "rocks": each group's bodies (an inventory's blocks, a
// shape or a scanned shape at a size) and its release.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include "rockcal/core/limits.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/polygon.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/inventory.h"
#include "rockcal/sites/shape_file.h"
#include "rockcal/sites/surface.h"
#include "site_readers.h"

namespace rockcal::sites {
namespace {

// What a release's messages name: the site's length unit and the terrain's extent.
struct ReleaseText {
  double to_file = 1.0;  // m -> file units
  std::string grid;      // "the terrain spans x .. to .., y .. to .."
  std::string At(const Eigen::Vector2d& p) const {
    return "(" + FormatNumber(p.x() * to_file) + ", " + FormatNumber(p.y() * to_file) + ")";
  }
};

// A release zone (`zone`, SI; from the node `z`): on the terrain. Returns
// its centre.
Eigen::Vector2d ReadReleaseZone(const JsonNode& z, Polygon zone, Units units,
                                const core::HeightGrid& grid, const ReleaseText& text,
                                core::Release* r, std::string* note) {
  r->zone = std::move(zone);
  if (auto off = FindOffTerrain(grid, r->zone, grid.spacing / 4)) {
    z.Fail("release zone point " + text.At(*off) + " is off the terrain (outside the grid or " +
           "over a hole; " + text.grid + "); expected a zone entirely on the terrain");
  }
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& v : r->zone) centre += v;
  centre /= static_cast<double>(r->zone.size());
  *note = "zone of " + std::to_string(r->zone.size()) + " vertices, area " +
          FormatNumber(std::abs(SignedArea(r->zone)) * text.to_file * text.to_file) + " " +
          LengthUnit(units) + "^2";
  return centre;
}

// A release point on the terrain, and the disc of its "position_spread".
// Returns the point.
Eigen::Vector2d ReadReleasePoint(const JsonNode& node, Units units, const core::HeightGrid& grid,
                                 const ReleaseText& text, core::Release* r, std::string* note) {
  const JsonNode p = node.Get("point");
  const std::vector<double> xy = p.Numbers(2);
  r->point = Eigen::Vector2d(LengthToSI(xy[0], units), LengthToSI(xy[1], units));
  if (!OnTerrain(grid, r->point.x(), r->point.y())) {
    p.Fail("release point is off the terrain (outside the grid or over a hole; " + text.grid +
           "); expected a point on the terrain");
  }
  *note = "point (" + FormatNumber(r->point.x() * text.to_file) + ", " +
          FormatNumber(r->point.y() * text.to_file) + ") " + LengthUnit(units);
  if (const auto spread = node.Find("position_spread")) {
    // A tracked release is known within an error: each rock starts at a
    // point drawn uniformly from the disc of this radius about the point
    // (core::DiscPolygon, released as a zone).
    const double radius = NumberInRange(*spread, LengthToSI(spread->NonNegative(), units), 0,
                                        1000.0, "release position spread", Quantity::kLength, units);
    if (radius > 0) {
      r->zone = core::DiscPolygon(r->point, radius);
      if (auto off = FindOffTerrain(grid, r->zone, grid.spacing / 4))
        spread->Fail("the disc of this radius about the release point reaches " + text.At(*off) +
                     ", off the terrain (" + text.grid + "); expected a disc on the terrain");
      *note += " within " + LengthText(radius, units) + " (uniform in the disc)";
    }
  }
  return r->point;
}

// The release's "height" above the ground, or its drop "elevation": above
// the ground everywhere in the zone (its vertices and `centre`), and within
// reach of it.
void ReadReleaseHeight(const JsonNode& node, Units units, const core::HeightGrid& grid,
                       const Eigen::Vector2d& centre, const ReleaseText& text, core::Release* r,
                       std::string* note) {
  if (auto h = node.Find("height"))
    r->height = NumberInRange(*h, LengthToSI(h->NonNegative(), units), 0, core::kMaxCoordinate,
                              "release height", Quantity::kLength, units);
  if (auto e = node.Find("elevation")) {
    r->elevation = LengthToSI(e->Number(), units);
    std::vector<Eigen::Vector2d> where = r->zone;
    where.push_back(centre);
    double ground_max = -std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2d& p : where)
      if (const std::optional<double> z = ElevationAt(grid, p.x(), p.y()))
        ground_max = std::max(ground_max, *z);
    if (!(*r->elevation >= ground_max && *r->elevation <= ground_max + 1000.0)) {
      e->Fail("the ground of the release reaches " + FormatNumber(ground_max * text.to_file) +
              " " + LengthUnit(units) +
              "; expected a drop elevation at or above it (and at most 1 km above it)");
    }
    *note += ", dropped from elevation " + LengthText(*r->elevation, units);
  }
}

// A release "velocity" or "velocity_spread" (`spread`: each component >= 0).
Eigen::Vector3d ReadReleaseVelocity(const JsonNode& v, Units units, bool spread) {
  const std::vector<double> vel = v.Numbers(3);
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    out[k] = LengthToSI(vel[static_cast<std::size_t>(k)], units);
    if (spread && !(out[k] >= 0)) v.Fail("expected three spreads >= 0 (one sigma per component)");
  }
  NumberInRange(v, out.norm(), 0, core::kMaxSpeed,
                spread ? "release velocity spread" : "release speed", Quantity::kSpeed, units);
  return out;
}

}  // namespace

core::Release ReadRelease(const JsonNode& node, Units units, const core::HeightGrid& grid,
                          std::string* note, const ZoneFileReader& read_zone_file) {
  node.Keys(SiteKeysAt("$.rocks[].release"));
  core::Release r;
  if (node.Has("position_spread") && !node.Has("point"))
    node.Get("position_spread").Fail("goes with a release 'point' only (a zone is already spread)");
  if (node.Has("height") && node.Has("elevation"))
    node.Fail("expected 'height' (above the ground) or 'elevation' (absolute), not both");
  const bool has_zone = node.Has("zone"), has_file = node.Has("zone_file"),
             has_point = node.Has("point");
  if (int{has_zone} + int{has_file} + int{has_point} != 1)
    node.Fail(
        "expected exactly one of 'zone' (plan polygon), 'zone_file' (a polygon of a GIS file) "
        "or 'point' ([x, y])");
  if (has_file && !read_zone_file)
    node.Get("zone_file").Fail("a release zone file is read with its site (expected 'zone')");
  ReleaseText text;
  text.to_file = 1.0 / LengthToSI(1.0, units);
  text.grid = "the terrain spans x " + FormatNumber(grid.x(0) * text.to_file) + " to " +
              FormatNumber(grid.x(grid.nx - 1) * text.to_file) + ", y " +
              FormatNumber(grid.y(0) * text.to_file) + " to " +
              FormatNumber(grid.y(grid.ny - 1) * text.to_file);
  Eigen::Vector2d centre;
  if (has_zone) {
    const JsonNode z = node.Get("zone");
    centre = ReadReleaseZone(z, ReadPolygon(z, units), units, grid, text, &r, note);
  } else if (has_file) {
    const JsonNode z = node.Get("zone_file");
    std::string where;
    Polygon polygon = read_zone_file(z, &where);
    centre = ReadReleaseZone(z, std::move(polygon), units, grid, text, &r, note);
    *note += " (" + where + ")";
  } else {
    centre = ReadReleasePoint(node, units, grid, text, &r, note);
  }
  if (const std::optional<double> z = ElevationAt(grid, centre.x(), centre.y()))
    *note += ", ground " + LengthText(*z, units);
  ReadReleaseHeight(node, units, grid, centre, text, &r, note);
  if (auto v = node.Find("velocity")) r.velocity = ReadReleaseVelocity(*v, units, false);
  if (auto v = node.Find("velocity_spread"))
    r.velocity_spread = ReadReleaseVelocity(*v, units, true);
  return r;
}

namespace {

using ShapeCache = std::map<std::string, std::shared_ptr<const core::ScannedShape>>;

// The clump options of a rock group: its "spheres" (the budget), if any.
core::ClumpOptions ReadClumpOptions(const JsonNode& node) {
  core::ClumpOptions options;
  if (auto n = node.Find("spheres")) options.spheres = static_cast<int>(n->Integer(1, 64));
  return options;
}

// A shape file named in a site: loaded once per resolved path.
std::shared_ptr<const core::ScannedShape> LoadShapeOnce(const std::string& file, Units units,
                                                        const core::ClumpOptions& options,
                                                        ShapeCache* cache,
                                                        std::vector<std::string>* inputs) {
  auto it = cache->find(file);
  if (it != cache->end()) return it->second;
  auto shape = LoadScannedShape(file, LengthToSI(1.0, units), options);
  inputs->push_back(file);
  cache->emplace(file, shape);
  return shape;
}

// How an inventory's scanned shapes take each block's size.
enum class ShapeScale { kSides, kMass };
constexpr std::pair<ShapeScale, const char*> kShapeScales[] = {{ShapeScale::kSides, "sides"},
                                                               {ShapeScale::kMass, "mass"}};

std::string FitSummary(const core::ScannedShape& s) {
  const core::Clump& c = s.clump;
  char text[200];
  std::snprintf(text, sizeof text,
                ": %zu spheres, union volume %+.2f %%, moments within %.2f %%, sides within "
                "%.1f %% of the hull's",
                c.centres.size(), 100.0 * c.volume_error, 100.0 * c.moment_error,
                100.0 * c.side_error);
  return s.name + text;
}

// How an inventory group's scanned shapes are fitted and scaled.
struct InventoryShapes {
  std::string library;  // the folder of the shape files
  core::ClumpOptions clump;
  ShapeScale scale = ShapeScale::kSides;
  double unit_weight = 0.0;  // N/m^3, with ShapeScale::kMass
};

InventoryShapes ReadInventoryShapes(const JsonNode& node, Units units,
                                    const std::string& base_dir) {
  InventoryShapes shapes;
  // Scanned shapes: from the library folder ("shapes", relative to the
  // site file) or else beside the site file.
  shapes.library = base_dir;
  if (auto lib = node.Find("shapes")) {
    shapes.library = ResolvePath(base_dir, lib->String());
    if (!std::filesystem::is_directory(shapes.library))
      lib->Fail("shape library '" + shapes.library + "' is not a folder");
  }
  shapes.clump = ReadClumpOptions(node);
  if (auto sc = node.Find("shape_scale")) {
    const std::string name = sc->String();
    bool found = false;
    for (const auto& [value, label] : kShapeScales)
      if (name == label) shapes.scale = value, found = true;
    if (!found) sc->Fail("unknown shape_scale '" + name + "' (allowed: sides, mass)");
  }
  if (auto uw = node.Find("unit_weight")) {
    if (shapes.scale != ShapeScale::kMass)
      uw->Fail("an inventory's blocks have their measured masses: 'unit_weight' goes with "
               "\"shape_scale\": \"mass\" only");
    shapes.unit_weight =
        NumberInRange(*uw, UnitWeightToSI(uw->Positive(), units), core::kMinUnitWeight,
                      core::kMaxUnitWeight, "unit weight", Quantity::kUnitWeight, units);
  }
  return shapes;
}

// Each inventory block with a shape file takes its scanned shape, fitted
// and scaled to the block; returns each shape's worst fit over the blocks
// (error, summary), for the note. The shape files are read in order, then
// the blocks' clumps fitted side by side (each fit is serial and depends on
// its block only: the same rocks at any thread count).
std::map<std::string, std::pair<double, std::string>> ScanInventory(
    const JsonNode& node, Units units, const InventoryShapes& shapes,
    const std::vector<std::string>& shape_files, core::RockGroup* g, ShapeCache* cache,
    std::vector<std::string>* inputs) {
  const std::size_t n = g->inventory.size();
  std::vector<std::shared_ptr<const core::ScannedShape>> base(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (shape_files[k].empty()) continue;
    base[k] = LoadShapeOnce(ResolvePath(shapes.library, shape_files[k]), units, shapes.clump, cache,
                            inputs);
    if (shapes.scale != ShapeScale::kSides && !(shapes.unit_weight > 0))
      node.Fail("\"shape_scale\": \"mass\" needs the rocks' \"unit_weight\"");
  }
  const long blocks = static_cast<long>(n);
#pragma omp parallel for schedule(dynamic)
  for (long i = 0; i < blocks; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (!base[k]) continue;
    core::Block& b = g->inventory[k];
    if (shapes.scale == ShapeScale::kSides) {
      b.scanned = ShapeAtSides(*base[k], b.sides, shapes.clump);
    } else {
      const double volume = b.mass * core::kStandardGravity / shapes.unit_weight;
      b.scanned = std::make_shared<const core::ScannedShape>(
          core::ScaleShape(*base[k], std::cbrt(volume / base[k]->mass.volume)));
    }
  }
  std::map<std::string, std::pair<double, std::string>> fits;
  for (std::size_t k = 0; k < n; ++k) {
    if (!base[k]) continue;
    const core::Block& b = g->inventory[k];
    const double worst =
        std::max({std::abs(b.scanned->clump.volume_error), b.scanned->clump.moment_error});
    auto it = fits.find(base[k]->name);
    if (it == fits.end() || worst > it->second.first)
      fits[base[k]->name] = {worst, FitSummary(*b.scanned)};
  }
  return fits;
}

// The blocks of a field inventory; count (default one rock per block)
// repeats them in turn.
core::RockGroup ReadInventoryGroup(const JsonNode& node, Units units, const core::HeightGrid& grid,
                                   const std::string& base_dir, core::RockGroup g,
                                   std::vector<std::string>* inputs, std::string* note,
                                   const ZoneFileReader& read_zone_file) {
  node.Keys(SiteKeysAt("$.rocks[] (inventory)"));
  const JsonNode inv = node.Get("inventory");
  const std::string file = ResolvePath(base_dir, inv.String());
  std::vector<std::string> shape_files;
  g.inventory = ReadInventory(file, units, &shape_files);
  inputs->push_back(file);
  const InventoryShapes shapes = ReadInventoryShapes(node, units, base_dir);
  ShapeCache cache;
  const auto fits = ScanInventory(node, units, shapes, shape_files, &g, &cache, inputs);
  if (fits.empty()) {
    for (const char* key : {"shapes", "spheres", "shape_scale", "unit_weight"})
      if (auto n = node.Find(key))
        n->Fail(std::string("'") + key + "' goes with shape files in the inventory's shape column");
  }
  g.shape = g.inventory.front().shape;
  g.count = node.Has("count") ? static_cast<int>(node.Get("count").Integer(1, core::kMaxRocks))
                              : static_cast<int>(g.inventory.size());
  std::string release_note;
  g.release = ReadRelease(node.Get("release"), units, grid, &release_note, read_zone_file);
  const core::GroupExtent extent = core::GroupBodies(g, core::kStandardGravity);
  *note = std::to_string(g.count) + " rocks from the inventory " + file + " (" +
          std::to_string(g.inventory.size()) + " blocks, " +
          MassText(extent.lightest.mass, units) + " to " + MassText(extent.heaviest.mass, units) +
          "), release " + release_note;
  for (const auto& [name, fit] : fits) *note += "; worst fit of " + fit.second;
  return g;
}

// A group's "size": one size, or a range [min, max].
void ReadSize(const JsonNode& size, Units units, core::RockGroup* g) {
  if (size.is_array()) {
    const std::vector<double> s = size.Numbers(2);
    if (!(s[0] > 0)) size.Fail("expected [min, max] with 0 < min <= max");
    if (s[0] > s[1]) size.Fail("expected [min, max] with min <= max");
    g->size_min = LengthToSI(s[0], units);
    g->size_max = LengthToSI(s[1], units);
  } else {
    if (!size.is_number()) size.Fail("expected a size > 0 or a range [min, max]");
    g->size_min = g->size_max = LengthToSI(size.Positive(), units);
  }
}

// A shape (or a scanned shape's file) at a size and unit weight.
core::RockGroup ReadShapeGroup(const JsonNode& node, Units units, const core::HeightGrid& grid,
                               const std::string& base_dir, core::RockGroup g,
                               std::vector<std::string>* inputs, std::string* note,
                               const ZoneFileReader& read_zone_file) {
  node.Keys(SiteKeysAt("$.rocks[]"));
  g.count = static_cast<int>(node.Get("count").Integer(1, core::kMaxRocks));
  if (auto sf = node.Find("shape_file")) {
    if (node.Has("shape")) sf->Fail("give \"shape\" or \"shape_file\", not both");
    g.shape = core::Shape::kScanned;
    ShapeCache cache;
    g.scanned = LoadShapeOnce(ResolvePath(base_dir, sf->String()), units, ReadClumpOptions(node),
                              &cache, inputs);
  } else {
    if (auto sp = node.Find("spheres")) sp->Fail("'spheres' goes with \"shape_file\" only");
    const JsonNode shape = node.Get("shape");
    if (!core::StringToShape(shape.String(), &g.shape))
      shape.Fail(std::string("unknown shape (allowed: ") + core::ShapeNames() + ")");
  }
  const JsonNode size = node.Get("size");
  ReadSize(size, units, &g);
  if (auto box = node.Find("box")) {
    if (g.shape != core::Shape::kBox) box->Fail("'box' goes with \"shape\": \"box\" only");
    const std::vector<double> b = box->Numbers(3);
    for (double side : b)
      if (!(side > 0 && side <= 1e3)) box->Fail("expected three proportions L1, L2, L3 in (0, 1000]");
    g.box = Eigen::Vector3d(b[0], b[1], b[2]);
  }
  NumberInRange(size, g.size_max, 0, core::kMaxRockSize, "rock size", Quantity::kLength, units);
  g.unit_weight = NumberInRange(
      node.Get("unit_weight"), UnitWeightToSI(node.Get("unit_weight").Positive(), units),
      core::kMinUnitWeight, core::kMaxUnitWeight, "unit weight", Quantity::kUnitWeight, units);
  std::string release_note;
  g.release = ReadRelease(node.Get("release"), units, grid, &release_note, read_zone_file);
  *note = std::to_string(g.count) + " " +
          (g.scanned ? "of the shape " + FitSummary(*g.scanned) : core::ShapeToString(g.shape)) +
          ", size " +
          (g.size_max > g.size_min
               ? FormatNumber(g.size_min / LengthToSI(1.0, units)) + "-" +
                     LengthText(g.size_max, units)
               : LengthText(g.size_min, units)) +
          ", unit weight " + UnitWeightText(g.unit_weight, units) + ", release " + release_note;
  return g;
}

}  // namespace

core::RockGroup ReadGroup(const JsonNode& node, Units units, const core::HeightGrid& grid,
                          const std::string& base_dir, std::vector<std::string>* inputs,
                          std::string* note, const ZoneFileReader& read_zone_file) {
  core::RockGroup g;
  if (const auto id = node.Find("id")) {
    g.id = id->String();
    if (g.id.empty()) id->Fail("expected a non-empty group id");
  }
  if (node.Has("inventory"))
    return ReadInventoryGroup(node, units, grid, base_dir, std::move(g), inputs, note,
                              read_zone_file);
  return ReadShapeGroup(node, units, grid, base_dir, std::move(g), inputs, note, read_zone_file);
}

}  // namespace rockcal::sites
