#include "rockcal/sites/site.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>

#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/material_field.h"
#include "rockcal/sites/class_table.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/geometry.h"
#include "rockcal/sites/inventory.h"
#include "rockcal/sites/shape_file.h"
#include "rockcal/sites/surface.h"
#include "rockcal/sites/text_reader.h"
#include "rockcal/sites/zone_files.h"
#include "site_readers.h"

namespace rockcal::sites {
namespace {

using core::kMaxContactTime;
using core::kMinContactTime;

bool ValidId(const std::string& id) {
  if (id.empty()) return false;
  for (char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string ReadId(const JsonNode& node) {
  const std::string id = node.String();
  if (!ValidId(id)) node.Fail("expected an id of letters, digits, '_' and '-' (not empty)");
  return id;
}

// Material fields whose checks need the grid spacing (roughness <= s/2).
struct PendingMaterial {
  JsonNode node;
  std::optional<Polygon> zone;
};

// A material's "calibrate" object: bounds for any field of
// core::MaterialFields(), in the file's units, each around the material's own
// value (for friction and rolling resistance: explicit, or the hardness
// model's). Roughness bounds lie within [min_roughness_m, max_roughness_m]
// (core::MinRoughness, half the grid spacing): a search over them never
// meets the unbounded spheres of a roughness near 0.
void ReadCalibrateBounds(const JsonNode& node, const core::Material& mat,
                         const std::string& mat_class, Units units, double min_roughness_m,
                         double max_roughness_m, Site* site) {
  node.Keys(SiteKeysAt("$.materials[].calibrate"));
  const double to_si = LengthToSI(1.0, units);
  for (const core::MaterialFieldInfo& f : core::MaterialFields()) {
    auto b = node.Find(f.name);
    if (!b) continue;
    if (f.field == core::MaterialField::kHardness && mat.restitution && mat.friction) {
      b->Fail(
          "hardness has no effect when both 'restitution' and 'friction' are given; "
          "expected no hardness bounds for this material");
    }
    const double value = core::FieldValue(mat, f.field, site->scene.hardness_model);
    if (f.unit == core::FieldUnit::kLength) {
      site->calibrate.push_back(ReadBound(*b, mat.id, mat_class, f.name,
                                          std::max(f.min, min_roughness_m) / to_si * (1 - 1e-12),
                                          max_roughness_m / to_si, false, value / to_si, to_si,
                                          std::string(" ") + LengthUnit(units)));
    } else if (f.unit == core::FieldUnit::kStress) {
      const double to_pa = StressToSI(1.0, units);
      site->calibrate.push_back(ReadBound(*b, mat.id, mat_class, f.name, f.min / to_pa,
                                          f.max / to_pa, false, value / to_pa, to_pa,
                                          std::string(" ") + StressUnit(units)));
    } else {
      site->calibrate.push_back(ReadBound(*b, mat.id, mat_class, f.name, f.min, f.max, false,
                                          value, 1.0,
                                          f.unit == core::FieldUnit::kTime ? " s" : ""));
    }
  }
}

void ReadSimulation(const JsonNode& node, Units units, core::SimulationOptions* o) {
  node.Keys(SiteKeysAt("$.simulation"));
  if (auto v = node.Find("seed"))
    o->seed = static_cast<std::uint64_t>(v->Integer(0, core::kMaxSeed));
  if (auto v = node.Find("max_time")) o->max_time = v->Positive();
  if (auto v = node.Find("stop_speed")) o->stop_speed = LengthToSI(v->Positive(), units);
  if (auto v = node.Find("stop_duration")) o->stop_duration = v->Positive();
  if (auto v = node.Find("steps_per_contact"))
    o->steps_per_contact = static_cast<int>(v->Integer(4, 100000));
  if (auto v = node.Find("gentle_steps_per_contact")) {
    o->gentle_steps_per_contact = static_cast<int>(v->Integer(0, 100000));
    if (o->gentle_steps_per_contact == 1) v->Fail("expected 0 (off) or a whole number >= 2");
  }
  if (auto v = node.Find("safety")) {
    o->safety = v->Number();
    if (!(o->safety > 0 && o->safety <= 1)) v->Fail("expected a number in (0, 1]");
  }
  if (auto v = node.Find("gentle_safety")) {
    o->gentle_safety = v->Number();
    if (!(o->gentle_safety > 0 && o->gentle_safety <= 1)) v->Fail("expected a number in (0, 1]");
  }
  if (auto v = node.Find("rest_window")) o->rest_window = v->NonNegative();
  if (auto v = node.Find("exact_flight")) o->exact_flight = v->Bool();
  if (auto v = node.Find("reference_path")) o->reference_path = v->Bool();
  if (auto v = node.Find("threads")) o->threads = static_cast<int>(v->Integer(0, 4096));
  // stop_duration below max_time, named at the key given (the other's value
  // is the default when absent).
  if (!(o->stop_duration < o->max_time)) {
    if (auto v = node.Find("stop_duration"))
      v->Fail("expected a number of seconds below max_time (" + FormatNumber(o->max_time) + " s)");
    node.Get("max_time")
        .Fail("expected a number of seconds above stop_duration (" +
              FormatNumber(o->stop_duration) + " s, the default)");
  }
  std::string error;
  if (!o->IsValid(&error)) throw InputError(node.where(), error);
}

// The whole run: at most kMaxRocks rocks, and a step count that can finish.
void CheckRun(const JsonNode& root, const core::Scene& scene) {
  long rocks = 0;
  for (const core::RockGroup& g : scene.groups) rocks += g.count;
  if (rocks > core::kMaxRocks) {
    root.Get("rocks").Fail("the rock groups hold " + std::to_string(rocks) +
                           " rocks; expected at most " + std::to_string(core::kMaxRocks));
  }
  std::string error;
  if (!scene.IsValid(&error))
    throw InputError(root.where() + (root.Has("simulation") ? ".simulation" : ""), error);
}

// The class table a material names: its "table" (a file or a folder,
// relative to the site file), else the built-in one; read once per file.
const ClassTable& TableOf(const JsonNode& m, std::map<std::string, ClassTable>* tables,
                          const Site& site) {
  auto t = m.Find("table");
  if (!t) return BuiltInClassTable();
  const std::string given = t->String();
  std::filesystem::path p(given);
  if (p.is_relative()) p = std::filesystem::path(site.path).parent_path() / p;
  const std::string path = p.string();
  auto it = tables->find(path);
  if (it != tables->end()) return it->second;
  std::error_code ec;
  if (!std::filesystem::exists(p, ec))
    t->Fail("no such file or folder (" + path +
            "); expected a table.json written by rockcal table, or its folder");
  return tables->emplace(path, ReadClassTable(path)).first->second;
}

// The values of material `m` (already holding the site's own) that its
// class gives: each field of the class's rows that the material does not
// set takes the row's median. An unknown class, or a class that lacks
// hardness or roughness the material does not give, fails at "class",
// naming the table and the classes it holds.
ClassMaterial ValuesFromClass(const JsonNode& m, core::Material* mat,
                              std::map<std::string, ClassTable>* tables, Site* site) {
  const JsonNode cls = m.Get("class");
  const ClassTable& table = TableOf(m, tables, *site);
  const MaterialClass* c = table.Find(site->material_classes.back());
  if (!c)
    cls.Fail("unknown class in the table " + table.file + "; expected one of its classes: " +
             table.ClassNames());
  ClassMaterial out;
  out.material = mat->id;
  out.material_class = c->name;
  out.table = table.file;
  out.description = c->description;
  for (const char* needed : {"hardness", "roughness"})
    if (!m.Has(needed) && !c->Find(needed))
      cls.Fail(std::string("class '") + c->name + "' of the table " + table.file + " gives no " +
               needed + "; expected '" + needed + "' in the material, or a class that has one");
  for (const ClassRow& row : c->rows) {
    const core::MaterialFieldInfo* f = core::FindMaterialField(row.parameter);
    if (m.Has(f->name)) {
      out.explicit_fields.push_back(f->name);
      continue;
    }
    if (!(row.median >= f->min && row.median <= f->max))
      throw InputError(table.file, "class " + c->name + ": " + f->name + " median " +
                                       FormatNumber(row.median) + " outside [" +
                                       FormatNumber(f->min) + ", " + FormatNumber(f->max) + "]");
    core::SetFieldValue(mat, f->field, row.median);
    out.from_table.push_back(row);
  }
  return out;
}

// The "materials" array: each material into site->scene.materials and its
// class into site->material_classes; the nodes and zones are kept for the
// checks that need the grid.
std::vector<PendingMaterial> ReadMaterials(const JsonNode& node, Units units, Site* site) {
  std::vector<PendingMaterial> pending;
  std::vector<std::string> ids;
  std::map<std::string, ClassTable> tables;  // the class tables read, by file
  const std::vector<JsonNode> materials = node.Array(1);
  for (std::size_t k = 0; k < materials.size(); ++k) {
    const JsonNode& m = materials[k];
    m.Keys(SiteKeysAt("$.materials[]"));
    core::Material mat;
    const JsonNode id = m.Get("id");
    mat.id = ReadId(id);
    if (std::find(ids.begin(), ids.end(), mat.id) != ids.end())
      id.Fail("duplicate material id; expected each material id once");
    ids.push_back(mat.id);
    if (auto c = m.Find("class")) {
      // Same rule as ids: the class goes into CSV and Markdown tables as it is.
      site->material_classes.push_back(c->String());
      if (!ValidId(site->material_classes.back()))
        c->Fail("expected a class name of letters, digits, '_' and '-' (not empty)");
    } else {
      site->material_classes.push_back(mat.id);
    }
    // A class without hardness or roughness (or with its own table) takes
    // them from the class table; otherwise the class is a label only.
    const bool from_class =
        m.Has("class") && (!m.Has("hardness") || !m.Has("roughness") || m.Has("table"));
    if (auto t = m.Find("table"); t && !m.Has("class"))
      t->Fail("a table goes with a 'class' (the class whose values the table gives)");
    if (!from_class || m.Has("hardness")) mat.hardness = m.Get("hardness").Number(0.0, 1.0);
    if (!from_class || m.Has("roughness"))
      mat.roughness_m = LengthToSI(m.Get("roughness").NonNegative(), units);
    if (auto t = m.Find("contact_time")) {
      mat.contact_time_s = t->Positive();
      NumberInRange(*t, mat.contact_time_s, kMinContactTime, kMaxContactTime, "contact time",
                    Quantity::kTime, units, "(a shorter contact takes too many steps to finish)");
    }
    if (auto e = m.Find("restitution")) {
      const double v = e->Number(0.0, 1.0);
      if (!(v > 0.0 && v < 1.0)) e->Fail("expected a restitution in (0, 1)");
      mat.restitution = v;
    }
    if (auto f = m.Find("friction")) mat.friction = f->Number(0.0, 10.0);
    if (auto r = m.Find("rolling_resistance")) mat.rolling_resistance = r->Number(0.0, 1.0);
    if (auto v = m.Find("vegetation")) {
      mat.vegetation_pa = NumberInRange(*v, StressToSI(v->NonNegative(), units), 0.0,
                                        core::kMaxVegetationStress, "vegetation resistance",
                                        Quantity::kStress, units);
    }
    if (from_class) site->class_materials.push_back(ValuesFromClass(m, &mat, &tables, site));
    PendingMaterial p{m, std::nullopt};
    if (auto z = m.Find("zone")) {
      if (k == 0) {
        z->Fail(
            "the first material covers everything no zone claims and takes no zone; "
            "expected 'zone' only on later materials");
      }
      p.zone = ReadPolygon(*z, units);
    }
    site->scene.materials.push_back(mat);
    pending.push_back(std::move(p));
  }
  return pending;
}

// Material zones: the last zone holding a node wins.
void ApplyZones(const std::vector<PendingMaterial>& pending, double to_file,
                core::HeightGrid* grid_out) {
  core::HeightGrid& grid = *grid_out;
  for (std::size_t k = 1; k < pending.size(); ++k) {
    if (!pending[k].zone) continue;
    const Polygon& zone = *pending[k].zone;
    int claimed = 0;
    for (int j = 0; j < grid.ny; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        if (PointInPolygon(zone, Eigen::Vector2d(grid.x(i), grid.y(j)))) {
          grid.material[grid.index(i, j)] = static_cast<int>(k);
          ++claimed;
        }
      }
    }
    if (claimed == 0) {
      pending[k].node.Get("zone").Fail(
          "the zone contains no grid node (the terrain spans x " +
          FormatNumber(grid.x(0) * to_file) + " to " + FormatNumber(grid.x(grid.nx - 1) * to_file) +
          ", y " + FormatNumber(grid.y(0) * to_file) + " to " +
          FormatNumber(grid.y(grid.ny - 1) * to_file) + "); expected a zone over the terrain");
    }
  }
}

// Every material must cover a node; notes on the grid, its holes and the
// materials; the terrain's elevation range into *zmin_out, *zmax_out.
void CheckCoverAndNote(const std::vector<PendingMaterial>& pending, Site* site, double* zmin_out,
                       double* zmax_out) {
  const core::Scene& scene = site->scene;
  const core::HeightGrid& grid = scene.grid;
  const double s = grid.spacing;
  std::vector<int> count(scene.materials.size(), 0);
  int holes = 0;
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  for (std::size_t n = 0; n < grid.z.size(); ++n) {
    if (std::isnan(grid.z[n])) {
      ++holes;
      continue;
    }
    ++count[static_cast<std::size_t>(grid.material[n])];
    zmin = std::min(zmin, grid.z[n]);
    zmax = std::max(zmax, grid.z[n]);
  }
  // Rounding residue of the plane fits (e.g. -1e-16 for 0) would clutter messages.
  const double zscale = 1e-12 * std::max({1.0, std::abs(zmin), std::abs(zmax)});
  if (std::abs(zmin) < zscale) zmin = 0.0;
  if (std::abs(zmax) < zscale) zmax = 0.0;
  for (std::size_t k = 0; k < count.size(); ++k) {
    if (count[k] == 0) {
      pending[k].node.Fail("material '" + scene.materials[k].id +
                           "' covers no terrain node (its zone is overridden by later zones, "
                           "off the data, or no surface or zone file names it); expected every "
                           "material to cover part of the terrain");
    }
  }
  const Units units = site->units;
  const double to_file = 1.0 / LengthToSI(1.0, units);
  site->notes.push_back("grid: " + std::to_string(grid.nx) + " x " + std::to_string(grid.ny) +
                        " nodes at " + LengthText(s, units) + " spacing, x " +
                        FormatNumber(grid.x(0) * to_file) + " to " +
                        LengthText(grid.x(grid.nx - 1), units) + ", y " +
                        FormatNumber(grid.y(0) * to_file) + " to " +
                        LengthText(grid.y(grid.ny - 1), units) + ", elevation " +
                        FormatNumber(zmin * to_file) + " to " + LengthText(zmax, units));
  site->notes.push_back("holes: " + std::to_string(holes) + " of " + std::to_string(grid.z.size()) +
                       " nodes");
  for (std::size_t k = 0; k < count.size(); ++k) {
    const core::Material& mat = scene.materials[k];
    site->notes.push_back(
        "material " + mat.id + ": " + std::to_string(count[k]) + " nodes, class " +
        site->material_classes[k] + ", hardness " + FormatNumber(mat.hardness) + ", roughness " +
        LengthText(mat.roughness_m, units) + ", contact time " + FormatNumber(mat.contact_time_s) +
        " s" + (mat.restitution ? ", restitution " + FormatNumber(*mat.restitution) : "") +
        (mat.friction ? ", friction " + FormatNumber(*mat.friction) : ""));
  }
  *zmin_out = zmin;
  *zmax_out = zmax;
}

// The "partitions" array, each within the terrain (x) or its elevations (z).
void ReadPartitions(const JsonNode& parts, Units units, double zmin, double zmax, Site* site) {
  const core::HeightGrid& grid = site->scene.grid;
  const double to_file = 1.0 / LengthToSI(1.0, units);
  std::vector<std::string> part_ids;
  for (const JsonNode& p : parts.Array()) {
    p.Keys(SiteKeysAt("$.partitions[]"));
    core::Partition part;
    const JsonNode id = p.Get("id");
    part.id = ReadId(id);
    if (std::find(part_ids.begin(), part_ids.end(), part.id) != part_ids.end())
      id.Fail("duplicate partition id; expected each partition id once");
    part_ids.push_back(part.id);
    if (p.Has("x") == p.Has("z")) p.Fail("expected exactly one of 'x' or 'z'");
    if (auto x = p.Find("x")) {
      part.kind = core::Partition::Kind::kX;
      part.value = LengthToSI(x->Number(), units);
      const double lo = grid.x(0), hi = grid.x(grid.nx - 1);
      if (part.value < lo || part.value > hi) {
        x->Fail("the X partition lies off the terrain; expected x in [" +
                FormatNumber(lo * to_file) + ", " + FormatNumber(hi * to_file) + "]");
      }
    } else {
      const JsonNode z = p.Get("z");
      part.kind = core::Partition::Kind::kZ;
      part.value = LengthToSI(z.Number(), units);
      if (part.value < zmin || part.value > zmax) {
        z.Fail("the Z partition is outside the terrain's elevations; expected z in [" +
               FormatNumber(zmin * to_file) + ", " + FormatNumber(zmax * to_file) + "]");
      }
    }
    site->notes.push_back("partition " + part.id + ": " +
                         (part.kind == core::Partition::Kind::kX ? "x" : "z") + " = " +
                         LengthText(part.value, units));
    site->scene.partitions.push_back(part);
  }
}

// What is wrong with a barrier's line on `grid` ("" when nothing): fewer
// than 2 vertices, a vertex not finite, no length, or off the terrain.
std::string LineFault(const std::vector<Eigen::Vector2d>& line, const core::HeightGrid& grid,
                      Units units) {
  const double to_file = 1.0 / LengthToSI(1.0, units);
  if (line.size() < 2)
    return "a line of " + std::to_string(line.size()) + " vertices; expected at least 2 [x, y]";
  Eigen::Vector2d lo = line[0], hi = line[0];
  for (std::size_t k = 0; k < line.size(); ++k) {
    if (!line[k].allFinite()) {
      return "vertex " + std::to_string(k) + " is (" + FormatNumber(line[k].x() * to_file) + ", " +
             FormatNumber(line[k].y() * to_file) + "); expected finite coordinates";
    }
    lo = lo.cwiseMin(line[k]);
    hi = hi.cwiseMax(line[k]);
  }
  if (lo == hi) return "every vertex is the same point; expected a line of some length";
  const double x0 = grid.x(0), x1 = grid.x(grid.nx - 1), y0 = grid.y(0), y1 = grid.y(grid.ny - 1);
  if (hi.x() < x0 || lo.x() > x1 || hi.y() < y0 || lo.y() > y1) {
    return "the line (x " + FormatNumber(lo.x() * to_file) + " to " +
           FormatNumber(hi.x() * to_file) + ", y " + FormatNumber(lo.y() * to_file) + " to " +
           FormatNumber(hi.y() * to_file) + ") lies off the terrain; expected it over x " +
           FormatNumber(x0 * to_file) + " to " + FormatNumber(x1 * to_file) + ", y " +
           FormatNumber(y0 * to_file) + " to " + FormatNumber(y1 * to_file) +
           ", in the site's frame and unit";
  }
  return "";
}

// The "barriers" array and the "barriers_file": lines in plan, appended to
// the scene's partitions (docs/reference/site-file.md#barriers), their ids
// unique among the partitions'.
void ReadBarriers(const JsonNode& root, const std::string& base_dir, Site* site) {
  const Units units = site->units;
  std::vector<core::Partition>& parts = site->scene.partitions;
  // Fails with fail_id (a duplicate id) or fail_line (its line).
  using Fail = std::function<void(const std::string&)>;
  auto add = [&](core::Partition part, const Fail& fail_id, const Fail& fail_line) {
    for (const core::Partition& p : parts)
      if (p.id == part.id)
        fail_id("the id '" + part.id +
                "' is also a partition's or another barrier's; expected ids unique among the "
                "partitions and barriers");
    if (const std::string fault = LineFault(part.line, site->scene.grid, units); !fault.empty())
      fail_line(fault);
    const double to_file = 1.0 / LengthToSI(1.0, units);
    site->notes.push_back("barrier " + part.id + ": a line of " + std::to_string(part.line.size()) +
                          " vertices, " + FormatNumber(part.height * to_file) + " " +
                          LengthUnit(units) + " high, " + FormatNumber(part.capacity * 1e-3) +
                          " kJ" + (part.stops ? ", stops the rocks it catches" : ""));
    parts.push_back(std::move(part));
  };
  if (auto list = root.Find("barriers")) {
    for (const JsonNode& b : list->Array(1)) {
      b.Keys(SiteKeysAt("$.barriers[]"));
      core::Partition part;
      part.kind = core::Partition::Kind::kLine;
      const JsonNode id = b.Get("id");
      part.id = ReadId(id);
      const JsonNode line = b.Get("line");
      if (!line.is_array() || line.raw().size() < 2)
        line.Fail("expected a line: an array of at least 2 [x, y] vertices");
      for (const JsonNode& v : line.Array()) {
        const std::vector<double> xy = CoordinatesToSI(v, 2, units);
        part.line.emplace_back(xy[0], xy[1]);
      }
      part.height = LengthToSI(b.Get("height").Positive(), units);
      part.capacity = b.Get("energy_kj").Positive() * 1e3;
      if (auto stops = b.Find("stops")) part.stops = stops->Bool();
      add(
          std::move(part), [&](const std::string& why) { id.Fail(why); },
          [&](const std::string& why) { line.Fail(why); });
    }
  }
  if (auto file = root.Find("barriers_file")) {
    for (BarrierFeature& f : ReadBarrierFile(*file, base_dir, site)) {
      auto fail = [&](const std::string& why) { throw InputError(f.file, f.where + ": " + why); };
      if (!ValidId(f.barrier.id))
        fail("field 'id' holds " + Excerpt(f.barrier.id) +
             "; expected an id of letters, digits, '_' and '-' (not empty)");
      add(std::move(f.barrier), fail, fail);
    }
  }
}

// Where a material's roughness is given: its "roughness", or its class.
JsonNode RoughnessNode(const JsonNode& m) {
  return m.Has("roughness") ? m.Get("roughness") : m.Get("class");
}

// A roughness from a class table: a note when the table's values come from
// virtual spheres spaced otherwise than this site's (a roughness means the
// same ground only at the same spacing), and the interval the draws take
// cut to what this grid allows.
void ClassRoughness(const core::Material& mat, double min_rough, double s,
                    Site* site) {
  for (ClassMaterial& c : site->class_materials) {
    if (c.material != mat.id) continue;
    for (ClassRow& row : c.from_table) {
      if (row.parameter != "roughness") continue;
      for (double spacing : row.spacings_m)
        if (std::abs(spacing - s) > 1e-9 * s)
          c.notes.push_back("the class's roughness was calibrated on virtual spheres " +
                            FormatNumber(spacing) + " m apart, this site's are " +
                            FormatNumber(s) + " m apart: the same roughness is not the same "
                            "ground (set surface.sphere_spacing to " + FormatNumber(spacing) +
                            " m to use it as calibrated)");
      if (row.low && (*row.low < min_rough || *row.high > s / 2)) {
        row.low = std::clamp(*row.low, min_rough, s / 2);
        row.high = std::clamp(*row.high, min_rough, s / 2);
        c.notes.push_back("the roughness interval is cut to [" + FormatNumber(*row.low) + ", " +
                          FormatNumber(*row.high) + "] m, what this grid allows");
      }
    }
  }
}

// Each material's roughness within what the grid's spacing allows, and its
// calibration bounds.
void CheckRoughness(const std::vector<PendingMaterial>& pending, Units units, Site* site) {
  const double s = site->scene.grid.spacing;
  const double to_file = 1.0 / LengthToSI(1.0, units);
  const char* unit = LengthUnit(units);
  for (std::size_t k = 0; k < pending.size(); ++k) {
    const JsonNode& m = pending[k].node;
    core::Material& mat = site->scene.materials[k];
    const std::string& mat_class = site->material_classes[k];
    const double max_rough = s / 2 * to_file;
    if (mat.roughness_m > s / 2 * (1 + 1e-12)) {
      RoughnessNode(m).Fail("roughness exceeds half the grid spacing (" + FormatNumber(max_rough) + " " + unit +
                "): a virtual sphere cannot sag more than s/2; expected a "
                "roughness in [0, " +
                FormatNumber(max_rough) + "]");
    }
    const double min_rough = core::MinRoughness(s);
    if (mat.roughness_m > 0.0 && mat.roughness_m < min_rough * (1 - 1e-12)) {
      RoughnessNode(m).Fail("roughness " + FormatNumber(mat.roughness_m * to_file) + " " + unit +
                " gives virtual spheres of radius " +
                FormatNumber(core::VirtualSphereRadius(mat.roughness_m, s) * to_file, "%.4g") +
                " " + unit + ", more than 10 grid spacings (" + FormatNumber(10 * s * to_file) +
                " " + unit + "); expected 0 (smooth) or a roughness in [" +
                FormatNumber(min_rough * to_file) + ", " + FormatNumber(max_rough) + "] " + unit);
    }
    ClassRoughness(mat, min_rough, s, site);
    if (auto c = m.Find("calibrate"))
      ReadCalibrateBounds(*c, mat, mat_class, units, min_rough, s / 2, site);
  }
}

}  // namespace

ParameterBound ReadBound(const JsonNode& node, const std::string& material,
                         const std::string& material_class, const char* name, double min,
                         double max, bool open_min, double value, double to_si,
                         const std::string& unit) {
  const std::vector<double> b = node.Numbers(2);
  if (!(b[0] < b[1])) node.Fail("expected [lower, upper] with lower < upper");
  // (max may come from a unit conversion: allow for its rounding.)
  if (b[0] < min || (open_min && b[0] <= min) || b[1] > max * (1 + 1e-12)) {
    node.Fail(std::string("expected bounds within ") + (open_min ? "(" : "[") + FormatNumber(min) +
              ", " + FormatNumber(max) + "]" + unit);
  }
  if (value < b[0] || value > b[1]) {
    const core::MaterialFieldInfo* f = core::FindMaterialField(name);
    node.Fail(std::string(f && f->forest ? "the forest's " : "the material's ") + name + " " +
              FormatNumber(value) + unit +
              " is outside its calibrate bounds; expected lower <= value <= upper");
  }
  return ParameterBound{material, name, b[0] * to_si, b[1] * to_si, material_class};
}


Polygon ReadPolygon(const JsonNode& node, Units units) {
  if (!node.is_array() || node.raw().size() < 3)
    node.Fail("expected a polygon: an array of at least 3 [x, y] vertices");
  Polygon polygon;
  double scale = 0.0;
  for (const JsonNode& v : node.Array()) {
    const std::vector<double> xy = CoordinatesToSI(v, 2, units);
    polygon.emplace_back(xy[0], xy[1]);
  }
  for (const Eigen::Vector2d& v : polygon) scale = std::max(scale, (v - polygon[0]).norm());
  if (!(std::abs(SignedArea(polygon)) > 1e-9 * scale * scale))
    node.Fail("degenerate polygon: its vertices enclose no area");
  if (const auto edges = FindSelfIntersection(polygon)) {
    node.Fail("self-intersecting polygon: edge " + std::to_string(edges->first) + " (vertices " +
              std::to_string(edges->first) + "-" + std::to_string(edges->first + 1) +
              ") meets edge " + std::to_string(edges->second) +
              "; expected a simple polygon whose edges meet only at shared vertices");
  }
  return polygon;
}

Site LoadSite(const std::string& path) {
  const nlohmann::json json = ReadJsonFile(path);
  const JsonNode root(&json, path, "$");
  root.Keys(SiteKeysAt("$"));
  Site site;
  site.path = path;
  site.units = ReadUnits(root.Get("units"));
  const Units units = site.units;
  const double to_file = 1.0 / LengthToSI(1.0, units);
  core::Scene& scene = site.scene;
  {
    const JsonNode name = root.Get("name");
    scene.name = name.String();
    if (scene.name.empty()) name.Fail("expected a non-empty name");
  }
  if (auto d = root.Find("description")) d->Text();

  // Materials (their roughness limit needs the grid spacing: checked below).
  std::vector<PendingMaterial> pending = ReadMaterials(root.Get("materials"), units, &site);
  std::vector<std::string> ids;
  for (const core::Material& m : scene.materials) ids.push_back(m.id);

  // Surface.
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  Surface surface = ReadSurface(root.Get("surface"), units, base_dir, ids);
  scene.grid = std::move(surface.grid);
  core::HeightGrid& grid = scene.grid;
  site.notes = surface.notes;
  site.resampled = surface.resampled;
  site.inputs.push_back(path);
  site.inputs.insert(site.inputs.end(), surface.files.begin(), surface.files.end());
  site.crs_wkt = surface.crs_wkt;
  site.gis = surface.gis;

  CheckRoughness(pending, units, &site);
  for (const ClassMaterial& c : site.class_materials) {
    if (c.table != kBuiltInTable) site.inputs.push_back(c.table);
    std::string taken;
    for (const ClassRow& r : c.from_table)
      taken += (taken.empty() ? "" : ", ") + r.parameter + " " + FormatNumber(r.median, "%.4g") +
               (r.low ? " (" + r.interval + " " + FormatNumber(*r.low, "%.4g") + "-" +
                            FormatNumber(*r.high, "%.4g") + ")"
                      : std::string(""));
    site.notes.push_back("material " + c.material + ": class " + c.material_class + " of " +
                         c.table + ": " + taken + " (SI; medians, drawn in the intervals by "
                         "simulate)" +
                         (c.explicit_fields.empty()
                              ? std::string("")
                              : "; the site's own " + Join(c.explicit_fields) +
                                    " override the class's"));
    for (const std::string& n : c.notes) site.notes.push_back("material " + c.material + ": " + n);
  }

  // Zones: the zone file's first, then the materials' own on top.
  if (auto zones = root.Find("zones")) ApplyZoneFile(*zones, base_dir, &site);
  ApplyZones(pending, to_file, &grid);
  double zmin = 0.0, zmax = 0.0;
  CheckCoverAndNote(pending, &site, &zmin, &zmax);

  if (auto parts = root.Find("partitions")) ReadPartitions(*parts, units, zmin, zmax, &site);
  ReadBarriers(root, base_dir, &site);

  // Rock groups.
  const std::vector<JsonNode> rocks = root.Get("rocks").Array(1);
  for (std::size_t k = 0; k < rocks.size(); ++k) {
    std::string note;
    // A release area from a GIS file: ReadReleaseFile on this site (its CRS,
    // inputs).
    const ZoneFileReader read_zone_file = [&](const JsonNode& z, std::string* where) {
      return ReadReleaseFile(z, base_dir, &site, where);
    };
    scene.groups.push_back(
        ReadGroup(rocks[k], units, grid, base_dir, &site.inputs, &note, read_zone_file));
    const std::string& id = scene.groups.back().id;
    for (std::size_t j = 0; j + 1 < scene.groups.size() && !id.empty(); ++j)
      if (scene.groups[j].id == id)
        rocks[k].Get("id").Fail("group id '" + id + "' is also rocks[" + std::to_string(j) +
                                "]'s; expected ids unique within the site");
    site.notes.push_back("rock group " + std::to_string(k + 1) +
                         (id.empty() ? "" : " '" + id + "'") + ": " + note);
  }

  if (auto sim = root.Find("simulation")) ReadSimulation(*sim, units, &scene.options);
  if (auto forest = root.Find("forest")) ReadForest(*forest, units, base_dir, &site);
  if (auto report = root.Find("report")) {
    // The barrier a designer checks: a fence height (site length units) and
    // its energy capacity (kJ).
    report->Keys(SiteKeysAt("$.report"));
    if (auto h = report->Find("barrier_height"))
      site.barrier_height_m = LengthToSI(h->Positive(), units);
    if (auto e = report->Find("barrier_energy_kj")) site.barrier_energy_j = e->Positive() * 1e3;
  }
  CheckRun(root, scene);
  site.notes.push_back("simulation: seed " + std::to_string(scene.options.seed) + ", max time " +
                       FormatNumber(scene.options.max_time) + " s, " +
                       std::to_string(scene.total_rocks()) + " rocks in " +
                       std::to_string(scene.groups.size()) + " group(s)");
  if (!site.calibrate.empty()) {
    // Each bound in the file's units, with the unit (none for a number).
    std::string list;
    for (const ParameterBound& b : site.calibrate) {
      const core::FieldUnit unit = core::FindMaterialField(b.name)->unit;
      const double to_unit = 1.0 / FieldToSI(1.0, unit, units);
      const std::string text = FieldUnitText(unit, units);
      list += (list.empty() ? "" : ", ") + b.material + "." + b.name + " [" +
              FormatNumber(b.lower * to_unit) + ", " + FormatNumber(b.upper * to_unit) + "]" +
              (text.empty() ? "" : " " + text);
    }
    site.notes.push_back("calibrate: " + list);
  }
  return site;
}

void ApplySetting(const std::string& key_value, Site* site) {
  const std::string where = "--set " + key_value;
  const std::size_t eq = key_value.find('=');
  const std::string key = key_value.substr(0, eq);
  const std::string prefix = "material.";
  const std::size_t dot = key.rfind('.');
  if (eq == std::string::npos || key.compare(0, prefix.size(), prefix) != 0 ||
      dot < prefix.size()) {
    throw InputError(where, std::string("expected material.<id>.<field>=VALUE with field one of ") +
                                core::MaterialFieldNames());
  }
  const std::string id = key.substr(prefix.size(), dot - prefix.size());
  const std::string field = key.substr(dot + 1);
  const std::string text = key_value.substr(eq + 1);
  double value = 0.0;
  if (!ParseNumber(text, &value))
    throw InputError(where, "'" + text + "' is not a number; expected a finite number");
  // In the site's units (roughness a length, vegetation a stress); an unknown
  // field is refused by SetMaterialValue, naming the allowed ones.
  const core::MaterialFieldInfo* info = core::FindMaterialField(field);
  const double si = info ? FieldToSI(value, info->unit, site->units) : value;
  std::string message;
  if (SetMaterialValue(id, field, si, site->units, &site->scene, &message) !=
      MaterialValueFault::kNone)
    throw InputError(where, message);
}

MaterialValueFault SetMaterialValue(const std::string& id, const std::string& field,
                                    double value_si, Units units, core::Scene* scene,
                                    std::string* message) {
  // The forest's values, for the entry core::kForestEntry.
  if (const core::MaterialFieldInfo* f = core::FindMaterialField(field); f && f->forest) {
    if (id != core::kForestEntry) {
      *message = "'" + field + "' is a value of the forest (" + core::kForestEntry + "." + field +
                 "), not of material '" + id + "'";
      return MaterialValueFault::kField;
    }
    if (scene->forest.empty()) {
      *message = std::string("the site has no forest (expected a site with a 'forest' for ") +
                 core::kForestEntry + "." + field + ")";
      return MaterialValueFault::kMaterial;
    }
    if (!(value_si >= f->min && value_si <= f->max)) {
      *message = std::string("expected a ") + f->label + " in [" + FormatNumber(f->min) + ", " +
                 FormatNumber(f->max) + "]";
      return MaterialValueFault::kValue;
    }
    core::SetForestFieldValue(&scene->forest, f->field, value_si);
    return MaterialValueFault::kNone;
  }
  std::vector<core::Material>& materials = scene->materials;
  auto it = std::find_if(materials.begin(), materials.end(),
                         [&](const core::Material& m) { return m.id == id; });
  if (it == materials.end()) {
    std::vector<std::string> ids;
    for (const core::Material& m : materials) ids.push_back(m.id);
    *message = "unknown material '" + id + "' (materials: " + Join(ids) + ")";
    return MaterialValueFault::kMaterial;
  }
  const core::MaterialFieldInfo* f = core::FindMaterialField(field);
  if (!f) {
    *message = "unknown field '" + field + "' (allowed: " + core::MaterialFieldNames() + ")";
    return MaterialValueFault::kField;
  }
  const double value = value_si;
  if (f->unit == core::FieldUnit::kLength) {
    const double max_rough = scene->grid.spacing / 2;
    const double min_rough = core::MinRoughness(scene->grid.spacing);
    if (!(value == 0.0 || (value >= min_rough * (1 - 1e-12) && value <= max_rough * (1 + 1e-12)))) {
      const double to_file = 1.0 / LengthToSI(1.0, units);
      *message = std::string("expected 0 (smooth) or a ") + f->label + " in [" +
                 FormatNumber(min_rough * to_file) + ", " + FormatNumber(max_rough * to_file) +
                 "] " + LengthUnit(units) +
                 " (virtual spheres of at most 10 grid spacings, sag at most half a spacing)";
      return MaterialValueFault::kValue;
    }
  } else if (f->unit == core::FieldUnit::kStress && !(value >= f->min && value <= f->max)) {
    const double to_file = 1.0 / StressToSI(1.0, units);
    *message = std::string("expected a ") + f->label + " in [" + FormatNumber(f->min * to_file) +
               ", " + FormatNumber(f->max * to_file) + "] " + StressUnit(units);
    return MaterialValueFault::kValue;
  } else if (!(value >= f->min && value <= f->max)) {
    *message = std::string("expected a ") + f->label +
               (f->unit == core::FieldUnit::kTime ? " in seconds" : "") + " in [" +
               FormatNumber(f->min) + ", " + FormatNumber(f->max) + "]" +
               (f->field == core::MaterialField::kContactTime
                    ? " (shorter ones take too many steps to finish)"
                    : "");
    return MaterialValueFault::kValue;
  }
  core::SetFieldValue(&*it, f->field, value);
  return MaterialValueFault::kNone;
}

std::vector<std::string> IdenticalCopyWarnings(const core::Scene& scene) {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < scene.groups.size(); ++k) {
    const core::RockGroup& g = scene.groups[k];
    if (g.count < 2 || !g.release.zone.empty() || g.release.velocity_spread.any()) continue;
    // The same body every time: one size, and one block (or none) ...
    bool same_body = g.inventory.empty() ? g.size_min == g.size_max : g.inventory.size() == 1;
    // ... whose orientation is fixed or does not matter (a sphere).
    const core::Shape shape = g.inventory.empty() ? g.shape : g.inventory.front().shape;
    same_body = same_body && (shape == core::Shape::kSphere || g.release.orientation.has_value());
    if (!same_body) continue;
    out.push_back("rock group " + std::to_string(k + 1) + (g.id.empty() ? "" : " '" + g.id + "'") +
                  ": its " + std::to_string(g.count) +
                  " rocks are identical copies (one point, one velocity, one body whose "
                  "orientation does not matter): the Monte Carlo adds nothing; give the release "
                  "a 'position_spread' or a 'velocity_spread', or the block as a box");
  }
  return out;
}

}  // namespace rockcal::sites
