// The site file's "forest" (docs/reference/site-file.md, `$.forest`).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rockcal/core/simulate.h"
#include "rockcal/sites/site.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;
using Json = nlohmann::json;

// An SI site: a 100 m x 60 m plane from 50 m down to 0, grid of 2 m.
Json BaseSite() {
  return Json::parse(R"({
    "name": "forest slope",
    "units": "si",
    "surface": {"resolution": 2, "sphere_spacing": 2,
                "points": [[0, 0, 50], [100, 0, 0], [0, 60, 50], [100, 60, 0]]},
    "materials": [{"id": "soil", "hardness": 0.3, "roughness": 0.2}],
    "rocks": [{"count": 4, "shape": "sphere", "size": [0.5, 1], "unit_weight": 26,
               "release": {"zone": [[2, 20], [8, 20], [8, 40], [2, 40]]}}],
    "simulation": {"seed": 3, "max_time": 20}
  })");
}

struct Loaded {
  std::string path, error;
  Site site;
};
// Loads BaseSite() with `forest`, and `trees` written to trees.csv beside it.
Loaded Load(const Json& forest, const std::string& trees = "", bool expect_error = false) {
  TempDir dir;
  Json site = BaseSite();
  site["forest"] = forest;
  Loaded out;
  if (!trees.empty()) dir.Write("trees.csv", trees);
  out.path = dir.Write("site.json", site.dump(2));
  if (expect_error) {
    out.error = ErrorOf([&] { LoadSite(out.path); });
  } else {
    out.site = LoadSite(out.path);
  }
  return out;
}

TEST(ReadForest, TreeFileGivesItsStemsInSIWithTheirCapacities) {
  const Loaded l = Load({{"trees_file", "trees.csv"}},
                        "# a comment\nx,y,dbh_cm,species,height\n50,30,30,conifer,25\n"
                        "60,20,10,Broadleaf,12\n");
  const core::Forest& f = l.site.scene.forest;
  ASSERT_EQ(f.stems.size(), 2u);
  EXPECT_DOUBLE_EQ(f.stems[0].x, 50.0);
  EXPECT_DOUBLE_EQ(f.stems[0].dbh, 0.30);
  EXPECT_DOUBLE_EQ(f.stems[0].height, 25.0);
  EXPECT_EQ(f.stems[1].species, core::SpeciesClass::kBroadleaf);
  EXPECT_DOUBLE_EQ(f.stems[0].capacity, core::StemCapacity(0.30, core::SpeciesClass::kConifer));
  EXPECT_EQ(l.site.drawn_stems_first, 2u);  // none drawn
}

TEST(ReadForest, TreeFileErrorsNameTheFileAndLine) {
  struct Case {
    std::string text, says;
  };
  const Case cases[] = {
      {"x,y,dbh_cm\n50,30,-5\n", "trees.csv:2: dbh_cm -5"},
      {"x,y,dbh_cm\n50,30,30\n50,30,3000\n", "trees.csv:3: dbh_cm 3000"},
      {"x,y,dbh_cm\n50,30\n", "trees.csv:2: 2 fields; expected 3"},
      {"x,y,dbh_cm\n50,thirty,30\n", "trees.csv:2:"},
      {"x,y,dbh_cm\n500,30,30\n", "trees.csv:2: the stem at (500, 30) m is off the terrain"},
      {"x,y,dbh_cm,species\n50,30,30,oak\n", "trees.csv:2: species 'oak'"},
      {"x,y,diameter\n", "trees.csv:1: unknown column 'diameter'"},
      {"x,dbh_cm\n", "trees.csv:1: missing column y"},
      {"x,y,dbh_cm\n", "no stems"},
  };
  for (const Case& c : cases) {
    const Loaded l = Load({{"trees_file", "trees.csv"}}, c.text, true);
    EXPECT_THAT(l.error, HasSubstr(c.says)) << c.text;
  }
}

TEST(ReadForest, InlineTreesAndTheirErrorsNameTheJsonPath) {
  const Loaded ok = Load({{"trees", {{{"x", 40}, {"y", 30}, {"dbh_cm", 20}}}}});
  ASSERT_EQ(ok.site.scene.forest.stems.size(), 1u);
  EXPECT_DOUBLE_EQ(ok.site.scene.forest.stems[0].height, 20.0);  // the default
  const Loaded bad = Load({{"trees", {{{"x", 40}, {"y", 30}, {"dbh_cm", 0}}}}}, "", true);
  EXPECT_THAT(bad.error, HasSubstr("$.forest.trees[0]"));
  EXPECT_THAT(bad.error, HasSubstr("dbh_cm 0"));
  const Loaded key = Load({{"trees", {{{"x", 40}, {"y", 30}, {"dbh", 20}}}}}, "", true);
  EXPECT_THAT(key.error, HasSubstr("dbh"));
  const Loaded none = Load(Json::object(), "", true);
  EXPECT_THAT(none.error, HasSubstr("no stems"));
}

