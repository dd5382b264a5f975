// Site files: read, validate and turn into a core::Scene (SI units).
#ifndef ROCKCAL_SITES_SITE_H_
#define ROCKCAL_SITES_SITE_H_

#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/sites/class_table.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// A calibrated parameter and its bounds, SI units (roughness in m, contact
// time in s; hardness dimensionless).
struct ParameterBound {
  std::string material;  // material id, or core::kForestEntry for a forest field
  std::string name;      // a field of core::MaterialFields(): "hardness", "roughness", ...
  double lower = 0.0, upper = 0.0;
  std::string material_class;  // the material's class ("class"; empty: the id)
};

struct Site {
  std::string path;  // the site file
  Units units = Units::kUS;
  core::Scene scene;
  // The class of each material of scene.materials (same order): the
  // material's "class" in the site file, default its id. A label for the
  // default tables built across sites, and the class whose values a
  // material without its own takes from a class table (class_materials).
  std::vector<std::string> material_classes;
  // The materials that took values from a class table ("class" without
  // hardness or roughness, or with a "table"), in site order.
  std::vector<ClassMaterial> class_materials;
  std::vector<ParameterBound> calibrate;  // from each material's "calibrate"
  // Every file the site was read from: the site file, then its data files
  // (points, LIDAR, grid, STL) as resolved. A calibration's log fingerprints them.
  std::vector<std::string> inputs;
  // What the reader found and did, for `rockcal validate` (one line each).
  std::vector<std::string> notes;
  // Each resampling of the terrain data, with units and node counts (also
  // among `notes`): `simulate`, `calibrate` and `score` print them.
  std::vector<std::string> resampled;
  // The barrier of the report's barrier check ("report" in the site file):
  // fence height [m] and energy capacity [J]; default a 10 ft, 500 kJ fence.
  double barrier_height_m = 3.048;
  double barrier_energy_j = 500e3;
  // The terrain's coordinate reference system as WKT (empty when unknown):
  // from a raster surface, a zone file, or the surface's "crs". Every raster
  // output carries it.
  std::string crs_wkt;
  // True when the terrain or the zones came from GIS files (a raster surface,
  // a vector or raster zone file): `simulate` and `calibrate` then write
  // rasters without being asked (--rasters).
  bool gis = false;
  // The forest's stems from this index on (of scene.forest.stems) were
  // drawn from its stands: `simulate` writes them to trees.csv.
  std::size_t drawn_stems_first = 0;
};

// Reads, validates and builds the site at `path`. Throws InputError naming the
// file, the JSON path (or line), the value and what was expected.
Site LoadSite(const std::string& path);

// One warning per rock group whose rocks are identical copies of one
// another (count > 1, a release point with no position or velocity spread,
// and one body whose orientation does not matter: a sphere of one size, or
// a fixed orientation): each of its rocks follows the same path, so the
// group's Monte Carlo adds nothing. Empty when there is none.
std::vector<std::string> IdenticalCopyWarnings(const core::Scene& scene);

// Applies one --set override "material.<id>.<hardness|roughness|contact_time>=VALUE"
// (VALUE in the site's units) to site->scene. Throws InputError on a bad key or value.
void ApplySetting(const std::string& key_value, Site* site);

// What SetMaterialValue found wrong: nothing, the material id, the field
// name or the value.
enum class MaterialValueFault { kNone, kMaterial, kField, kValue };
// Sets `field` ("hardness", "roughness", "contact_time" or
// "rolling_resistance") of material `id` of `scene` to `value_si` (SI: m,
// s), after the same range checks as the site reader: the one place --set
// and a calibration's parameters.json change a material. On a fault nothing
// changes and it returns which, with *message saying what was expected
// (lengths in `units`, the file's). A forest field ("capacity_factor") is
// the forest's, with `id` core::kForestEntry ("forest"): it rescales every
// stem's capacity.
MaterialValueFault SetMaterialValue(const std::string& id, const std::string& field,
                                    double value_si, Units units, core::Scene* scene,
                                    std::string* message);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SITE_H_
