#include "rockcal/sites/zone_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "gis_files.h"
#include "rockcal/sites/site.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using ::testing::Contains;
using ::testing::EndsWith;
using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::RasterSpec;
using testing::TempDir;
using testing::WriteRaster;
using testing::WriteZones;
using testing::ZoneFeature;
using Json = nlohmann::json;

// A 100 m x 50 m plane, nodes every 5 m; three materials; zones from a file.
Json BaseSite(const Json& zones) {
  Json site = Json::parse(R"({
    "name": "zones", "units": "si",
    "surface": {"resolution": 5, "sphere_spacing": 5, "points": [[0, 0, 50], [100, 0, 0], [0, 50, 50], [100, 50, 0]]},
    "materials": [
      {"id": "rock", "hardness": 0.6, "roughness": 0.5},
      {"id": "talus", "hardness": 0.3, "roughness": 1.0},
      {"id": "soil", "hardness": 0.2, "roughness": 1.0}
    ],
    "rocks": [{"count": 1, "shape": "sphere", "size": 1, "unit_weight": 26,
               "release": {"point": [10, 25]}}]
  })");
  site["zones"] = zones;
  return site;
}

// talus from x = 42, soil from x = 72 on top of it (the later feature wins).
std::vector<ZoneFeature> TwoBands() {
  return {{"POLYGON ((42 -1, 101 -1, 101 51, 42 51, 42 -1))", "talus"},
          {"POLYGON ((72 -1, 101 -1, 101 51, 72 51, 72 -1))", "soil"}};
}

Site Load(const TempDir& dir, const Json& site) {
  return LoadSite(dir.Write("site.json", site.dump(2)));
}

std::string LoadError(const TempDir& dir, const Json& site) {
  const std::string path = dir.Write("site.json", site.dump(2));
  return ErrorOf([&] { LoadSite(path); });
}

// The material id of the node at (x, y).
std::string MaterialAt(const Site& site, double x, double y) {
  const core::HeightGrid& g = site.scene.grid;
  const int i = static_cast<int>(std::lround((x - g.x0) / g.spacing));
  const int j = static_cast<int>(std::lround((y - g.y0) / g.spacing));
  return site.scene.materials[static_cast<std::size_t>(g.material[g.index(i, j)])].id;
}

void ExpectBands(const Site& site, const std::string& what) {
  for (double y : {0.0, 25.0, 50.0}) {
    for (double x = 0; x <= 100; x += 5) {
      const char* want = x < 42 ? "rock" : x < 72 ? "talus" : "soil";
      EXPECT_EQ(MaterialAt(site, x, y), want) << what << " node " << x << ", " << y;
    }
  }
}

TEST(ApplyZoneFile, PolygonsOfGeoPackageShapefileAndGeoJson) {
  const std::vector<std::pair<std::string, std::string>> formats = {
      {"GPKG", "zones.gpkg"}, {"ESRI Shapefile", "zones.shp"}, {"GeoJSON", "zones.geojson"}};
  for (const auto& [driver, name] : formats) {
    TempDir dir;
    WriteZones(dir.path() + "/" + name, TwoBands(), "EPSG:2154", driver);
    const Site site = Load(dir, BaseSite({{"file", name}, {"field", "material"}}));
    ExpectBands(site, driver);
    EXPECT_TRUE(site.gis) << driver;
    EXPECT_THAT(site.inputs, Contains(EndsWith("/" + name))) << driver;
    EXPECT_THAT(site.notes,
                Contains(HasSubstr("zones: 2 polygon features of " + dir.path() + "/" + name)))
        << driver;
    if (driver == "ESRI Shapefile") {
      EXPECT_THAT(site.inputs, Contains(EndsWith("/zones.dbf")));
    }
  }
}

