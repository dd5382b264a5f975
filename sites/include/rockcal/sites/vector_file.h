// The one reader of vector GIS files (GeoPackage, Shapefile, GeoJSON, any
// format GDAL/OGR reads) that the site file names: material zones
// ("zones" with "field"), barrier lines ("barriers_file") and release areas
// (a rock group's "release": {"zone_file": ...}). It opens the file, picks
// the layer, finds the attribute fields, matches the layer's CRS with the
// terrain's, walks the features naming each ("layer 'L', feature FID"), and
// records the file among the site's inputs; each caller reads the
// geometries and attributes it needs (docs/reference/site-file.md).
#ifndef ROCKCAL_SITES_VECTOR_FILE_H_
#define ROCKCAL_SITES_VECTOR_FILE_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "rockcal/sites/gdal_util.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/site.h"

namespace rockcal::sites {

// What a kind of vector file is called in messages.
struct VectorFileKind {
  std::string name;      // "zone file", "barrier file", "release file"
  std::string holds;     // what its layer holds: "the zones", "the barriers", ...
  std::string expected;  // the formats expected: "a GeoPackage, ... of polygons"
};

class VectorFile final {
 public:
  // `file_node` names the file (resolved against `base_dir`); `layer_node`,
  // when there is one, the layer ("layer"; required when the file has
  // several, and failing at `where` when it is missing). Fails at the nodes
  // on an unreadable file or a missing layer, and matches the layer's CRS
  // with site->crs_wkt (adopted when the terrain has none).
  VectorFile(const JsonNode& file_node, const std::optional<JsonNode>& layer_node,
             const JsonNode& where, const std::string& base_dir, VectorFileKind kind, Site* site);

  const std::string& file() const { return file_; }
  const std::string& layer_name() const { return layer_name_; }
  // The attribute fields of the layer, in order.
  const std::vector<std::string>& fields() const { return fields_; }
  // The index of the attribute `name`: -1 when the layer has none and it is
  // optional; fails at the file's node, listing the fields and
  // `expected_fields`, when it is required.
  int Field(const std::string& name, bool required, const std::string& expected_fields) const;
  // Each feature in the layer's order with its place, "layer 'L', feature
  // FID"; `visit` throws InputError(file(), where + ": ...") on a bad one.
  void ForEach(const std::function<void(OGRFeatureH, const std::string& where)>& visit) const;
  // The file and its side files into site->inputs; site->gis becomes true.
  void Record(Site* site) const;

 private:
  JsonNode file_node_;
  std::string file_, layer_name_;
  VectorFileKind kind_;
  std::vector<std::string> fields_;
  gdal::Dataset ds_;
  OGRLayerH layer_ = nullptr;
};

// A GIS file's CRS (`wkt`, "" for none; `driver` GDAL's short name)
// against the terrain's (site->crs_wkt): the same, or adopted when the
// terrain has none (with a note). Fails at `file_node` naming the `kind` of
// file ("zone file") on differing CRSs or one not in the site's unit.
void MatchTerrainCrs(const JsonNode& file_node, const std::string& file, const std::string& wkt,
                     const std::string& driver, const std::string& kind, Site* site);

// A feature's attribute `k` as text; "" when it has none or it is not set.
std::string FeatureText(OGRFeatureH feature, int k);

// A feature's geometry of type `single`, or the one member of a `multi` of
// one; throws InputError(file, where + ": a <type>; expected " + expected)
// for another geometry or none.
OGRGeometryH SingleGeometry(OGRFeatureH feature, OGRwkbGeometryType single,
                            OGRwkbGeometryType multi, const std::string& expected,
                            const std::string& file, const std::string& where);

// The outer ring of a feature's Polygon (or a MultiPolygon of one polygon)
// in plan, in SI (`to_si` per file unit), without its closing vertex. Throws
// InputError(file, where + ": ...") for another geometry, a polygon with
// holes or one of fewer than 3 vertices.
std::vector<Eigen::Vector2d> FeaturePolygon(OGRFeatureH feature, double to_si,
                                            const std::string& file, const std::string& where);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_VECTOR_FILE_H_
