#include "rockcal/sites/vector_file.h"

#include <utility>

#include "rockcal/sites/crs.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/surface.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::sites {
namespace {

// The layer's CRS as WKT, "" for none. GeoPackage's reserved "Undefined
// geographic SRS" and "Undefined Cartesian SRS" (srs_id 0 and -1, with no
// authority) are a layer without a CRS too.
std::string LayerCrs(OGRLayerH layer) {
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(layer);
  if (!srs) return "";
  const char* name = OSRGetName(srs);
  const std::string n = name ? name : "";
  if ((n == "Undefined geographic SRS" || n == "Undefined Cartesian SRS") &&
      !OSRGetAuthorityName(srs, nullptr))
    return "";
  return gdal::WktOf(srs);
}

}  // namespace

VectorFile::VectorFile(const JsonNode& file_node, const std::optional<JsonNode>& layer_node,
                       const JsonNode& where, const std::string& base_dir, VectorFileKind kind,
                       Site* site)
    : file_node_(file_node), kind_(std::move(kind)) {
  file_ = ResolveDataFile(file_node, base_dir);
  if (file_.rfind("/vsi", 0) != 0) CheckInputFile(file_);  // GDAL's virtual paths excepted
  gdal::Init();
  {
    gdal::ErrorCapture errors;
    ds_.reset(
        GDALOpenEx(file_.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!ds_) {
      const std::string why = errors.message().empty() ? "" : " (GDAL: " + errors.message() + ")";
      file_node.Fail("'" + file_ + "' is not a vector file GDAL can read" + why + "; expected " +
                     kind_.expected);
    }
  }
  // The layer: the one "layer" names, or the file's only one.
  std::vector<std::string> layer_names;
  for (int k = 0; k < GDALDatasetGetLayerCount(ds_.get()); ++k)
    layer_names.emplace_back(OGR_L_GetName(GDALDatasetGetLayer(ds_.get(), k)));
  if (layer_node) {
    layer_ = GDALDatasetGetLayerByName(ds_.get(), layer_node->String().c_str());
    if (!layer_) {
      layer_node->Fail("the " + kind_.name + " '" + file_ + "' has no such layer (layers: " +
                       Join(layer_names) + ")");
    }
  } else if (layer_names.size() == 1) {
    layer_ = GDALDatasetGetLayer(ds_.get(), 0);
  } else {
    where.Fail("the " + kind_.name + " '" + file_ + "' has " + std::to_string(layer_names.size()) +
               " layers" + (layer_names.empty() ? "" : " (" + Join(layer_names) + ")") +
               "; expected \"layer\" naming the one with " + kind_.holds);
  }
  layer_name_ = OGR_L_GetName(layer_);
  OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer_);
  for (int k = 0; k < OGR_FD_GetFieldCount(defn); ++k)
    fields_.emplace_back(OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, k)));

  MatchTerrainCrs(file_node, file_, LayerCrs(layer_),
                  GDALGetDriverShortName(GDALGetDatasetDriver(ds_.get())), kind_.name, site);
}

void MatchTerrainCrs(const JsonNode& file_node, const std::string& file, const std::string& wkt,
                     const std::string& driver, const std::string& kind, Site* site) {
  if (wkt.empty()) return;
  // GeoJSON without a "crs" member is WGS 84 (RFC 7946): say so.
  const std::string hint =
      driver == "GeoJSON"
          ? " (a GeoJSON file without a \"crs\" member is WGS 84 longitude and latitude, by "
            "RFC 7946)"
          : "";
  if (site->crs_wkt.empty()) {
    if (const std::string problem = CrsUnitMismatch(wkt, site->units); !problem.empty())
      file_node.Fail(kind + " '" + file + "': " + problem + hint);
    site->crs_wkt = wkt;
    site->notes.push_back("crs: " + CrsLabel(wkt) + ", adopted from the " + kind + " " + file);
  } else if (!SameCrs(site->crs_wkt, wkt)) {
    file_node.Fail("the " + kind + " '" + file + "' has the CRS " + CrsLabel(wkt) +
                   ", the terrain " + CrsLabel(site->crs_wkt) +
                   "; expected the same CRS (reproject the file first, e.g. ogr2ogr -t_srs)" +
                   hint);
  }
}

