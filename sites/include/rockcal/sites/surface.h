// The "surface" object of a site file: one terrain source (inline points,
// points file, CRSP LIDAR text, ESRI ASCII grid or ASCII STL) brought onto a
// regular grid in SI units.
#ifndef ROCKCAL_SITES_SURFACE_H_
#define ROCKCAL_SITES_SURFACE_H_

#include <string>
#include <vector>

#include "rockcal/core/terrain.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// Default grid spacing when "resolution" is absent: CRSP's 12 ft (3.6576 m),
// in both unit systems (an ESRI grid keeps its own cell size instead).
constexpr double kDefaultResolutionM = 12 * 0.3048;
// Largest grid accepted (nodes), so a typo in "resolution" fails clearly.
constexpr long kMaxGridNodes = 20'000'000;

struct Surface {
  core::HeightGrid grid;               // SI; material indices set by STL files, else all 0
  std::string source;                  // "points", "points_file", "lidar", "grid_file" or "stl"
  bool materials_from_source = false;  // true for STL (each file names a material)
  std::vector<std::string> notes;      // what was read and how it was gridded
  std::vector<std::string> files;      // the data files read, as resolved
};

// Reads `surface` (the site's "surface" object). `base_dir` resolves
// relative file names; `material_ids` are the site's materials, which STL
// files refer to by id. Throws InputError naming the file and JSON path, or
// the data file and line.
Surface ReadSurface(const JsonNode& surface, Units units, const std::string& base_dir,
                    const std::vector<std::string>& material_ids);

// `file` if absolute, else `base_dir`/`file`.
std::string ResolvePath(const std::string& base_dir, const std::string& file);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SURFACE_H_
