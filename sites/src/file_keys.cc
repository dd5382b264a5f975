#include "rockcal/sites/file_keys.h"

#include <stdexcept>

#include "rockcal/core/material_field.h"

namespace rockcal::sites {
namespace {

std::vector<const char*> MaterialFieldKeys() {
  std::vector<const char*> names;
  for (const core::MaterialFieldInfo& f : core::MaterialFields())
    if (!f.forest) names.push_back(f.name);
  return names;
}

std::vector<const char*> ForestFieldKeys() {
  std::vector<const char*> names;
  for (const core::MaterialFieldInfo& f : core::MaterialFields())
    if (f.forest) names.push_back(f.name);
  return names;
}

}  // namespace

const std::vector<FileObjectKeys>& SiteFileKeys() {
  static const std::vector<FileObjectKeys> objects = {
      {"$",
       {"name", "description", "units", "surface", "zones", "materials", "partitions", "barriers",
        "barriers_file", "rocks", "simulation", "report", "forest"}},
      {"$.surface",
       {"resolution", "sphere_spacing", "crs", "max_edge", "points", "points_file", "lidar",
        "grid_file", "raster", "stl"}},
      {"$.surface.lidar", {"file", "offset", "spin_deg"}},
      {"$.surface.raster", {"file", "band"}},
      {"$.surface.stl", {"files", "axes"}},
      {"$.surface.stl.files[]", {"file", "material"}},
      {"$.zones", {"file", "field", "layer", "classes"}},
      {"$.materials[]",
       {"id", "hardness", "roughness", "contact_time", "restitution", "friction",
        "rolling_resistance", "vegetation", "class", "table", "zone", "calibrate"}},
      {"$.materials[].calibrate", MaterialFieldKeys()},
      {"$.partitions[]", {"id", "x", "z"}},
      {"$.barriers[]", {"id", "line", "height", "energy_kj", "stops"}},
      {"$.barriers_file", {"file", "layer"}},
      {"$.rocks[]",
       {"id", "count", "shape", "shape_file", "spheres", "size", "box", "unit_weight", "release"}},
      {"$.rocks[] (inventory)",
       {"id", "count", "inventory", "release", "shapes", "spheres", "shape_scale", "unit_weight"}},
      {"$.rocks[].release",
       {"zone", "zone_file", "point", "height", "elevation", "velocity", "velocity_spread",
        "position_spread"}},
      {"$.rocks[].release.zone_file", {"file", "layer", "id"}},
      {"$.simulation",
       {"seed", "max_time", "stop_speed", "stop_duration", "steps_per_contact",
        "gentle_steps_per_contact", "safety", "gentle_safety", "rest_window", "exact_flight",
        "reference_path", "threads"}},
      {"$.report", {"barrier_height", "barrier_energy_kj"}},
      {"$.forest",
       {"trees_file", "trees", "stands", "rasters", "contact", "capacity_factor", "calibrate"}},
      {"$.forest.calibrate", ForestFieldKeys()},
      {"$.forest.trees[]", {"x", "y", "dbh_cm", "species", "height"}},
      {"$.forest.stands[]",
       {"zone", "stems_per_ha", "dbh_mean_cm", "dbh_sd_cm", "conifer_percent", "height"}},
      {"$.forest.rasters",
       {"stems_per_ha", "dbh_mean_cm", "dbh_sd_cm", "conifer_percent", "height"}},
      {"$.forest.contact", {"restitution", "contact_time", "friction"}},
  };
  return objects;
}

const std::vector<const char*>& KeysAt(const std::vector<FileObjectKeys>& objects,
                                       const std::string& path) {
  for (const FileObjectKeys& o : objects)
    if (o.path == path) return o.keys;
  throw std::logic_error("no key list for the file object '" + path + "'");
}

const std::vector<const char*>& SiteKeysAt(const std::string& path) {
  return KeysAt(SiteFileKeys(), path);
}

}  // namespace rockcal::sites