Json Stand(double per_ha) {
  return {{"zone", {{20, 10}, {80, 10}, {80, 50}, {20, 50}}},
          {"stems_per_ha", per_ha},
          {"dbh_mean_cm", 30},
          {"dbh_sd_cm", 10},
          {"conifer_percent", 70}};
}

TEST(ReadForest, StandsDrawTheirStemsFromTheSeed) {
  const Loaded a = Load({{"stands", {Stand(500)}}});
  const core::Forest& f = a.site.scene.forest;
  // 500 per ha on 0.24 ha: a Poisson count of mean 120.
  EXPECT_NEAR(static_cast<double>(f.stems.size()), 120.0, 4 * std::sqrt(120.0));
  EXPECT_EQ(a.site.drawn_stems_first, 0u);
  double conifers = 0, dbh = 0;
  for (const core::Stem& s : f.stems) {
    EXPECT_TRUE(s.x >= 20 && s.x <= 80 && s.y >= 10 && s.y <= 50) << s.x << ", " << s.y;
    EXPECT_GE(s.dbh, 0.05);
    conifers += s.species == core::SpeciesClass::kConifer;
    dbh += s.dbh;
  }
  const double n = static_cast<double>(f.stems.size());
  EXPECT_NEAR(conifers / n, 0.7, 4 * std::sqrt(0.21 / n));
  EXPECT_NEAR(dbh / n, 0.30, 4 * 0.10 / std::sqrt(n));
  // The same seed draws the same stand; another seed another.
  const Loaded b = Load({{"stands", {Stand(500)}}});
  ASSERT_EQ(b.site.scene.forest.stems.size(), f.stems.size());
  EXPECT_EQ(b.site.scene.forest.stems[5].x, f.stems[5].x);
}

TEST(ReadForest, ATreeFileAndAStandMix) {
  const Loaded l =
      Load({{"trees_file", "trees.csv"}, {"stands", {Stand(300)}}}, "x y dbh_cm\n50 30 30\n");
  EXPECT_EQ(l.site.drawn_stems_first, 1u);
  EXPECT_GT(l.site.scene.forest.stems.size(), 20u);
  // And the site runs through them.
  core::Scene scene = l.site.scene;
  scene.options.record.tree_strikes = true;
  const core::SimulationResult r = core::Simulate(scene);
  EXPECT_EQ(r.figures.non_finite, 0);
}

TEST(ReadForest, StandAndContactRangesAreChecked) {
  Json stand = Stand(300);
  stand["conifer_percent"] = 120;
  EXPECT_THAT(Load({{"stands", {stand}}}, "", true).error,
              HasSubstr("$.forest.stands[0].conifer_percent"));
  Json off = Stand(300);
  off["zone"] = {{20, 10}, {180, 10}, {180, 50}};
  EXPECT_THAT(Load({{"stands", {off}}}, "", true).error, HasSubstr("off the terrain"));
  EXPECT_THAT(Load({{"stands", {Stand(300)}}, {"contact", {{"restitution", 1.5}}}}, "", true).error,
              HasSubstr("$.forest.contact.restitution"));
}

// An ESRI ASCII grid of 2 x 2 cells of 20 m from (20, 10): `v` gives the
// rows from the north, west to east.
std::string Grid2x2(const std::string& v, double xll = 20) {
  return "ncols 2\nnrows 2\nxllcorner " + std::to_string(xll) +
         "\nyllcorner 10\ncellsize 20\nNODATA_value -9999\n" + v;
}

// Loads BaseSite() with the four stand rasters (and `stands`, when given);
// each raster's text by name, "" for the default.
struct Rasters {
  std::string stems = Grid2x2("400 400\n400 400\n"), mean = Grid2x2("30 30\n30 30\n"),
              sd = Grid2x2("10 10\n10 10\n"), conifer = Grid2x2("70 70\n70 70\n");
};
Loaded LoadRasters(const Rasters& r, const Json& stands = nullptr, bool expect_error = false) {
  TempDir dir;
  Json site = BaseSite();
  site["forest"]["rasters"] = {{"stems_per_ha", "stems.asc"},
                               {"dbh_mean_cm", "dbh_mean.asc"},
                               {"dbh_sd_cm", "dbh_sd.asc"},
                               {"conifer_percent", "conifer.asc"}};
  if (!stands.is_null()) site["forest"]["stands"] = stands;
  dir.Write("stems.asc", r.stems);
  dir.Write("dbh_mean.asc", r.mean);
  dir.Write("dbh_sd.asc", r.sd);
  dir.Write("conifer.asc", r.conifer);
  Loaded out;
  out.path = dir.Write("site.json", site.dump(2));
  if (expect_error) {
    out.error = ErrorOf([&] { LoadSite(out.path); });
  } else {
    out.site = LoadSite(out.path);
  }
  return out;
}

Json Square(double x0, double y0, double per_ha) {
  Json st = Stand(per_ha);
  st["zone"] = {{x0, y0}, {x0 + 20, y0}, {x0 + 20, y0 + 20}, {x0, y0 + 20}};
  return st;
}

