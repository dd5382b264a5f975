#include "rockcal/sites/surface.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <system_error>

#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/sites/crs.h"
#include "rockcal/sites/esri_grid.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/gridding.h"
#include "rockcal/sites/point_files.h"
#include "rockcal/sites/raster.h"
#include "rockcal/sites/stl.h"

namespace rockcal::sites {
namespace {

constexpr const char* kSources[] = {"points", "points_file", "lidar", "grid_file", "raster", "stl"};

std::string SourceList() {
  std::string s;
  for (const char* k : kSources) s += std::string(s.empty() ? "" : ", ") + k;
  return s;
}

struct Box {
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
  double ymin = xmin, ymax = -xmin;
  void Add(double x, double y) {
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
};

// Fails unless a grid of `spacing` over `box` has 2..kMaxGridNodes nodes.
void CheckGridSize(const JsonNode& where, const Box& box, double spacing, double to_file) {
  const long nx = NodeCount(box.xmax - box.xmin, spacing);
  const long ny = NodeCount(box.ymax - box.ymin, spacing);
  if (nx < 2 || ny < 2) {
    where.Fail("the surface data span " + FormatNumber((box.xmax - box.xmin) * to_file) + " x " +
               FormatNumber((box.ymax - box.ymin) * to_file) +
               " (file units) in plan, less than one grid spacing (" +
               FormatNumber(spacing * to_file) + ") along " + (nx < 2 ? "x" : "y") +
               "; expected data covering at least 2 x 2 grid nodes");
  }
  if (static_cast<double>(nx) * static_cast<double>(ny) > static_cast<double>(kMaxGridNodes)) {
    where.Fail("a grid of " + std::to_string(nx) + " x " + std::to_string(ny) +
               " nodes at spacing " + FormatNumber(spacing * to_file) + " is too large (limit " +
               std::to_string(kMaxGridNodes) + " nodes); expected a coarser resolution");
  }
}

// The one range of every terrain source's coordinates and elevations
// (points, LIDAR, grids, rasters, STL; docs/reference/site-file.md): within
// +-core::kMaxCoordinate. `si` is the value in metres, `what` names it and
// where it is ("the elevation of row 3, column 7"); the error names the file
// and the value in the file's units.
void CheckTerrainValue(double si, double to_file, const std::string& file,
                       const std::string& what) {
  if (std::abs(si) <= core::kMaxCoordinate) return;
  throw InputError(file, what + " is " + FormatNumber(si * to_file) +
                             ", out of range; expected coordinates and elevations within +-" +
                             FormatNumber(core::kMaxCoordinate * to_file) + " (file units)");
}

// Turns points (SI) into the grid by triangulation, with notes; errors at
// `src` (a point out of range: at `src`, naming `file` when there is one),
// but a grid too small or too large at `where` (the resolution).
void GridInto(const std::vector<Eigen::Vector3d>& points, const JsonNode& where,
              const JsonNode& src, const std::string& file, const GriddingOptions& options,
              double to_file, Surface* out) {
  Box box;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d& p = points[k];
    if (!(p.cwiseAbs().maxCoeff() <= core::kMaxCoordinate)) {
      src.Fail("surface point " + std::to_string(k + 1) +
               (file.empty() ? std::string() : " of '" + file + "'") + " (" +
               FormatNumber(p.x() * to_file) + ", " + FormatNumber(p.y() * to_file) + ", " +
               FormatNumber(p.z() * to_file) +
               ") is out of range; expected coordinates and elevations within +-" +
               FormatNumber(core::kMaxCoordinate * to_file) + " (file units)");
    }
    box.Add(p.x(), p.y());
  }
  CheckGridSize(where, box, options.spacing, to_file);
  GriddingReport rep;
  std::string error;
  if (!GridPoints(points, options, &out->grid, &rep, &error)) src.Fail(error);
  std::string merged;
  if (rep.merged > 0) {
    merged = ", " + std::to_string(rep.merged) +
             " point(s) at a plan position already taken merged (elevations averaged)";
  }
  out->notes.push_back("triangulation: " + std::to_string(rep.points) + " points" + merged + ", " +
                       std::to_string(rep.triangles) + " Delaunay triangles; " +
                       std::to_string(rep.nodes) + " nodes interpolated, " +
                       std::to_string(rep.outside_hull) + " holes outside the convex hull" +
                       (std::isfinite(options.max_edge)
                            ? ", " + std::to_string(rep.long_edge) +
                                  " holes in triangles with an edge longer than " +
                                  FormatNumber(options.max_edge * to_file) + " (max_edge)"
                            : std::string()));
}

std::vector<Eigen::Vector3d> ToSI(std::vector<Eigen::Vector3d> points, Units units) {
  for (Eigen::Vector3d& p : points)
    for (int k = 0; k < 3; ++k) p[k] = LengthToSI(p[k], units);
  return points;
}

void CheckPointCount(const JsonNode& where, const std::string& file, std::size_t n) {
  if (n < 3) {
    where.Fail("'" + file + "' holds " + std::to_string(n) +
               " point(s); expected at least 3 points");
  }
}

}  // namespace

std::string ResolvePath(const std::string& base_dir, const std::string& file) {
  const std::filesystem::path p(file);
  if (p.is_absolute() || base_dir.empty()) return p.string();
  return (std::filesystem::path(base_dir) / p).string();
}

std::string ResolveDataFile(const JsonNode& node, const std::string& base_dir) {
  const std::string name = node.String();
  if (name.empty()) node.Fail("expected a file name, relative to the site file's folder");
  const std::string file = ResolvePath(base_dir, name);
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    node.Fail("'" + file + "' is a folder; expected a data file");
  if (::access(file.c_str(), R_OK) != 0)
    node.Fail("cannot open file '" + file + "': " + std::strerror(errno));
  return file;
}

namespace {

// The data file named by `node`, recorded in out->files.
std::string DataFile(const JsonNode& node, const std::string& base_dir, Surface* out) {
  std::string file = ResolveDataFile(node, base_dir);
  out->files.push_back(file);
  return file;
}

// The raster (SI) onto the grid: its own cells, or resampled to `spacing`.
// Its extent and every elevation within the terrain's range (errors naming
// `file`).
void RasterInto(const RasterGrid& raster, const JsonNode& where, bool has_resolution,
                double spacing, Units units, const std::string& file, const std::string& what,
                Surface* out) {
  const double cell = LengthToSI(raster.cellsize, units);
  const double to_file = 1.0 / LengthToSI(1.0, units);
  CheckTerrainValue(LengthToSI(raster.x_center, units), to_file, file,
                    "the x of the lower-left cell's centre");
  CheckTerrainValue(LengthToSI(raster.y_center, units), to_file, file,
                    "the y of the lower-left cell's centre");
  CheckTerrainValue(LengthToSI(raster.x_center + (raster.ncols - 1) * raster.cellsize, units),
                    to_file, file, "the x of the last column's centre");
  CheckTerrainValue(LengthToSI(raster.y_center + (raster.nrows - 1) * raster.cellsize, units),
                    to_file, file, "the y of the top row's centre");
  for (int j = 0; j < raster.nrows; ++j)
    for (int i = 0; i < raster.ncols; ++i) {
      const double z = raster.at(i, j);
      if (!std::isnan(z))
        CheckTerrainValue(LengthToSI(z, units), to_file, file,
                          "the elevation of row " + std::to_string(raster.nrows - j) +
                              " (counted from the north), column " + std::to_string(i + 1));
    }
  if (!has_resolution) spacing = cell;
  Box box;
  box.Add(0, 0);
  box.Add((raster.ncols - 1) * cell, (raster.nrows - 1) * cell);
  CheckGridSize(where, box, spacing, 1.0 / LengthToSI(1.0, units));
  out->grid = RasterToHeightGrid(raster, LengthToSI(1.0, units), spacing);
  const std::string unit = std::string(" ") + LengthUnit(units);
  const std::string cells = std::to_string(raster.ncols) + " x " + std::to_string(raster.nrows) +
                            " cells of " + FormatNumber(raster.cellsize) + unit;
  if (std::abs(out->grid.spacing - cell) <= 1e-9 * cell) {
    out->notes.push_back("surface: " + what + ", " + cells + " (cell centres are the grid nodes)");
  } else {
    out->notes.push_back("surface: " + what + ", " + cells);
    out->resampled.push_back(
        "surface: " + cells + " resampled bilinearly to the resolution " +
        FormatNumber(out->grid.spacing * to_file) + unit + " (resolution): " +
        std::to_string(out->grid.nx) + " x " + std::to_string(out->grid.ny) + " nodes");
    out->notes.push_back(out->resampled.back());
  }
}

}  // namespace

namespace {

// What every source's reader needs of the surface object: the units, the
// data files' folder, the grid's spacing and the node its errors name, the
// triangulation's options and the CRS the site file names.
struct SurfaceSettings {
  Units units;
  std::string base_dir;
  double to_file = 1.0;           // m -> file units
  std::optional<JsonNode> resolution;
  double spacing = 0.0;           // the grid's, m
  JsonNode where;                 // the resolution's node, or the surface's
  GriddingOptions gridding;
  std::optional<JsonNode> crs;
  std::string named_crs;          // the CRS `crs` names, as WKT
};

// The one source key of `surface` (kSources).
std::string SourceOf(const JsonNode& surface) {
  std::vector<const char*> present;
  for (const char* k : kSources)
    if (surface.Has(k)) present.push_back(k);
  if (present.size() != 1) {
    std::string found;
    for (const char* k : present) found += std::string(found.empty() ? "" : ", ") + k;
    surface.Fail("expected exactly one surface source (one of " + SourceList() + "), found " +
                 (present.empty() ? std::string("none") : found));
  }
  return present[0];
}

// The settings of `surface` for its source, whose grid defaults to the
// virtual spheres' spacing.
SurfaceSettings ReadSurfaceSettings(const JsonNode& surface, const std::string& source,
                                    Units units, const std::string& base_dir,
                                    double sphere_spacing) {
  SurfaceSettings set{units, base_dir, 1.0 / LengthToSI(1.0, units), surface.Find("resolution"),
                      0.0, surface, {}, surface.Find("crs"), {}};
  set.spacing = set.resolution ? LengthToSI(set.resolution->Positive(), units) : sphere_spacing;
  if (set.resolution) set.where = *set.resolution;
  const bool from_points = source == "points" || source == "points_file" || source == "lidar";
  set.gridding.spacing = set.spacing;
  if (const std::optional<JsonNode> max_edge = surface.Find("max_edge")) {
    if (!from_points) {
      max_edge->Fail(
          "'max_edge' applies to triangulated points (points, points_file, lidar) "
          "only; expected no max_edge with " +
          source);
    }
    set.gridding.max_edge = LengthToSI(max_edge->Positive(), units);
  }
  // The CRS the site file names (checked against the data's own later).
  if (set.crs) {
    std::string error;
    if (!CrsFromUserInput(set.crs->Text(), &set.named_crs, &error)) {
      set.crs->Fail("not a coordinate reference system GDAL recognises (" + error +
                    "); expected e.g. \"EPSG:2154\" or a WKT string");
    }
  }
  return set;
}

// "points": inline [x, y, z] triples.
void ReadInlinePoints(const JsonNode& src, const SurfaceSettings& set, Surface* out) {
  std::vector<Eigen::Vector3d> points;
  for (const JsonNode& p : src.Array(3)) {
    const std::vector<double> v = p.Numbers(3);
    points.emplace_back(v[0], v[1], v[2]);
  }
  out->notes.push_back("surface: " + std::to_string(points.size()) + " inline points");
  GridInto(ToSI(std::move(points), set.units), set.where, src, "", set.gridding, set.to_file, out);
}

// "points_file": a text file of points.
void ReadPointsSource(const JsonNode& src, const SurfaceSettings& set, Surface* out) {
  const std::string file = DataFile(src, set.base_dir, out);
  std::vector<Eigen::Vector3d> points = ReadPointsFile(file);
  CheckPointCount(src, file, points.size());
  out->notes.push_back("surface: " + std::to_string(points.size()) + " points from " + file);
  GridInto(ToSI(std::move(points), set.units), set.where, src, file, set.gridding, set.to_file,
           out);
}

// "lidar": a scan with its offset and spin.
void ReadLidarSource(const JsonNode& src, const SurfaceSettings& set, Surface* out) {
  src.Keys(SiteKeysAt("$.surface.lidar"));
  const std::string file = DataFile(src.Get("file"), set.base_dir, out);
  LidarTransform transform;
  if (const std::optional<JsonNode> offset = src.Find("offset")) {
    if (offset->is_string()) {
      if (offset->String() != "auto") offset->Fail("expected \"auto\" or [x, y, z]");
      transform.auto_offset = true;
    } else {
      if (!offset->is_array()) offset->Fail("expected \"auto\" or [x, y, z]");
      const std::vector<double> v = offset->Numbers(3);
      transform.offset = Eigen::Vector3d(v[0], v[1], v[2]);
    }
  }
  if (const std::optional<JsonNode> spin = src.Find("spin_deg"))
    transform.spin_deg = spin->Number(-360.0, 360.0);
  if (set.crs && (transform.auto_offset || transform.offset.x() != 0.0 ||
                  transform.offset.y() != 0.0 || transform.spin_deg != 0.0)) {
    set.crs->Fail(
        "a LIDAR offset in plan or a spin moves the points out of any map frame; "
        "expected no 'crs' with them (or no offset in x, y and no spin)");
  }
  std::vector<Eigen::Vector3d> points = ReadLidarFile(file);
  CheckPointCount(src.Get("file"), file, points.size());
  const Eigen::Vector3d offset = ApplyLidarTransform(transform, &points);
  out->notes.push_back("surface: " + std::to_string(points.size()) + " LIDAR points from " + file +
                       ", offset (" + FormatNumber(offset.x()) + ", " + FormatNumber(offset.y()) +
                       ", " + FormatNumber(offset.z()) + ") subtracted, then spun " +
                       FormatNumber(transform.spin_deg) + " deg about Z");
  GridInto(ToSI(std::move(points), set.units), set.where, src.Get("file"), file, set.gridding,
           set.to_file, out);
}

// "grid_file": an ESRI ASCII grid.
void ReadGridFileSource(const JsonNode& src, const SurfaceSettings& set, Surface* out) {
  const std::string file = DataFile(src, set.base_dir, out);
  RasterInto(ReadEsriGrid(file), set.where, set.resolution.has_value(), set.spacing, set.units,
             file, "ESRI grid " + file, out);
}

// "raster": "dem.tif" or {"file": "dem.tif", "band": 2}, read by GDAL, its
// CRS checked against the one named.
void ReadRasterSource(const JsonNode& src, const SurfaceSettings& set, Surface* out) {
  int band = 1;
  JsonNode file_node = src;
  if (src.is_object()) {
    src.Keys(SiteKeysAt("$.surface.raster"));
    file_node = src.Get("file");
    if (const std::optional<JsonNode> b = src.Find("band"))
      band = static_cast<int>(b->Integer(1, 1'000'000));
  } else if (!src.is_string()) {
    src.Fail("expected a file name, or {\"file\": NAME, \"band\": N}");
  }
  const std::string file = DataFile(file_node, set.base_dir, out);
  RasterFile raster = ReadRaster(file, band);
  for (const std::string& f : raster.files)
    if (f != file) out->files.push_back(f);
  if (!raster.crs_wkt.empty()) {
    if (set.crs && !SameCrs(raster.crs_wkt, set.named_crs)) {
      set.crs->Fail("the raster '" + file + "' has the CRS " + CrsLabel(raster.crs_wkt) +
                    ", not the one named here (" + CrsLabel(set.named_crs) +
                    "); expected the same CRS, or no 'crs'");
    }
    if (const std::string problem = CrsUnitMismatch(raster.crs_wkt, set.units); !problem.empty())
      throw InputError(file, problem);
    out->crs_wkt = raster.crs_wkt;
  }
  out->gis = true;
  RasterInto(raster.grid, set.where, set.resolution.has_value(), set.spacing, set.units, file,
             "raster " + file + " (" + raster.driver + ", band " + std::to_string(band) + ")",
             out);
}

// "stl": triangle meshes, each of one material.
void ReadStlSource(const JsonNode& src, const SurfaceSettings& set,
                   const std::vector<std::string>& material_ids, Surface* out) {
  src.Keys(SiteKeysAt("$.surface.stl"));
  StlAxes axes = StlAxes::kXYZ;
  if (const std::optional<JsonNode> a = src.Find("axes")) {
    if (!StringToStlAxes(a->String(), &axes)) a->Fail("unknown axes (allowed: xyz, xzy)");
  }
  std::vector<TriangleSet> sets;
  Box box;
  for (const JsonNode& f : src.Get("files").Array(1)) {
    f.Keys(SiteKeysAt("$.surface.stl.files[]"));
    const JsonNode m = f.Get("material");
    const std::string id = m.String();
    const auto it = std::find(material_ids.begin(), material_ids.end(), id);
    if (it == material_ids.end()) {
      std::string list;
      for (const std::string& k : material_ids) list += (list.empty() ? "" : ", ") + k;
      m.Fail("unknown material '" + id + "' (materials: " + list + ")");
    }
    const std::string file = DataFile(f.Get("file"), set.base_dir, out);
    TriangleSet triangles;
    triangles.triangles = ReadStl(file, axes, LengthToSI(1.0, set.units));
    triangles.material = static_cast<int>(it - material_ids.begin());
    for (std::size_t k = 0; k < triangles.triangles.size(); ++k) {
      const Triangle& t = triangles.triangles[k];
      for (const Eigen::Vector3d* p : {&t.a, &t.b, &t.c}) {
        for (int c = 0; c < 3; ++c)
          CheckTerrainValue(
              (*p)[c], set.to_file, file,
              std::string("the ") + "xyz"[c] + " of a vertex of triangle " + std::to_string(k + 1));
        box.Add(p->x(), p->y());
      }
    }
    out->notes.push_back("surface: " + std::to_string(triangles.triangles.size()) +
                         " triangles from " + file + " (material " + id + ")");
    sets.push_back(std::move(triangles));
  }
  CheckGridSize(set.where, box, set.spacing, set.to_file);
  out->grid = SampleTriangles(sets, set.spacing);
  out->materials_from_source = true;
}

// Fails at `src` unless some grid cell has four valid corners: something to
// stand on.
void CheckSomeCell(const core::HeightGrid& g, const JsonNode& src) {
  bool any_cell = false;
  for (int j = 0; j + 1 < g.ny && !any_cell; ++j) {
    for (int i = 0; i + 1 < g.nx && !any_cell; ++i) {
      any_cell = !std::isnan(g.z[g.index(i, j)]) && !std::isnan(g.z[g.index(i + 1, j)]) &&
                 !std::isnan(g.z[g.index(i, j + 1)]) && !std::isnan(g.z[g.index(i + 1, j + 1)]);
    }
  }
  if (!any_cell) {
    src.Fail(
        "the surface has no grid cell with four valid corners (every cell touches a "
        "hole); expected data dense enough for the resolution");
  }
}

}  // namespace

Surface ReadSurface(const JsonNode& surface, Units units, const std::string& base_dir,
                    const std::vector<std::string>& material_ids) {
  surface.Keys(SiteKeysAt("$.surface"));
  Surface out;
  out.source = SourceOf(surface);
  // The virtual spheres' spacing, at which roughness is defined: the one
  // given, else a DEM's own grid, else 12 ft (kDefaultSphereSpacingM, which
  // a points or STL source's resolution defaults to).
  const std::optional<JsonNode> sphere_node = surface.Find("sphere_spacing");
  const bool given = sphere_node.has_value();
  const double given_spacing = given ? LengthToSI(sphere_node->Positive(), units) : 0.0;
  const SurfaceSettings set = ReadSurfaceSettings(surface, out.source, units, base_dir,
                                                  given ? given_spacing : kDefaultSphereSpacingM);
  out.crs_wkt = set.named_crs;
  const JsonNode src = surface.Get(out.source.c_str());
  if (out.source == "points") {
    ReadInlinePoints(src, set, &out);
  } else if (out.source == "points_file") {
    ReadPointsSource(src, set, &out);
  } else if (out.source == "lidar") {
    ReadLidarSource(src, set, &out);
  } else if (out.source == "grid_file") {
    ReadGridFileSource(src, set, &out);
  } else if (out.source == "raster") {
    ReadRasterSource(src, set, &out);
  } else {
    ReadStlSource(src, set, material_ids, &out);
  }
  if (set.crs) {
    if (const std::string problem = CrsUnitMismatch(out.crs_wkt, units); !problem.empty())
      set.crs->Fail(problem);
  }
  const bool dem = out.source == "grid_file" || out.source == "raster";
  const double sphere_spacing =
      given ? given_spacing : dem ? out.grid.spacing : kDefaultSphereSpacingM;
  if (std::abs(sphere_spacing - out.grid.spacing) > 1e-9 * sphere_spacing) {
    Box box;
    box.Add(out.grid.x(0), out.grid.y(0));
    box.Add(out.grid.x(out.grid.nx - 1), out.grid.y(out.grid.ny - 1));
    CheckGridSize(sphere_node ? *sphere_node : surface, box, sphere_spacing, set.to_file);
    const core::HeightGrid from = out.grid;
    out.grid = ResampleGrid(out.grid, sphere_spacing);
    const std::string unit = std::string(" ") + LengthUnit(units);
    out.resampled.push_back(
        "surface: the grid of " + FormatNumber(from.spacing * set.to_file) + unit + " (" +
        std::to_string(from.nx) + " x " + std::to_string(from.ny) +
        " nodes) resampled bilinearly to the virtual spheres' spacing " +
        FormatNumber(sphere_spacing * set.to_file) + unit + " (" + std::to_string(out.grid.nx) +
        " x " + std::to_string(out.grid.ny) + " nodes; " +
        (given ? "sphere_spacing" : "the default 12 ft of scattered points and STL") +
        ")");
    out.notes.push_back(out.resampled.back());
  }
  if (!out.crs_wkt.empty()) out.notes.push_back("crs: " + CrsLabel(out.crs_wkt));
  CheckSomeCell(out.grid, src);
  return out;
}

}  // namespace rockcal::sites