int VectorFile::Field(const std::string& name, bool required,
                      const std::string& expected_fields) const {
  const int k = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(layer_), name.c_str());
  if (k < 0 && required) {
    file_node_.Fail("layer '" + layer_name_ + "' of the " + kind_.name + " '" + file_ +
                    "' has no field '" + name + "' (fields: " + Join(fields_) + "); expected " +
                    expected_fields);
  }
  return k;
}

void VectorFile::ForEach(
    const std::function<void(OGRFeatureH, const std::string& where)>& visit) const {
  OGR_L_ResetReading(layer_);
  while (gdal::Feature f{OGR_L_GetNextFeature(layer_)}) {
    const auto feature = static_cast<OGRFeatureH>(f.get());
    visit(feature,
          "layer '" + layer_name_ + "', feature " + std::to_string(OGR_F_GetFID(feature)));
  }
}

void VectorFile::Record(Site* site) const {
  std::vector<std::string> files = gdal::FileList(ds_.get());
  if (files.empty()) files.push_back(file_);
  site->inputs.insert(site->inputs.end(), files.begin(), files.end());
  site->gis = true;
}

std::string FeatureText(OGRFeatureH feature, int k) {
  return k >= 0 && OGR_F_IsFieldSetAndNotNull(feature, k) ? OGR_F_GetFieldAsString(feature, k) : "";
}

OGRGeometryH SingleGeometry(OGRFeatureH feature, OGRwkbGeometryType single,
                            OGRwkbGeometryType multi, const std::string& expected,
                            const std::string& file, const std::string& where) {
  OGRGeometryH g = OGR_F_GetGeometryRef(feature);
  OGRwkbGeometryType type = g ? OGR_GT_Flatten(OGR_G_GetGeometryType(g)) : wkbNone;
  if (type == multi && OGR_G_GetGeometryCount(g) == 1) {
    g = OGR_G_GetGeometryRef(g, 0);
    type = OGR_GT_Flatten(OGR_G_GetGeometryType(g));
  }
  if (type != single)
    throw InputError(file, where + ": " +
                               (g ? std::string("a ") + OGRGeometryTypeToName(type)
                                  : std::string("no geometry")) +
                               "; expected " + expected);
  return g;
}

std::vector<Eigen::Vector2d> FeaturePolygon(OGRFeatureH feature, double to_si,
                                            const std::string& file, const std::string& where) {
  auto fail = [&](const std::string& what) { throw InputError(file, where + ": " + what); };
  OGRGeometryH g = SingleGeometry(feature, wkbPolygon, wkbMultiPolygon,
                                  "a Polygon (or a MultiPolygon of one polygon)", file, where);
  if (OGR_G_GetGeometryCount(g) != 1) {
    fail(OGR_G_GetGeometryCount(g) == 0
             ? std::string("an empty polygon; expected a polygon of at least 3 vertices")
             : "a polygon with " + std::to_string(OGR_G_GetGeometryCount(g) - 1) +
                   " hole(s); expected a polygon without holes");
  }
  OGRGeometryH ring = OGR_G_GetGeometryRef(g, 0);
  std::vector<Eigen::Vector2d> out;
  for (int k = 0; k < OGR_G_GetPointCount(ring); ++k)
    out.emplace_back(OGR_G_GetX(ring, k) * to_si, OGR_G_GetY(ring, k) * to_si);
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();  // the closing vertex
  if (out.size() < 3)
    fail("a polygon of " + std::to_string(out.size()) +
         " distinct vertices; expected at least 3");
  return out;
}

}  // namespace rockcal::sites
