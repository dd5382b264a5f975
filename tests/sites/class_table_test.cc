// Material classes from a class table (sites/class_table.h): a material that
// names a class and lacks hardness or roughness takes the class's medians;
// its own values override the class's; a bad class or table is named.
#include "rockcal/sites/class_table.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "rockcal/sites/site.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;
using Json = nlohmann::json;

// A table as rockcal table writes it (the keys the reader takes): meadow
// with a posterior envelope on hardness, a range of values on roughness and
// one value of friction; bedrock with hardness only.
Json Table() {
  return Json::parse(R"({
    "rows": [
      {"class": "meadow", "parameter": "hardness", "sites": 2, "values": 2, "median": 0.4,
       "min": 0.35, "max": 0.45, "posterior": {"p05": 0.2, "p95": 0.7, "values": 2},
       "entries": [{"grid_spacing_m": 5.0}, {"grid_spacing_m": 1.0}]},
      {"class": "meadow", "parameter": "roughness", "sites": 2, "values": 2, "median": 0.3,
       "min": 0.25, "max": 0.5, "posterior": null,
       "entries": [{"grid_spacing_m": 3.048}, {"grid_spacing_m": 5.0}]},
      {"class": "meadow", "parameter": "friction", "sites": 1, "values": 1, "median": 0.5,
       "min": 0.5, "max": 0.5, "entries": []},
      {"class": "bedrock", "parameter": "hardness", "sites": 1, "values": 1, "median": 0.7,
       "min": 0.7, "max": 0.7, "entries": []}
    ],
    "about": {"classes": {"meadow": {"description": "grass on fine soil"}}}
  })");
}

// A US plane (10 ft spheres) whose second material is `talus`.
Json SiteWith(const Json& talus) {
  Json site = Json::parse(R"({
    "name": "class slope", "units": "us",
    "surface": {"resolution": 10, "sphere_spacing": 10,
                "points": [[0, 0, 100], [200, 0, 0], [0, 100, 100], [200, 100, 0]]},
    "materials": [{"id": "rock", "hardness": 0.6, "roughness": 1.0}],
    "rocks": [{"count": 4, "shape": "sphere", "size": [1, 3], "unit_weight": 165,
               "release": {"point": [20, 50]}}]
  })");
  Json t = talus;
  t["id"] = "talus";
  t["zone"] = Json::parse("[[100, -5], [205, -5], [205, 105], [100, 105]]");
  site["materials"].push_back(t);
  return site;
}

struct Written {
  TempDir dir;
  std::string site, table;
};

void Write(Written* w, const Json& talus, const Json& table = Table()) {
  w->table = w->dir.Write("tables/table.json", table.dump(2));
  w->site = w->dir.Write("site.json", SiteWith(talus).dump(2));
}

TEST(ClassTable, AClassTakesTheTablesMediansExactly) {
  Written w;
  Write(&w, {{"class", "meadow"}, {"table", "tables/table.json"}});
  const Site site = LoadSite(w.site);
  const core::Material& talus = site.scene.materials[1];
  EXPECT_EQ(talus.hardness, 0.4);
  EXPECT_EQ(talus.roughness_m, 0.3);  // the table is SI whatever the site's units
  ASSERT_TRUE(talus.friction.has_value());
  EXPECT_EQ(*talus.friction, 0.5);
  ASSERT_EQ(site.class_materials.size(), 1u);
  const ClassMaterial& c = site.class_materials[0];
  EXPECT_EQ(c.material, "talus");
  EXPECT_EQ(c.material_class, "meadow");
  EXPECT_EQ(c.table, w.table);
  EXPECT_EQ(c.description, "grass on fine soil");
  ASSERT_EQ(c.from_table.size(), 3u);
  EXPECT_EQ(c.from_table[0].interval, "posterior envelope");
  EXPECT_EQ(*c.from_table[0].low, 0.2);
  EXPECT_EQ(*c.from_table[0].high, 0.7);
  EXPECT_EQ(c.from_table[1].interval, "range of calibrated values");
  EXPECT_EQ(*c.from_table[1].low, 0.25);
  EXPECT_FALSE(c.from_table[2].low.has_value()) << "one value: no interval";
  EXPECT_TRUE(c.explicit_fields.empty());
  // The roughness came from spheres 5 m apart too; this site's are 10 ft.
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_THAT(c.notes[0], HasSubstr("virtual spheres 5 m apart, this site's are 3.048 m apart"));
  std::string notes;
  for (const std::string& n : site.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("material talus: class meadow of " + w.table +
                               ": hardness 0.4 (posterior envelope 0.2-0.7), roughness 0.3"));
  // The table file is an input of the site (a calibration's fingerprint).
  EXPECT_EQ(site.inputs.back(), w.table);
}

