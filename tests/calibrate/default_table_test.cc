#include "rockcal/calibrate/default_table.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../sites/test_files.h"
#include "default_table_fixture.h"

namespace rockcal::calibrate {
namespace {

using sites::testing::ErrorOf;
using sites::testing::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;
using Json = nlohmann::json;
using testing::ParametersFile;
using testing::WithPosterior;
using testing::WriteResult;

TEST(Statistics, CountsDistinctSites) {
  const ValueStatistics s = Statistics({0.5, 0.2, 0.9, 0.4}, {"a", "b", "a", "c"});
  EXPECT_EQ(s.values, 4);
  EXPECT_EQ(s.sites, 3);
  EXPECT_DOUBLE_EQ(s.median, 0.45);
  EXPECT_DOUBLE_EQ(s.min, 0.2);
  EXPECT_DOUBLE_EQ(s.max, 0.9);
  EXPECT_EQ(Statistics({}, {}).values, 0);
}

TEST(AtBound, WithinOnePercentOfTheRange) {
  // Range 0.5: 1 % is 0.005.
  EXPECT_EQ(AtBound(0.1, 0.1, 0.6, 0.01), BoundPosition::kAtLower);
  EXPECT_EQ(AtBound(0.1049, 0.1, 0.6, 0.01), BoundPosition::kAtLower);
  EXPECT_EQ(AtBound(0.1051, 0.1, 0.6, 0.01), BoundPosition::kInside);
  EXPECT_EQ(AtBound(0.35, 0.1, 0.6, 0.01), BoundPosition::kInside);
  EXPECT_EQ(AtBound(0.5949, 0.1, 0.6, 0.01), BoundPosition::kInside);
  EXPECT_EQ(AtBound(0.5951, 0.1, 0.6, 0.01), BoundPosition::kAtUpper);
  EXPECT_EQ(AtBound(0.6, 0.1, 0.6, 0.01), BoundPosition::kAtUpper);
  EXPECT_EQ(AtBound(0.1051, 0.1, 0.6, 0.0), BoundPosition::kInside);
  EXPECT_STREQ(BoundName(BoundPosition::kAtUpper), "upper");
}


TEST(BuildDefaultTable, ARowOfValuesWithPosteriorsHasTheirIntervalsEnvelope) {
  TempDir dir;
  Json a = WithPosterior();
  Json b = WithPosterior();
  b["site"] = "Other slope";
  b["parameters"][0]["value"] = 0.45;
  b["parameters"][0]["posterior"] = {{"median", 0.45}, {"p05", 0.35}, {"p95", 0.6}, {"determined", true}};
  const CalibratedSite sa = ReadCalibratedSite(WriteResult(dir, "a", a));
  const CalibratedSite sb = ReadCalibratedSite(WriteResult(dir, "b", b));
  const DefaultTable t = BuildDefaultTable({sa, sb}, {});
  EXPECT_TRUE(t.any_posterior);
  const TableRow* hardness = nullptr;
  for (const TableRow& r : t.rows)
    if (r.material_class == "scree" && r.name == "hardness") hardness = &r;
  ASSERT_NE(hardness, nullptr);
  ASSERT_TRUE(hardness->posterior_p05.has_value());
  EXPECT_DOUBLE_EQ(*hardness->posterior_p05, 0.2);  // site a's 5 %
  EXPECT_DOUBLE_EQ(*hardness->posterior_p95, 0.6);  // site b's 95 %
  EXPECT_EQ(hardness->posterior_values, 2);
  // The row pools the posterior medians (0.3 and 0.45), not the search
  // values (0.35 and 0.45).
  EXPECT_DOUBLE_EQ(hardness->values[0].value, 0.35);
  EXPECT_DOUBLE_EQ(hardness->values[0].pooled(), 0.3);
  EXPECT_DOUBLE_EQ(hardness->headline.median, 0.375);
  EXPECT_DOUBLE_EQ(hardness->headline.min, 0.3);
  EXPECT_DOUBLE_EQ(hardness->headline.max, 0.45);

  // One counted value without a posterior: no interval for the row, and a note.
  Json c = ParametersFile();
  c["site"] = "Third slope";
  const CalibratedSite sc = ReadCalibratedSite(WriteResult(dir, "c", c));
  const DefaultTable mixed = BuildDefaultTable({sa, sc}, {});
  for (const TableRow& r : mixed.rows) EXPECT_FALSE(r.posterior_p05.has_value()) << r.name;
  std::string notes;
  for (const std::string& n : mixed.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("scree hardness: 1 of 2 counted values have a posterior"));
  // Without a posterior a calibration enters with its search value.
  for (const TableRow& r : mixed.rows) {
    if (r.material_class != "scree" || r.name != "hardness") continue;
    ASSERT_EQ(r.values.size(), 2u);
    EXPECT_DOUBLE_EQ(r.values[1].pooled(), 0.35);
    EXPECT_DOUBLE_EQ(r.headline.median, 0.325);  // 0.3 (a's posterior) and 0.35 (c's search)
  }
}

TEST(BuildDefaultTable, TheBoundTestIsOnThePooledValue) {
  // The search stopped at its lower bound (0.1 in [0.1, 0.7]) while the
  // posterior's median lies inside: the posterior says where the data put
  // the value, so it counts. A posterior whose median sits at the bound
  // is left out.
  TempDir dir;
  Json a = WithPosterior();
  a["parameters"][0]["value"] = 0.1;
  a["parameters"][0]["posterior"]["median"] = 0.25;
  Json b = a;
  b["site"] = "Other slope";
  b["parameters"][0]["posterior"] = {
      {"median", 0.102}, {"p05", 0.1}, {"p95", 0.2}, {"determined", false}};
  const DefaultTable t = BuildDefaultTable(
      {ReadCalibratedSite(WriteResult(dir, "a", a)), ReadCalibratedSite(WriteResult(dir, "b", b))},
      {});
  bool seen = false;
  for (const TableRow& r : t.rows) {
    if (r.material_class != "scree" || r.name != "hardness") continue;
    seen = true;
    EXPECT_EQ(r.at_bound, 1);
    EXPECT_EQ(r.values[0].bound, BoundPosition::kInside);
    EXPECT_EQ(r.values[1].bound, BoundPosition::kAtLower);
    EXPECT_EQ(r.headline.values, 1);
    EXPECT_DOUBLE_EQ(r.headline.median, 0.25);
    EXPECT_DOUBLE_EQ(r.all.median, 0.5 * (0.25 + 0.102));
  }
  EXPECT_TRUE(seen);
  std::string notes;
  for (const std::string& n : t.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("Other slope"));
  EXPECT_THAT(notes, HasSubstr("is at its lower bound (0.102 in [0.1, 0.7])"));
  EXPECT_THAT(notes, Not(HasSubstr("(0.1 in [0.1, 0.7])")));
}

// A hand-made calibration of `site` in folder `dir`.
CalibratedSite Site(const std::string& site, const std::string& dir,
                    std::vector<CalibratedParameter> parameters) {
  CalibratedSite s;
  s.site = site;
  s.result_dir = dir;
  s.file = dir + "/parameters.json";
  s.stage = Stage{Method::kBobyqa};
  s.misfit = static_cast<double>(dir.size());
  s.evaluations = 10;
  s.parameters = std::move(parameters);
  return s;
}

using testing::P;

// Three sites. talus hardness: 0.30 (A), 0.50 (B, material "scree"), 0.40
// and 0.10 (C, the second at its lower bound). talus roughness: 0.2 (A),
// 0.5 (B, at its upper bound). bedrock hardness: 0.7 (A).
std::vector<CalibratedSite> ThreeSites() {
  return {Site("A", "/results/a",
               {P("talus", "talus", "hardness", 0.30, 0.1, 0.7),
                P("talus", "talus", "roughness", 0.2, 0.05, 0.5),
                P("rock", "bedrock", "hardness", 0.7, 0.1, 0.9)}),
          Site("B", "/results/b",
               {P("scree", "talus", "hardness", 0.50, 0.1, 0.8),
                P("scree", "talus", "roughness", 0.5, 0.05, 0.5)}),
          Site("C", "/results/c",
               {P("talus", "talus", "hardness", 0.40, 0.1, 0.6),
                P("debris", "talus", "hardness", 0.10, 0.1, 0.6)})};
}

TEST(BuildDefaultTable, MedianRangeAndSitesPerClass) {
  const DefaultTable t = BuildDefaultTable(ThreeSites(), {});
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.rows[0].material_class, "bedrock");
  EXPECT_EQ(t.rows[0].name, "hardness");
  EXPECT_EQ(t.rows[0].headline.values, 1);
  EXPECT_DOUBLE_EQ(t.rows[0].headline.median, 0.7);

