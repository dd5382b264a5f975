#include "rockcal/sites/zone_files.h"

#include <gdal_alg.h>
#include <gdal_utils.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "rockcal/sites/crs.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/gdal_util.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/surface.h"
#include "rockcal/sites/text_reader.h"
#include "rockcal/sites/vector_file.h"

namespace rockcal::sites {
namespace {

std::vector<std::string> MaterialIds(const Site& site) {
  std::vector<std::string> ids;
  for (const core::Material& m : site.scene.materials) ids.push_back(m.id);
  return ids;
}

struct GeometryDestroyer {
  void operator()(void* g) const { OGR_G_DestroyGeometry(static_cast<OGRGeometryH>(g)); }
};
using Geometry = std::unique_ptr<void, GeometryDestroyer>;

// What the zone file claimed, for the checks and notes.
struct Claims {
  std::vector<int> material;  // per node: the material index claimed, or -1
  int claimed = 0;
};

// A vector file's features: a (multi)polygon and a material each.
struct ZoneFeatures {
  std::vector<Geometry> geometries;
  std::vector<int> material;  // per feature
  std::vector<GIntBig> fids;
};

// Each feature of the zone file with its material id in field
// `field_index` (one of `ids`); empty geometries left out.
ZoneFeatures ReadZoneFeatures(const VectorFile& vf, int field_index, const std::string& field,
                              const std::vector<std::string>& ids) {
  ZoneFeatures out;
  vf.ForEach([&](OGRFeatureH feature, const std::string& where) {
    OGRGeometryH geometry = OGR_F_GetGeometryRef(feature);
    const OGRwkbGeometryType type =
        geometry ? OGR_GT_Flatten(OGR_G_GetGeometryType(geometry)) : wkbNone;
    if (type != wkbPolygon && type != wkbMultiPolygon) {
      throw InputError(vf.file(), where + ": " +
                                      (geometry ? std::string("a ") + OGRGeometryTypeToName(type)
                                                : std::string("no geometry")) +
                                      "; expected a Polygon or a MultiPolygon");
    }
    const std::string id = FeatureText(feature, field_index);
    if (id.empty()) {
      throw InputError(vf.file(), where + ": field '" + field +
                                      "' is empty; expected a material id (materials: " +
                                      Join(ids) + ")");
    }
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) {
      throw InputError(vf.file(), where + ": field '" + field + "' holds " + Excerpt(id) +
                                      ", not a material of the site (materials: " + Join(ids) +
                                      ")");
    }
    if (OGR_G_IsEmpty(geometry)) return;
    out.geometries.emplace_back(OGR_G_Clone(geometry));
    out.material.push_back(static_cast<int>(it - ids.begin()));
    out.fids.push_back(OGR_F_GetFID(feature));
  });
  return out;
}

// Burns feature k + 1 (0: none) onto the site's nodes, so that each node
// knows its last feature, and counts each feature's nodes.
Claims BurnZones(const ZoneFeatures& features, const std::string& file, const Site& site,
                 std::vector<int>* nodes_of_feature) {
  const std::vector<Geometry>& geometries = features.geometries;
  const std::vector<int>& material = features.material;
  const core::HeightGrid& grid = site.scene.grid;
  const double to_file = 1.0 / LengthToSI(1.0, site.units);
  gdal::Dataset raster = gdal::NodeRaster(grid.nx, grid.ny, grid.x0 * to_file, grid.y0 * to_file,
                                          grid.spacing * to_file, GDT_Int32, 0.0, "");
  std::vector<OGRGeometryH> handles;
  std::vector<double> burn;
  for (std::size_t k = 0; k < geometries.size(); ++k) {
    handles.push_back(static_cast<OGRGeometryH>(geometries[k].get()));
    burn.push_back(static_cast<double>(k + 1));
  }
  int band = 1;
  gdal::ErrorCapture errors;
  if (!handles.empty() &&
      GDALRasterizeGeometries(raster.get(), 1, &band, static_cast<int>(handles.size()),
                              handles.data(), nullptr, nullptr, burn.data(), nullptr, nullptr,
                              nullptr) != CE_None) {
    throw InputError(file, "GDAL cannot rasterize the zones (" + errors.message() + ")");
  }
  std::vector<std::int32_t> cells(static_cast<std::size_t>(grid.nx) * grid.ny);
  gdal::ReadNodeRaster(raster.get(), GDT_Int32, cells.data());

  Claims claims;
  claims.material.assign(cells.size(), -1);
  nodes_of_feature->assign(geometries.size(), 0);
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      const std::int32_t k = cells[static_cast<std::size_t>(grid.ny - 1 - j) * grid.nx + i];
      if (k <= 0) continue;
      ++(*nodes_of_feature)[static_cast<std::size_t>(k - 1)];
      claims.material[static_cast<std::size_t>(grid.index(i, j))] = material[k - 1];
      ++claims.claimed;
    }
  }
  return claims;
}

