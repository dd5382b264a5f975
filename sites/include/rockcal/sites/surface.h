// The "surface" object of a site file: one terrain source (inline points,
// points file, CRSP LIDAR text, ESRI ASCII grid, any raster GDAL reads, or
// ASCII STL) brought onto a regular grid in SI units, with its CRS.
#ifndef ROCKCAL_SITES_SURFACE_H_
#define ROCKCAL_SITES_SURFACE_H_

#include <string>
#include <vector>

#include "rockcal/core/terrain.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::sites {

// Default spacing of the virtual spheres ("sphere_spacing") of scattered
// points (points, points_file, lidar) and STL: CRSP's surface resolution of
// 12 ft (3.6576 m), in both unit systems. A DEM (grid_file, raster) with no
// sphere_spacing keeps its own grid instead: its cells, or its "resolution"
// when given. Roughness is the sag between spheres this far apart, so one R
// means one ground at one sphere spacing (docs/physics.md, "Roughness is one
// ground at any resolution"). "resolution" (how the data are gridded first)
// defaults to the sphere spacing; an ESRI grid or a raster keeps its own
// cell size instead. A grid at another spacing than the spheres' is
// resampled bilinearly onto it (ResampleGrid), and Surface::resampled says so.
constexpr double kDefaultSphereSpacingM = 12 * 0.3048;
// Largest grid accepted (nodes), so a typo in "resolution" fails clearly.
constexpr long kMaxGridNodes = 20'000'000;

struct Surface {
  core::HeightGrid grid;  // SI; material indices set by STL files, else all 0
  std::string source;     // "points", "points_file", "lidar", "grid_file", "raster" or "stl"
  bool materials_from_source = false;  // true for STL (each file names a material)
  std::vector<std::string> notes;      // what was read and how it was gridded
  // Each resampling of the data (a DEM to its "resolution", a grid to the
  // spheres' spacing), with units and node counts; also among `notes`.
  std::vector<std::string> resampled;
  std::vector<std::string> files;      // the data files read, as resolved (with side files)
  // The terrain's CRS as WKT: the raster's own, else the "crs" key's; empty
  // when neither gives one.
  std::string crs_wkt;
  bool gis = false;  // true for a raster read with GDAL
};

// Reads `surface` (the site's "surface" object). `base_dir` resolves
// relative file names; `material_ids` are the site's materials, which STL
// files refer to by id. Throws InputError naming the file and JSON path, or
// the data file and line. Besides the source: "resolution", "sphere_spacing"
// (see kDefaultSphereSpacingM), "crs" (any text
// OSRSetFromUserInput accepts; it must be the raster's own CRS when the
// raster has one, and measure in the site's length unit) and "max_edge"
// (points sources only; see GriddingOptions).
Surface ReadSurface(const JsonNode& surface, Units units, const std::string& base_dir,
                    const std::vector<std::string>& material_ids);

// `file` if absolute, else `base_dir`/`file`.
std::string ResolvePath(const std::string& base_dir, const std::string& file);

// The data file named by `node` (a string), resolved against `base_dir`.
// Fails at `node` on an empty name, a folder, or a file that cannot be
// opened, naming the file and the cause.
std::string ResolveDataFile(const JsonNode& node, const std::string& base_dir);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SURFACE_H_