  // talus hardness without the value at a bound: 0.30, 0.50, 0.40.
  const TableRow& h = t.rows[1];
  EXPECT_EQ(h.material_class, "talus");
  EXPECT_EQ(h.name, "hardness");
  ASSERT_EQ(h.values.size(), 4u);
  EXPECT_EQ(h.values[1].material, "scree");
  EXPECT_EQ(h.values[1].result_dir, "/results/b");
  EXPECT_EQ(h.at_bound, 1);
  EXPECT_EQ(h.values[3].bound, BoundPosition::kAtLower);
  EXPECT_FALSE(h.values[3].counted);
  EXPECT_EQ(h.headline.values, 3);
  EXPECT_EQ(h.headline.sites, 3);
  EXPECT_DOUBLE_EQ(h.headline.median, 0.40);
  EXPECT_DOUBLE_EQ(h.headline.min, 0.30);
  EXPECT_DOUBLE_EQ(h.headline.max, 0.50);
  // With it: 0.10, 0.30, 0.40, 0.50 (even count), still 3 sites.
  EXPECT_EQ(h.all.values, 4);
  EXPECT_EQ(h.all.sites, 3);
  EXPECT_DOUBLE_EQ(h.all.median, 0.35);
  EXPECT_DOUBLE_EQ(h.all.min, 0.10);