// The polygons of a vector file, burnt in order onto the nodes.
Claims FromVector(const JsonNode& zones, const VectorFile& vf, Site* site) {
  const std::string& file = vf.file();
  const std::string& layer_name = vf.layer_name();
  const JsonNode field_node = zones.Get("field");
  const std::string field = field_node.String();
  const int field_index = vf.Field(field, false, "");
  if (field_index < 0) {
    field_node.Fail("layer '" + layer_name + "' of the zone file '" + file +
                    "' has no such field (fields: " + Join(vf.fields()) + ")");
  }
  const ZoneFeatures features = ReadZoneFeatures(vf, field_index, field, MaterialIds(*site));
  const std::vector<GIntBig>& fids = features.fids;
  std::vector<int> nodes_of_feature;
  Claims claims = BurnZones(features, file, *site, &nodes_of_feature);
  std::vector<std::string> idle;
  for (std::size_t k = 0; k < fids.size(); ++k)
    if (nodes_of_feature[k] == 0) idle.push_back(std::to_string(fids[k]));
  std::string note = "zones: " + std::to_string(fids.size()) + " polygon features of " + file +
                     " (layer " + layer_name + ", field " + field + ") claim " +
                     std::to_string(claims.claimed) + " nodes";
  if (!idle.empty()) {
    if (idle.size() > 10) {
      idle.resize(10);
      idle.push_back("...");
    }
    note +=
        "; features holding no grid node (off the terrain, smaller than a cell, or under "
        "later features): FID " +
        Join(idle);
  }
  site->notes.push_back(note);
  return claims;
}