TEST(ApplyZoneFile, InlineZonesGoOnTopAndMultiPolygonsCount) {
  TempDir dir;
  WriteZones(dir.path() + "/zones.gpkg",
             {{"MULTIPOLYGON (((42 -1, 60 -1, 60 51, 42 51, 42 -1)), "
               "((82 -1, 101 -1, 101 51, 82 51, 82 -1)))",
               "talus"},
              {"POLYGON ((62 -1, 80 -1, 80 51, 62 51, 62 -1))", "soil"}});
  Json json = BaseSite({{"file", "zones.gpkg"}, {"field", "material"}});
  json["materials"][2]["zone"] = Json::parse("[[-1, -1], [12, -1], [12, 51], [-1, 51]]");
  const Site site = Load(dir, json);
  for (double x = 0; x <= 100; x += 5) {
    const char* want = x < 12   ? "soil"  // the material's own zone, on top
                       : x < 42 ? "rock"
                       : x < 62 ? "talus"
                       : x < 82 ? "soil"
                                : "talus";
    EXPECT_EQ(MaterialAt(site, x, 20), want) << "node x " << x;
  }
}

TEST(ApplyZoneFile, ErrorsNameTheFileTheFeatureAndWhatWasExpected) {
  TempDir dir;
  const std::string gpkg = dir.path() + "/zones.gpkg";
  auto error_with = [&](const std::vector<ZoneFeature>& features, const Json& zones) {
    std::filesystem::remove(gpkg);
    WriteZones(gpkg, features);
    return LoadError(dir, BaseSite(zones));
  };
  const Json zones = {{"file", "zones.gpkg"}, {"field", "material"}};
  std::vector<ZoneFeature> f = TwoBands();
  f[1].material = "granite";
  EXPECT_THAT(error_with(f, zones),
              HasSubstr(gpkg + ": layer 'zones', feature 2: field 'material' holds 'granite', not "
                               "a material of the site (materials: rock, talus, soil)"));
  f = TwoBands();
  f[0].material = "";
  EXPECT_THAT(error_with(f, zones), HasSubstr(gpkg + ": layer 'zones', feature 1: field "
                                                     "'material' is empty; expected a material "
                                                     "id"));
  f = TwoBands();
  f.push_back({"LINESTRING (0 0, 10 10)", "talus"});
  EXPECT_THAT(error_with(f, zones), HasSubstr(gpkg + ": layer 'zones', feature 3: a Line String; "
                                                     "expected a Polygon or a MultiPolygon"));
  const std::string site = dir.path() + "/site.json: ";
  EXPECT_THAT(error_with(TwoBands(), {{"file", "zones.gpkg"}, {"field", "kind"}}),
              HasSubstr(site + "$.zones.field: layer 'zones' of the zone file '" + gpkg +
                        "' has no such field (fields: material)"));
  EXPECT_THAT(error_with(TwoBands(), {{"file", "zones.gpkg"}}),
              HasSubstr(site + "$.zones: expected exactly one of 'field'"));
  EXPECT_THAT(
      error_with(TwoBands(),
                 {{"file", "zones.gpkg"}, {"field", "material"}, {"classes", {{"1", "rock"}}}}),
      HasSubstr(site + "$.zones: expected exactly one of 'field'"));
  EXPECT_THAT(error_with({{"POLYGON ((500 500, 600 500, 600 600, 500 500))", "talus"}}, zones),
              HasSubstr(site + "$.zones.file: the zone file '" + gpkg +
                        "' claims no grid node (the terrain spans x 0 to 100, y 0 to 50)"));
  // Nothing claims talus: the usual check of every material.
  EXPECT_THAT(error_with({{"POLYGON ((72 -1, 101 -1, 101 51, 72 51, 72 -1))", "soil"}}, zones),
              HasSubstr(site + "$.materials[1]: material 'talus' covers no terrain node"));
  dir.Write("notes.txt", "no zones here\n");
  EXPECT_THAT(LoadError(dir, BaseSite({{"file", "notes.txt"}, {"field", "material"}})),
              HasSubstr(site + "$.zones.file: '" + dir.path() +
                        "/notes.txt' is not a vector file GDAL can read"));
}