  // talus roughness: 0.2 inside, 0.5 at its upper bound.
  const TableRow& r = t.rows[2];
  EXPECT_EQ(r.name, "roughness");
  EXPECT_EQ(r.headline.values, 1);
  EXPECT_DOUBLE_EQ(r.headline.median, 0.2);
  EXPECT_DOUBLE_EQ(r.all.median, 0.35);
  EXPECT_EQ(r.values[1].bound, BoundPosition::kAtUpper);

  std::string notes;
  for (const std::string& n : t.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("talus hardness: C (/results/c, material debris) is at its lower "
                               "bound (0.1 in [0.1, 0.6]); left out of the statistics"));
  EXPECT_THAT(notes, HasSubstr("talus roughness: B (/results/b, material scree) is at its upper"));
}

TEST(BuildDefaultTable, IncludeAtBoundCountsEveryValue) {
  DefaultTableOptions options;
  options.include_at_bound = true;
  const DefaultTable t = BuildDefaultTable(ThreeSites(), options);
  const TableRow& h = t.rows[1];
  EXPECT_EQ(h.at_bound, 1);
  EXPECT_TRUE(h.values[3].counted);
  EXPECT_EQ(h.headline.values, 4);
  EXPECT_DOUBLE_EQ(h.headline.median, 0.35);
  EXPECT_DOUBLE_EQ(h.headline.min, 0.10);
}

TEST(BuildDefaultTable, ARowWhoseValuesAreAllAtABound) {
  const DefaultTable t =
      BuildDefaultTable({Site("A", "/r/a", {P("soil", "soil", "hardness", 0.05, 0.05, 0.6)})}, {});
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].headline.values, 0);
  EXPECT_EQ(t.rows[0].headline.sites, 0);
  EXPECT_EQ(t.rows[0].all.values, 1);
}

TEST(BuildDefaultTable, OneSiteInTwoFoldersCountsOnce) {
  std::vector<CalibratedSite> sites = ThreeSites();
  sites[1].site = "A";  // B was another calibration of site A
  const DefaultTable t = BuildDefaultTable(sites, {});
  EXPECT_EQ(t.rows[1].headline.values, 3);
  EXPECT_EQ(t.rows[1].headline.sites, 2);
  std::string notes;
  for (const std::string& n : t.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("site 'A' comes from 2 result folders (/results/a, /results/b)"));
}

TEST(BuildDefaultTable, TheSameCalibrationTwiceIsAnError) {
  std::vector<CalibratedSite> sites = ThreeSites();
  sites.push_back(sites[0]);
  EXPECT_THAT(ErrorOf([&] { BuildDefaultTable(sites, {}); }),
              HasSubstr("/results/a: result folder given twice (also as /results/a)"));
  sites.back().result_dir = "/results/../results/a/";
  EXPECT_THAT(ErrorOf([&] { BuildDefaultTable(sites, {}); }), HasSubstr("given twice"));
  sites.back().result_dir = "/results/copy";
  sites.back().file = "/results/copy/parameters.json";
  EXPECT_THAT(ErrorOf([&] { BuildDefaultTable(sites, {}); }),
              HasSubstr("/results/copy/parameters.json: holds the same calibration as "
                        "/results/a/parameters.json"));
}

TEST(BuildDefaultTable, RoughnessFromDifferentGridSpacingsIsNoted) {
  std::vector<CalibratedSite> sites = ThreeSites();
  sites[0].grid_spacing_m = 1.0;
  sites[1].grid_spacing_m = 3.6576;
  const DefaultTable t = BuildDefaultTable(sites, {});
  std::string notes;
  for (const std::string& n : t.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("talus roughness: the values come from virtual spheres of different "
                               "spacings (1 m, 3.6576 m)"));
  // 12 ft computed two ways is one spacing.
  sites[0].grid_spacing_m = 3.6576000000000004;
  for (const std::string& n : BuildDefaultTable(sites, {}).notes)
    EXPECT_THAT(n, Not(HasSubstr("spacing")));
}

TEST(DefaultTableOptions, IsValid) {
  std::string error;
  EXPECT_TRUE(DefaultTableOptions{}.IsValid(&error));
  DefaultTableOptions o;
  o.bound_fraction = 0.5;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("bound_fraction 0.5 must lie in [0, 0.5)"));
  o.bound_fraction = -0.1;
  EXPECT_FALSE(o.IsValid(&error));
}

}  // namespace
}  // namespace rockcal::calibrate