// A raster of classes, sampled at the nodes (nearest neighbour).
Claims FromClasses(const JsonNode& zones, const std::string& file, GDALDatasetH ds, Site* site) {
  const JsonNode file_node = zones.Get("file");
  const JsonNode classes_node = zones.Get("classes");
  if (!classes_node.is_object() || classes_node.raw().empty())
    classes_node.Fail("expected an object {\"CLASS VALUE\": \"material id\", ...}");
  const std::vector<std::string> ids = MaterialIds(*site);
  std::map<double, int> classes;
  std::vector<std::string> class_names;
  for (const auto& item : classes_node.raw().items()) {
    const JsonNode value = classes_node.Get(item.key().c_str());
    double key = 0.0;
    if (!ParseNumber(item.key(), &key)) {
      value.Fail("the key " + Excerpt(item.key()) +
                 " is not a number; expected class values of the raster as keys");
    }
    const std::string id = value.String();
    const auto it = std::find(ids.begin(), ids.end(), id);
    if (it == ids.end()) value.Fail("unknown material '" + id + "' (materials: " + Join(ids) + ")");
    classes[key] = static_cast<int>(it - ids.begin());
    class_names.push_back(item.key());
  }
  if (GDALGetRasterCount(ds) < 1) {
    file_node.Fail("the zone file '" + file +
                   "' holds no raster band; expected a raster of "
                   "classes");
  }
  double gt[6];
  if (GDALGetGeoTransform(ds, gt) != CE_None) {
    throw InputError(file,
                     "has no georeferencing (no geotransform); expected a georeferenced "
                     "raster of classes");
  }
  const std::string wkt = gdal::WktOf(GDALGetSpatialRef(ds));
  MatchTerrainCrs(file_node, file, wkt, GDALGetDriverShortName(GDALGetDatasetDriver(ds)),
                  "zone file", site);

  const core::HeightGrid& grid = site->scene.grid;
  const double to_file = 1.0 / LengthToSI(1.0, site->units);
  const double kUnset = std::numeric_limits<double>::quiet_NaN();
  gdal::Dataset target = gdal::NodeRaster(grid.nx, grid.ny, grid.x0 * to_file, grid.y0 * to_file,
                                          grid.spacing * to_file, GDT_Float64, kUnset, wkt);
  gdal::ErrorCapture errors;
  const char* const args[] = {"-r", "near", "-dstnodata", "nan", "-q", nullptr};
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(const_cast<char**>(args), nullptr);
  GDALDatasetH source = ds;
  int usage_error = 0;
  GDALDatasetH done = GDALWarp(nullptr, target.get(), 1, &source, options, &usage_error);
  GDALWarpAppOptionsFree(options);
  if (!done) throw InputError(file, "GDAL cannot sample the classes (" + errors.message() + ")");
  std::vector<double> cells(static_cast<std::size_t>(grid.nx) * grid.ny);
  gdal::ReadNodeRaster(target.get(), GDT_Float64, cells.data());

  Claims claims;
  claims.material.assign(cells.size(), -1);
  std::map<double, int> count;
  int unclaimed = 0;
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      const double c = cells[static_cast<std::size_t>(grid.ny - 1 - j) * grid.nx + i];
      if (std::isnan(c)) {
        ++unclaimed;
        continue;
      }
      const auto it = classes.find(c);
      if (it == classes.end()) {
        throw InputError(file, "class value " + FormatNumber(c) + " (at grid node " +
                                   FormatNumber(grid.x(i) * to_file) + ", " +
                                   FormatNumber(grid.y(j) * to_file) +
                                   ") is not in \"classes\" (classes: " + Join(class_names) +
                                   "); expected every class on the terrain mapped to a material");
      }
      claims.material[static_cast<std::size_t>(grid.index(i, j))] = it->second;
      ++claims.claimed;
      ++count[c];
    }
  }
  std::string note = "zones: classes of " + file + " at the nodes:";
  for (const auto& [value, index] : classes) {
    note += " " + FormatNumber(value) + " -> " + ids[static_cast<std::size_t>(index)] + " " +
            std::to_string(count[value]) + " nodes,";
  }
  site->notes.push_back(note + " nodata or off the raster " + std::to_string(unclaimed) + " nodes");
  return claims;
}

}  // namespace