TEST(ApplyZoneFile, LayersByName) {
  TempDir dir;
  const std::string gpkg = dir.path() + "/zones.gpkg";
  WriteZones(gpkg, {{"POLYGON ((0 0, 1 0, 1 1, 0 0))", "rock"}}, "", "GPKG", "old",
             {{"current", TwoBands()}});
  EXPECT_THAT(LoadError(dir, BaseSite({{"file", "zones.gpkg"}, {"field", "material"}})),
              HasSubstr("$.zones: the zone file '" + gpkg +
                        "' has 2 layers (old, current); expected \"layer\" naming the one with "
                        "the zones"));
  EXPECT_THAT(
      LoadError(dir, BaseSite({{"file", "zones.gpkg"}, {"field", "material"}, {"layer", "new"}})),
      HasSubstr("$.zones.layer: the zone file '" + gpkg +
                "' has no such layer (layers: old, current)"));
  const Site site =
      Load(dir, BaseSite({{"file", "zones.gpkg"}, {"field", "material"}, {"layer", "current"}}));
  ExpectBands(site, "layer current");
}

TEST(ApplyZoneFile, TheZoneFilesCrsMatchesOrIsAdopted) {
  TempDir dir;
  const std::string gpkg = dir.path() + "/zones.gpkg";
  WriteZones(gpkg, TwoBands(), "EPSG:2154");
  Json json = BaseSite({{"file", "zones.gpkg"}, {"field", "material"}});
  // The terrain has no CRS: the zone file's is adopted.
  Site site = Load(dir, json);
  EXPECT_THAT(site.crs_wkt, HasSubstr("Lambert-93"));
  EXPECT_THAT(site.notes, Contains(HasSubstr("crs: RGF93 v1 / Lambert-93 (EPSG:2154), adopted "
                                             "from the zone file")));
  json["surface"]["crs"] = "EPSG:2154";
  site = Load(dir, json);
  ExpectBands(site, "same CRS");
  json["surface"]["crs"] = "EPSG:32631";
  EXPECT_THAT(LoadError(dir, json),
              HasSubstr("$.zones.file: the zone file '" + gpkg +
                        "' has the CRS RGF93 v1 / Lambert-93 (EPSG:2154), the terrain WGS 84 / "
                        "UTM zone 31N (EPSG:32631); expected the same CRS"));
  std::filesystem::remove(gpkg);
  WriteZones(gpkg, TwoBands(), "EPSG:4326");
  json["surface"].erase("crs");
  EXPECT_THAT(LoadError(dir, json), HasSubstr("the CRS WGS 84 (EPSG:4326) is geographic"));
  // GeoJSON without a "crs" member is WGS 84 (RFC 7946).
  WriteZones(dir.path() + "/zones.geojson", TwoBands(), "", "GeoJSON");
  json["zones"]["file"] = "zones.geojson";
  EXPECT_THAT(
      LoadError(dir, json),
      HasSubstr("is geographic (longitude and latitude in degrees); expected a projected "
                "CRS in metres (reproject first, with gdalwarp or ogr2ogr -t_srs) (a GeoJSON file "
                "without a \"crs\" member is WGS 84 longitude and latitude, by RFC "
                "7946)"));
}

// Classes on 10 m cells whose edges fall between the 5 m nodes: class 1
// west of x = 43, class 2 east of it; the north-west cell is nodata (0).
RasterSpec Classes() {
  RasterSpec r;
  r.nx = 11;
  r.ny = 6;
  r.geotransform = {-7, 10, 0, 57, 0, -10};
  r.type = GDT_Byte;
  r.nodata = 0;
  for (int row = 0; row < r.ny; ++row)
    for (int col = 0; col < r.nx; ++col) r.values.push_back(col < 5 ? 1 : 2);
  r.values[0] = 0;
  return r;
}