TEST(ClassTable, TheSitesOwnValuesOverrideTheClasss) {
  Written w;
  Write(&w, {{"class", "meadow"}, {"table", "tables"}, {"hardness", 0.35}, {"friction", 0.6}});
  const Site site = LoadSite(w.site);
  EXPECT_EQ(site.scene.materials[1].hardness, 0.35);
  EXPECT_EQ(*site.scene.materials[1].friction, 0.6);
  EXPECT_EQ(site.scene.materials[1].roughness_m, 0.3);
  const ClassMaterial& c = site.class_materials.at(0);
  EXPECT_EQ(c.explicit_fields, (std::vector<std::string>{"hardness", "friction"}));
  ASSERT_EQ(c.from_table.size(), 1u);
  EXPECT_EQ(c.from_table[0].parameter, "roughness");
  // A class with both values given and no table is a label (as before).
  Written label;
  Write(&label, {{"class", "meadow"}, {"hardness", 0.35}, {"roughness", 1.0}});
  EXPECT_TRUE(LoadSite(label.site).class_materials.empty());
}

TEST(ClassTable, BadClassesAndTablesAreNamed) {
  Written w;
  Write(&w, {{"class", "medow"}, {"table", "tables/table.json"}});
  EXPECT_THAT(ErrorOf([&] { LoadSite(w.site); }),
              HasSubstr(w.site + ": $.materials[1].class: unknown class in the table " + w.table +
                        "; expected one of its classes: bedrock, meadow (found \"medow\")"));
  Write(&w, {{"class", "bedrock"}, {"table", "tables/table.json"}});
  EXPECT_THAT(ErrorOf([&] { LoadSite(w.site); }),
              HasSubstr("$.materials[1].class: class 'bedrock' of the table " + w.table +
                        " gives no roughness; expected 'roughness' in the material"));
  Write(&w, {{"class", "meadow"}, {"table", "nowhere.json"}});
  EXPECT_THAT(ErrorOf([&] { LoadSite(w.site); }),
              HasSubstr("$.materials[1].table: no such file or folder (" + w.dir.path() +
                        "/nowhere.json); expected a table.json written by rockcal table"));
  Write(&w, {{"hardness", 0.3}, {"roughness", 1.0}, {"table", "tables/table.json"}});
  EXPECT_THAT(ErrorOf([&] { LoadSite(w.site); }),
              HasSubstr("$.materials[1].table: a table goes with a 'class'"));
  Json bad = Table();
  bad["rows"][1]["median"] = "0.3";
  Write(&w, {{"class", "meadow"}, {"table", "tables/table.json"}}, bad);
  EXPECT_THAT(ErrorOf([&] { LoadSite(w.site); }),
              HasSubstr(w.table + ": $.rows[1].median: expected a number"));
  // Without a table, the built-in one: its classes are named.
  Write(&w, {{"class", "no-such-class"}});
  EXPECT_THAT(ErrorOf([&] { LoadSite(w.site); }),
              HasSubstr("$.materials[1].class: unknown class in the table " +
                        std::string(kBuiltInTable) + "; expected one of its classes: " +
                        BuiltInClassTable().ClassNames()));
}

// The built-in table (sites/tables/default.json) gives each of its classes'
// medians to a site that names the class.
TEST(ClassTable, TheBuiltInTableGivesItsMedians) {
  for (const MaterialClass& c : BuiltInClassTable().classes) {
    if (!c.Find("hardness") || !c.Find("roughness")) continue;
    Written w;
    Write(&w, {{"class", c.name}});
    Site site;
    try {
      site = LoadSite(w.site);
    } catch (const InputError& e) {
      // A roughness the 10 ft grid cannot take is refused, not bent.
      EXPECT_THAT(e.what(), HasSubstr("roughness")) << c.name;
      continue;
    }
    EXPECT_EQ(site.scene.materials[1].hardness, c.Find("hardness")->median) << c.name;
    EXPECT_EQ(site.scene.materials[1].roughness_m, c.Find("roughness")->median) << c.name;
    EXPECT_EQ(site.class_materials.at(0).table, kBuiltInTable);
  }
}

}  // namespace
}  // namespace rockcal::sites