void ApplyZoneFile(const JsonNode& zones, const std::string& base_dir, Site* site) {
  zones.Keys(SiteKeysAt("$.zones"));
  const bool vector = zones.Has("field");
  if (vector == zones.Has("classes")) {
    zones.Fail(
        "expected exactly one of 'field' (the attribute of a vector file's polygons "
        "that holds material ids) or 'classes' (a raster's class values -> material "
        "ids)");
  }
  if (!vector && zones.Has("layer"))
    zones.Get("layer").Fail("'layer' goes with a vector file ('field') only");
  const JsonNode file_node = zones.Get("file");
  std::string file;
  Claims claims;
  if (vector) {
    const VectorFile vf(file_node, zones.Find("layer"), zones, base_dir,
                        {"zone file", "the zones",
                         "a GeoPackage, Shapefile, GeoJSON or another vector format GDAL reads "
                         "(with \"field\")"},
                        site);
    file = vf.file();
    claims = FromVector(zones, vf, site);
    vf.Record(site);
  } else {
    file = ResolveDataFile(file_node, base_dir);
    if (file.rfind("/vsi", 0) != 0) CheckInputFile(file);  // GDAL's virtual paths excepted
    gdal::Init();
    gdal::Dataset ds;
    {
      gdal::ErrorCapture errors;
      ds.reset(
          GDALOpenEx(file.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
      if (!ds) {
        const std::string why =
            errors.message().empty() ? "" : " (GDAL: " + errors.message() + ")";
        file_node.Fail("'" + file + "' is not a raster file GDAL can read" + why +
                       "; expected a GeoTIFF or another raster GDAL reads (with \"classes\")");
      }
    }
    claims = FromClasses(zones, file, ds.get(), site);
    std::vector<std::string> files = gdal::FileList(ds.get());
    if (files.empty()) files.push_back(file);
    site->inputs.insert(site->inputs.end(), files.begin(), files.end());
    site->gis = true;
  }
  if (claims.claimed == 0) {
    const core::HeightGrid& grid = site->scene.grid;
    const double to_file = 1.0 / LengthToSI(1.0, site->units);
    file_node.Fail("the zone file '" + file + "' claims no grid node (the terrain spans x " +
                   FormatNumber(grid.x(0) * to_file) + " to " +
                   FormatNumber(grid.x(grid.nx - 1) * to_file) + ", y " +
                   FormatNumber(grid.y(0) * to_file) + " to " +
                   FormatNumber(grid.y(grid.ny - 1) * to_file) +
                   "); expected zones over the terrain, in the site's frame and unit");
  }
  std::vector<int>& material = site->scene.grid.material;
  for (std::size_t n = 0; n < material.size(); ++n)
    if (claims.material[n] >= 0) material[n] = claims.material[n];
}

std::vector<BarrierFeature> ReadBarrierFile(const JsonNode& node, const std::string& base_dir,
                                            Site* site) {
  // A file name, or {"file": ..., "layer": ...}.
  const JsonNode file_node = node.is_string() ? node : node.Get("file");
  if (!node.is_string()) node.Keys(SiteKeysAt("$.barriers_file"));
  const VectorFile vf(file_node, node.is_string() ? std::nullopt : node.Find("layer"), node,
                      base_dir,
                      {"barrier file", "the barriers",
                       "a GeoPackage, Shapefile, GeoJSON or another vector format GDAL reads, "
                       "of lines"},
                      site);
  const std::string& file = vf.file();
  const std::string fields = "the fields id, height, energy_kj and, optionally, stops";
  const int id_k = vf.Field("id", true, fields), height_k = vf.Field("height", true, fields),
            energy_k = vf.Field("energy_kj", true, fields),
            stops_k = vf.Field("stops", false, fields);
  const double to_si = LengthToSI(1.0, site->units);
  std::vector<BarrierFeature> out;
  vf.ForEach([&](OGRFeatureH feature, const std::string& where) {
    BarrierFeature b;
    b.file = file;
    b.where = where;
    auto fail = [&](const std::string& what) { throw InputError(file, b.where + ": " + what); };
    OGRGeometryH g = SingleGeometry(
        feature, wkbLineString, wkbMultiLineString,
        "a LineString (or a MultiLineString of one line): the barrier in plan", file, b.where);
    core::Partition& part = b.barrier;
    part.kind = core::Partition::Kind::kLine;
    part.id = FeatureText(feature, id_k);
    for (int k = 0; k < OGR_G_GetPointCount(g); ++k)
      part.line.emplace_back(OGR_G_GetX(g, k) * to_si, OGR_G_GetY(g, k) * to_si);
    auto number = [&](int k, const char* name, const char* unit) {
      const std::string text = FeatureText(feature, k);
      double v = 0.0;
      if (!ParseNumber(text, &v) || !(v > 0.0) || !std::isfinite(v)) {
        fail(std::string("field '") + name + "' holds " + Excerpt(text) +
             "; expected a number > 0" + unit);
      }
      return v;
    };
    part.height =
        number(height_k, "height", (std::string(" (") + LengthUnit(site->units) + ")").c_str()) *
        to_si;
    part.capacity = number(energy_k, "energy_kj", " (kJ)") * 1e3;
    std::string stops = FeatureText(feature, stops_k);
    std::transform(stops.begin(), stops.end(), stops.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (stops == "1" || stops == "true" || stops == "yes") {
      part.stops = true;
    } else if (!(stops.empty() || stops == "0" || stops == "false" || stops == "no")) {
      fail("field 'stops' holds " + Excerpt(stops) +
           "; expected true or false (1 or 0, yes or no; empty: false)");
    }
    out.push_back(std::move(b));
  });
  if (out.empty())
    file_node.Fail("layer '" + vf.layer_name() + "' of the barrier file '" + file +
                   "' holds no feature; expected at least one barrier line");
  vf.Record(site);
  return out;
}

Polygon ReadReleaseFile(const JsonNode& node, const std::string& base_dir, Site* site,
                        std::string* where_out) {
  // A file name, or {"file": ..., "layer": ..., "id": ...}.
  const JsonNode file_node = node.is_string() ? node : node.Get("file");
  if (!node.is_string()) node.Keys(SiteKeysAt("$.rocks[].release.zone_file"));
  const std::optional<JsonNode> id_node = node.is_string() ? std::nullopt : node.Find("id");
  const VectorFile vf(file_node, node.is_string() ? std::nullopt : node.Find("layer"), node,
                      base_dir,
                      {"release file", "the release areas",
                       "a GeoPackage, Shapefile, GeoJSON or another vector format GDAL reads, "
                       "of polygons"},
                      site);
  const std::string& file = vf.file();
  const std::string wanted = id_node ? id_node->String() : "";
  const int id_k =
      vf.Field("id", id_node.has_value(), "the field id (the release area's name)");
  const double to_si = LengthToSI(1.0, site->units);
  Polygon polygon;
  std::string found_where;
  std::vector<std::string> ids;
  int features = 0;
  vf.ForEach([&](OGRFeatureH feature, const std::string& where) {
    ++features;
    const std::string id = FeatureText(feature, id_k);
    ids.push_back(id.empty() ? "(none)" : id);
    if (id_node ? id != wanted : features > 1) return;  // without "id": the only one
    if (!found_where.empty()) {
      throw InputError(file, where + ": its id " + Excerpt(wanted) + " is also " + found_where +
                                 "'s; expected the release areas' ids unique");
    }
    polygon = FeaturePolygon(feature, to_si, file, where);
    double scale = 0.0;
    for (const Eigen::Vector2d& v : polygon) scale = std::max(scale, (v - polygon[0]).norm());
    if (!(std::abs(SignedArea(polygon)) > 1e-9 * scale * scale))
      throw InputError(file, where + ": a degenerate polygon (its vertices enclose no area)");
    if (const auto edges = FindSelfIntersection(polygon)) {
      throw InputError(file, where + ": a self-intersecting polygon (edge " +
                                 std::to_string(edges->first) + " meets edge " +
                                 std::to_string(edges->second) +
                                 "); expected a simple polygon whose edges meet only at shared "
                                 "vertices");
    }
    found_where = where;
  });
  if (found_where.empty()) {
    if (id_node)
      id_node->Fail("layer '" + vf.layer_name() + "' of the release file '" + file +
                    "' has no feature whose id is " + Excerpt(wanted) + " (ids: " + Join(ids) + ")");
    file_node.Fail("layer '" + vf.layer_name() + "' of the release file '" + file +
                   "' holds no feature; expected one release area");
  }
  if (!id_node && features > 1) {
    node.Fail("the release file '" + file + "' has " + std::to_string(features) +
              " features; expected \"id\" naming the release area (ids: " + Join(ids) + ")");
  }
  vf.Record(site);
  *where_out = "'" + file + "', " + found_where;
  return polygon;
}

}  // namespace rockcal::sites