TEST(ApplyZoneFile, RasterOfClasses) {
  TempDir dir;
  WriteRaster(dir.path() + "/classes.tif", Classes());
  const Json zones = {{"file", "classes.tif"}, {"classes", {{"1", "soil"}, {"2", "talus"}}}};
  const Site site = Load(dir, BaseSite(zones));
  for (double y = 0; y <= 50; y += 5) {
    for (double x = 0; x <= 100; x += 5) {
      const char* want = (x < 3 && y > 47) ? "rock" : x < 43 ? "soil" : "talus";
      EXPECT_EQ(MaterialAt(site, x, y), want) << "node " << x << ", " << y;
    }
  }
  EXPECT_TRUE(site.gis);
  EXPECT_THAT(site.inputs, Contains(EndsWith("/classes.tif")));
  EXPECT_THAT(site.notes, Contains(HasSubstr("1 -> soil 98 nodes, 2 -> talus 132 nodes, nodata or "
                                             "off the raster 1 nodes")));

  RasterSpec bad = Classes();
  bad.values[30] = 7;  // row 2, column 8: x 73-83, y 27-37
  WriteRaster(dir.path() + "/bad.tif", bad);
  EXPECT_THAT(
      LoadError(dir, BaseSite({{"file", "bad.tif"}, {"classes", {{"1", "soil"}, {"2", "talus"}}}})),
      HasSubstr(dir.path() + "/bad.tif: class value 7 (at grid node 75, 30) is not in "
                             "\"classes\" (classes: 1, 2)"));
  EXPECT_THAT(LoadError(dir, BaseSite({{"file", "classes.tif"},
                                       {"classes", {{"one", "soil"}, {"2", "talus"}}}})),
              HasSubstr("$.zones.classes.one: the key 'one' is not a number"));
  EXPECT_THAT(LoadError(dir, BaseSite({{"file", "classes.tif"},
                                       {"classes", {{"1", "sand"}, {"2", "talus"}}}})),
              HasSubstr("$.zones.classes.1: unknown material 'sand' (materials: rock, talus, "
                        "soil)"));
  EXPECT_THAT(
      LoadError(dir,
                BaseSite({{"file", "classes.tif"}, {"classes", {{"1", "soil"}}}, {"layer", "x"}})),
      HasSubstr("$.zones.layer: 'layer' goes with a vector file ('field') only"));
}

// A GeoJSON file of barrier lines in Lambert-93 (metres), features as text.
std::string BarrierGeoJson(const std::vector<std::string>& features) {
  std::string s =
      R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
      R"("urn:ogc:def:crs:EPSG::2154"}}, "features": [)";
  for (std::size_t k = 0; k < features.size(); ++k) s += (k ? ", " : "") + features[k];
  return s + "]}";
}

std::string BarrierFeature(const std::string& properties, const std::string& geometry) {
  return R"({"type": "Feature", "properties": {)" + properties + R"(}, "geometry": )" + geometry +
         "}";
}

const char* kNetLine = R"({"type": "LineString", "coordinates": [[50, 0], [55, 25], [50, 50]]})";

// BaseSite's plane of one material, without zones.
Json BarrierSite() {
  Json json = BaseSite(nullptr);
  json.erase("zones");
  json["materials"] = Json::array({json["materials"][0]});
  return json;
}

TEST(ReadBarrierFile, LinesOfAGeoJsonFileWithTheirAttributes) {
  TempDir dir;
  dir.Write("barriers.geojson",
            BarrierGeoJson(
                {BarrierFeature(R"("id": "net-1", "height": 4, "energy_kj": 2000)", kNetLine),
                 BarrierFeature(R"("id": "dam", "height": 6.5, "energy_kj": 20000, "stops": true)",
                                R"({"type": "MultiLineString", "coordinates": )"
                                R"([[[80, 5], [80, 45]]]})")}));
  Json json = BarrierSite();
  json["barriers"] = Json::parse(
      R"([{"id": "inline", "line": [[30, 0], [30, 50]], "height": 2, "energy_kj": 100}])");
  json["barriers_file"] = "barriers.geojson";
  const Site site = Load(dir, json);
  const std::vector<core::Partition>& parts = site.scene.partitions;
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_EQ(parts[0].id, "inline");
  EXPECT_EQ(parts[1].id, "net-1");
  EXPECT_EQ(parts[1].kind, core::Partition::Kind::kLine);
  ASSERT_EQ(parts[1].line.size(), 3u);
  EXPECT_EQ(parts[1].line[1], Eigen::Vector2d(55, 25));
  EXPECT_DOUBLE_EQ(parts[1].height, 4.0);
  EXPECT_DOUBLE_EQ(parts[1].capacity, 2e6);
  EXPECT_FALSE(parts[1].stops);
  EXPECT_EQ(parts[2].id, "dam");
  ASSERT_EQ(parts[2].line.size(), 2u);
  EXPECT_EQ(parts[2].line[1], Eigen::Vector2d(80, 45));
  EXPECT_DOUBLE_EQ(parts[2].height, 6.5);
  EXPECT_TRUE(parts[2].stops);
  EXPECT_THAT(site.inputs, Contains(EndsWith("barriers.geojson")));
  EXPECT_TRUE(site.gis);
  EXPECT_NE(site.crs_wkt.find("Lambert"), std::string::npos) << site.crs_wkt;
}

