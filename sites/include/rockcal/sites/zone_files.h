// Material zones from GIS files: the site file's top-level "zones" object,
// either polygons of a vector file GDAL reads (GeoPackage, Shapefile,
// GeoJSON, ...) whose attribute names a material, or a raster of classes
// mapped to materials.
#ifndef ROCKCAL_SITES_ZONE_FILES_H_
#define ROCKCAL_SITES_ZONE_FILES_H_

#include <string>
#include <vector>

#include "rockcal/sites/geometry.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/site.h"

namespace rockcal::sites {

// Reads `zones` and assigns materials to the nodes of site->scene.grid
// (whose materials, site->scene.materials, are read already):
//
//   {"file": "zones.gpkg", "field": "material", "layer": "optional name"}
//     Each feature is a Polygon or MultiPolygon whose attribute `field` holds
//     a material id. The features are burnt in the layer's order with GDAL's
//     rasterizer onto a raster whose cell centres are the grid nodes: a node
//     takes the material of the last feature whose polygon holds it (GDAL's
//     rule: the node inside the polygon; a node exactly on an edge may fall
//     either way). `layer` is required when the file has several layers.
//   {"file": "classes.tif", "classes": {"1": "bedrock", "2": "talus"}}
//     Band 1 of a raster GDAL reads, sampled at the nodes with GDALWarp
//     (nearest neighbour); the class value there names the material. Nodata,
//     and nodes off the raster, claim nothing (the node keeps the first
//     material, or the STL file's).
//
// The file's coordinates are in the site's frame and length unit. When both
// the file and the terrain (site->crs_wkt) have a CRS they must be the same;
// when only the file has one, the site adopts it. The file (with its side
// files) goes into site->inputs, a note into site->notes, and site->gis
// becomes true. Throws InputError naming the site file and JSON path, or the
// zone file and feature, with what was expected: an unreadable file, a
// missing layer or field, a feature that is not a polygon or whose value is
// not a material id (the message lists the ids), a class value missing from
// `classes`, differing CRSs, or a file that claims no grid node at all.
void ApplyZoneFile(const JsonNode& zones, const std::string& base_dir, Site* site);

// One barrier line of a barrier file, and where it is ("layer 'L', feature
// N") for the checks its site makes after.
struct BarrierFeature {
  core::Partition barrier;  // Partition::Kind::kLine, SI
  std::string file;         // the barrier file, as resolved
  std::string where;
};

// Reads the site file's "barriers_file" (docs/reference/site-file.md#barriers):
// a file name, or {"file": ..., "layer": ...} (`layer` required when the
// file has several). Each feature is a LineString (or a MultiLineString of
// one line) in the site's frame and length unit, with the attributes `id`,
// `height` (site length unit, > 0), `energy_kj` (kJ, > 0) and, optionally,
// `stops` (true/false, 1/0, yes/no; empty or absent: false). The CRS is
// matched as a zone file's; the file goes into site->inputs and site->gis
// becomes true. The lines' vertex counts, ids and extent are the caller's
// to check. Throws InputError naming the site file and JSON path, or the
// barrier file and feature, with what was expected.
std::vector<BarrierFeature> ReadBarrierFile(const JsonNode& node, const std::string& base_dir,
                                            Site* site);

// Reads a rock group's release "zone_file" (docs/reference/site-file.md,
// `$.rocks[].release`): a file name, or {"file": ..., "layer": ..., "id":
// ...}. The release area is the polygon feature whose attribute `id` holds
// "id", or, without "id", the layer's only feature: a Polygon (or a
// MultiPolygon of one polygon) without holes, in the site's frame and length
// unit, enclosing an area, its edges not crossing. The CRS is matched as a
// zone file's; the file goes into site->inputs and site->gis becomes true.
// Throws InputError naming the site file and JSON path, or the release file
// and feature, with what was expected. Returns the polygon in SI; *where is
// set to its place in the file ("'areas.gpkg', layer 'L', feature 3").
Polygon ReadReleaseFile(const JsonNode& node, const std::string& base_dir, Site* site,
                        std::string* where);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_ZONE_FILES_H_