void ExpectSameStems(const core::Forest& a, const core::Forest& b) {
  ASSERT_EQ(a.stems.size(), b.stems.size());
  for (std::size_t k = 0; k < a.stems.size(); ++k) {
    EXPECT_EQ(a.stems[k].x, b.stems[k].x) << k;
    EXPECT_EQ(a.stems[k].y, b.stems[k].y) << k;
    EXPECT_EQ(a.stems[k].dbh, b.stems[k].dbh) << k;
    EXPECT_EQ(a.stems[k].height, b.stems[k].height) << k;
    EXPECT_EQ(a.stems[k].species, b.stems[k].species) << k;
  }
}

// A raster cell is a stand over its square: the rasters give the stems of
// one stand per cell with stems, in the file's order after the site file's
// stands (docs/reference/site-file.md, `$.forest.rasters`).
TEST(ReadForest, RastersDrawEachCellAsAStandOverItsSquare) {
  // Stems in the north-western cell only: the stand over its square.
  Rasters one;
  one.stems = Grid2x2("400 0\n0 -9999\n");
  const Loaded r = LoadRasters(one);
  const Loaded s = Load({{"stands", {Square(20, 30, 400)}}});
  EXPECT_GT(s.site.scene.forest.stems.size(), 8u) << "400 per ha on 0.04 ha";
  ExpectSameStems(r.site.scene.forest, s.site.scene.forest);
  EXPECT_EQ(r.site.drawn_stems_first, 0u);
  // Uniform rasters: four stands, one a cell (rows from the north).
  const Loaded uniform = LoadRasters(Rasters());
  const Loaded four = Load({{"stands",
                             {Square(20, 30, 400), Square(40, 30, 400), Square(20, 10, 400),
                              Square(40, 10, 400)}}});
  ExpectSameStems(uniform.site.scene.forest, four.site.scene.forest);
  // After a stand of the site file the cells take the streams after its.
  const Loaded after = LoadRasters(one, Json::array({Square(60, 10, 400)}));
  const Loaded two = Load({{"stands", {Square(60, 10, 400), Square(20, 30, 400)}}});
  ExpectSameStems(after.site.scene.forest, two.site.scene.forest);
}

// A cell reaching past the terrain's edge keeps its density on the part on
// the terrain: its stems drawn off the terrain are dropped.
TEST(ReadForest, RasterCellsPastTheTerrainsEdgeDropTheirStemsOffIt) {
  Rasters r;  // cells of 20 m from x = 90: the western half on the terrain
  r.stems = Grid2x2("10000 10000\n10000 10000\n", 90);
  r.mean = Grid2x2("30 30\n30 30\n", 90);
  r.sd = Grid2x2("10 10\n10 10\n", 90);
  r.conifer = Grid2x2("70 70\n70 70\n", 90);
  const Loaded l = LoadRasters(r);
  // 1 stem per m^2 on 10 m x 40 m of terrain: a Poisson count of mean 400.
  const core::Forest& f = l.site.scene.forest;
  EXPECT_NEAR(static_cast<double>(f.stems.size()), 400.0, 4 * std::sqrt(400.0));
  for (const core::Stem& s : f.stems) EXPECT_LE(s.x, 100.0);
}

TEST(ReadForest, BadRastersNameTheFileAndTheCell) {
  Rasters negative;
  negative.stems = Grid2x2("400 -5\n400 400\n");
  EXPECT_THAT(LoadRasters(negative, nullptr, true).error,
              HasSubstr("stems.asc: the cell at column 2, row 1 (centre 50, 40 m): -5 stems per "
                        "ha; expected a stem density in [0, 10000]"));
  Rasters absurd;
  absurd.mean = Grid2x2("30 30\n900 30\n");
  EXPECT_THAT(LoadRasters(absurd, nullptr, true).error,
              HasSubstr("dbh_mean.asc: the cell at column 1, row 2 (centre 30, 20 m): 900 where "
                        "the stems raster has 400 stems per ha; expected a mean DBH in [5, 300]"));
  Rasters missing;
  missing.conifer = Grid2x2("70 -9999\n70 70\n");
  EXPECT_THAT(LoadRasters(missing, nullptr, true).error,
              HasSubstr("conifer.asc: the cell at column 2, row 1 (centre 50, 40 m): nodata"));
  Rasters away;  // 1 km east of the terrain
  away.stems = Grid2x2("400 400\n400 400\n", 1020);
  away.mean = Grid2x2("30 30\n30 30\n", 1020);
  away.sd = Grid2x2("10 10\n10 10\n", 1020);
  away.conifer = Grid2x2("70 70\n70 70\n", 1020);
  EXPECT_THAT(LoadRasters(away, nullptr, true).error,
              HasSubstr("stems.asc: no cell with stems overlaps the terrain"));
  Rasters shifted;
  shifted.sd = Grid2x2("10 10\n10 10\n", 22);
  EXPECT_THAT(LoadRasters(shifted, nullptr, true).error,
              HasSubstr("dbh_sd.asc: 2 x 2 cells of 20 from (32, 20); expected the cells of"));
}

}  // namespace
}  // namespace rockcal::sites