// A barrier file's faults name the file and the feature, or the site file's key.
TEST(ReadBarrierFile, Errors) {
  auto error = [](const std::vector<std::string>& features) {
    TempDir dir;
    dir.Write("barriers.geojson", BarrierGeoJson(features));
    Json json = BarrierSite();
    json["barriers_file"] = {{"file", "barriers.geojson"}};
    return LoadError(dir, json);
  };
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": 4, "energy_kj": 1)",
                                    R"({"type": "Point", "coordinates": [50, 5]})")}),
              HasSubstr("barriers.geojson: layer 'barriers', feature 0: a Point; expected a "
                        "LineString"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": -4, "energy_kj": 1)", kNetLine)}),
              HasSubstr("feature 0: field 'height' holds '-4'; expected a number > 0 (m)"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": 4, "energy_kj": 1, "stops": "maybe")",
                                    kNetLine)}),
              HasSubstr("feature 0: field 'stops' holds 'maybe'; expected true or false"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": 4)", kNetLine)}),
              HasSubstr("$.barriers_file.file: layer 'barriers' of the barrier file"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": 4)", kNetLine)}),
              HasSubstr("has no field 'energy_kj'"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": 4, "energy_kj": 1)",
                                    R"({"type": "LineString", "coordinates": [[50, 5]]})")}),
              HasSubstr("feature 0: a line of 1 vertices; expected at least 2"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a", "height": 4, "energy_kj": 1)", kNetLine),
                     BarrierFeature(R"("id": "a", "height": 4, "energy_kj": 1)", kNetLine)}),
              HasSubstr("feature 1: the id 'a' is also a partition's or another barrier's"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "a b", "height": 4, "energy_kj": 1)", kNetLine)}),
              HasSubstr("feature 0: field 'id' holds 'a b'; expected an id"));
}

// Issue 55: a rock group's release area from a polygon of a GIS file, named
// by its attribute "id" (or the file's only one): the same zone as given
// inline, the file among the inputs.
TEST(ReadReleaseFile, APolygonOfAGisFileIsTheReleaseZone) {
  TempDir dir;
  const char* a = R"({"type": "Polygon", "coordinates": [[[5, 20], [15, 20], [15, 30], [5, 30], [5, 20]]]})";
  const char* b = R"({"type": "MultiPolygon", "coordinates": [[[[20, 10], [30, 10], [25, 40], [20, 10]]]]})";
  dir.Write("releases.geojson",
            BarrierGeoJson({BarrierFeature(R"("id": "A")", a), BarrierFeature(R"("id": "B")", b)}));
  dir.Write("one.geojson", BarrierGeoJson({BarrierFeature(R"("name": "scarp")", a)}));
  Json json = BarrierSite();
  json["rocks"][0]["release"] = Json::parse(R"({"zone_file": {"file": "releases.geojson", "id": "B"}})");
  const Site site = Load(dir, json);
  const std::vector<Eigen::Vector2d> want = {{20, 10}, {30, 10}, {25, 40}};
  EXPECT_EQ(site.scene.groups[0].release.zone, want);
  EXPECT_THAT(site.inputs, Contains(EndsWith("releases.geojson")));
  EXPECT_TRUE(site.gis);
  EXPECT_THAT(site.notes, Contains(HasSubstr("release zone of 3 vertices, area 150 m^2")));
  EXPECT_THAT(site.notes,
              Contains(HasSubstr("releases.geojson', layer 'releases', feature 1)")));
  // The same zone inline gives the same release.
  json["rocks"][0]["release"] = Json::parse(R"({"zone": [[20, 10], [30, 10], [25, 40]]})");
  EXPECT_EQ(Load(dir, json).scene.groups[0].release.zone, want);
  // A file of one polygon needs no id (nor an id field).
  json["rocks"][0]["release"] = Json::parse(R"({"zone_file": "one.geojson", "height": 1})");
  EXPECT_EQ(Load(dir, json).scene.groups[0].release.zone.size(), 4u);
}

// A release file's faults name the file and the feature, or the site
// file's key, with what was expected.
TEST(ReadReleaseFile, Errors) {
  auto error = [](const std::vector<std::string>& features, const Json& release) {
    TempDir dir;
    dir.Write("releases.geojson", BarrierGeoJson(features));
    Json json = BarrierSite();
    json["rocks"][0]["release"] = release;
    return LoadError(dir, json);
  };
  const char* square = R"({"type": "Polygon", "coordinates": [[[5, 20], [15, 20], [15, 30], [5, 30], [5, 20]]]})";
  const std::vector<std::string> two = {BarrierFeature(R"("id": "A")", square),
                                        BarrierFeature(R"("id": "B")", square)};
  const Json by_name = Json::parse(R"({"zone_file": "releases.geojson"})");
  EXPECT_THAT(error(two, by_name),
              HasSubstr("$.rocks[0].release.zone_file: the release file '"));
  EXPECT_THAT(error(two, by_name),
              HasSubstr("has 2 features; expected \"id\" naming the release area (ids: A, B)"));
  const Json by_id = Json::parse(R"({"zone_file": {"file": "releases.geojson", "id": "C"}})");
  EXPECT_THAT(error(two, by_id),
              HasSubstr("$.rocks[0].release.zone_file.id: layer 'releases' of the release file"));
  EXPECT_THAT(error(two, by_id), HasSubstr("has no feature whose id is 'C' (ids: A, B)"));
  const Json a = Json::parse(R"({"zone_file": {"file": "releases.geojson", "id": "A"}})");
  EXPECT_THAT(error({BarrierFeature(R"("id": "A")", kNetLine)}, a),
              HasSubstr("releases.geojson: layer 'releases', feature 0: a Line String; expected "
                        "a Polygon (or a MultiPolygon of one polygon)"));
  EXPECT_THAT(
      error({BarrierFeature(R"("id": "A")",
                            R"({"type": "Polygon", "coordinates": [[[0, 0], [40, 0], [40, 40], )"
                            R"([0, 0]], [[10, 5], [20, 5], [20, 10], [10, 5]]]})")},
            a),
      HasSubstr("feature 0: a polygon with 1 hole(s); expected a polygon without holes"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "A")",
                                    R"({"type": "Polygon", "coordinates": [[[5, 20], [25, 20], )"
                                    R"([25, 30], [15, 15], [5, 30], [5, 20]]]})")},
                    a),
              HasSubstr("feature 0: a self-intersecting polygon"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "A")", square), BarrierFeature(R"("id": "A")", square)},
                    a),
              HasSubstr("feature 1: its id 'A' is also layer 'releases', feature 0's"));
  EXPECT_THAT(error({BarrierFeature(R"("id": "A")",
                                    R"({"type": "Polygon", "coordinates": [[[200, 20], [215, 20], )"
                                    R"([215, 30], [200, 20]]]})")},
                    a),
              HasSubstr("$.rocks[0].release.zone_file: release zone point"));
  EXPECT_THAT(error(two, Json::parse(R"({"zone_file": "releases.geojson", "point": [5, 5]})")),
              HasSubstr("expected exactly one of 'zone' (plan polygon), 'zone_file'"));
}

}  // namespace
}  // namespace rockcal::sites
