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

// parameters.json as rockcal calibrate writes it.
Json ParametersFile() {
  return Json::parse(R"({
    "site": "Tutorial slope", "method": "nlopt:bobyqa", "misfit": 12.5, "evaluations": 40,
    "wall_seconds": 3.2, "grid_spacing_m": 3.6576,
    "parameters": [
      {"material": "talus", "class": "scree", "name": "hardness", "value": 0.35,
       "lower": 0.1, "upper": 0.7, "std_error": null},
      {"material": "talus", "class": "scree", "name": "roughness", "value": 0.4,
       "lower": 0.1524, "upper": 1.8288, "std_error": 0.05},
      {"material": "soil", "class": "soil", "name": "contact_time", "value": 0.006,
       "lower": 0.002, "upper": 0.01, "std_error": null}
    ]})");
}

std::string WriteResult(const TempDir& dir, const std::string& name, const Json& json) {
  return std::filesystem::path(dir.Write(name + "/parameters.json", json.dump(2)))
      .parent_path()
      .string();
}

TEST(ReadCalibratedSite, ReadsEveryKey) {
  TempDir dir;
  const std::string folder = WriteResult(dir, "t1", ParametersFile());
  const CalibratedSite s = ReadCalibratedSite(folder);
  EXPECT_EQ(s.result_dir, folder);
  EXPECT_EQ(s.file, folder + "/parameters.json");
  EXPECT_EQ(s.site, "Tutorial slope");
  EXPECT_EQ(s.stage, Stage{Method::kBobyqa});
  EXPECT_DOUBLE_EQ(s.misfit, 12.5);
  EXPECT_EQ(s.evaluations, 40);
  ASSERT_TRUE(s.grid_spacing_m.has_value());
  EXPECT_DOUBLE_EQ(*s.grid_spacing_m, 3.6576);
  ASSERT_EQ(s.parameters.size(), 3u);
  EXPECT_EQ(s.parameters[0].material, "talus");
  EXPECT_EQ(s.parameters[0].material_class, "scree");
  EXPECT_TRUE(s.parameters[0].class_given);
  EXPECT_EQ(s.parameters[0].name, "hardness");
  EXPECT_DOUBLE_EQ(s.parameters[0].value, 0.35);
  EXPECT_FALSE(s.parameters[0].std_error.has_value());
  ASSERT_TRUE(s.parameters[1].std_error.has_value());
  EXPECT_DOUBLE_EQ(*s.parameters[1].std_error, 0.05);
  EXPECT_DOUBLE_EQ(s.parameters[1].upper, 1.8288);
  EXPECT_EQ(s.parameters[2].name, "contact_time");
}

TEST(ReadCalibratedSite, OlderFilesFallBackToTheMaterialId) {
  TempDir dir;
  Json json = ParametersFile();
  json.erase("grid_spacing_m");
  for (Json& p : json["parameters"]) p.erase("class");
  const CalibratedSite s = ReadCalibratedSite(WriteResult(dir, "old", json));
  EXPECT_FALSE(s.grid_spacing_m.has_value());
  EXPECT_EQ(s.parameters[0].material_class, "talus");
  EXPECT_FALSE(s.parameters[0].class_given);
  EXPECT_EQ(s.parameters[2].material_class, "soil");

  const DefaultTable t = BuildDefaultTable({s}, {});
  std::string notes;
  for (const std::string& n : t.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr(s.file + ": no \"class\" on talus, soil"));
  EXPECT_THAT(notes, HasSubstr("each material id stands for its class"));
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.rows[0].material_class, "soil");
  EXPECT_EQ(t.rows[1].material_class, "talus");
}

// The error of reading the result folder holding ParametersFile() changed by
// `edit`; it must name the file.
std::string ReadError(const std::function<void(Json&)>& edit) {
  TempDir dir;
  Json json = ParametersFile();
  edit(json);
  const std::string folder = WriteResult(dir, "bad", json);
  const std::string msg = ErrorOf([&] { ReadCalibratedSite(folder); });
  EXPECT_THAT(msg, HasSubstr(folder + "/parameters.json: ")) << "the message must name the file";
  return msg;
}

TEST(ReadCalibratedSite, ErrorsNameTheFileAndPath) {
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][1].erase("value"); }),
              HasSubstr("$.parameters[1]: missing required key 'value'"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["value"] = "0.3"; }),
              HasSubstr("$.parameters[0].value: expected a number (found \"0.3\")"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["class"] = 4; }),
              HasSubstr("$.parameters[0].class: expected a string (found 4)"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["class"] = ""; }),
              HasSubstr("$.parameters[0].class: expected a class name (not empty)"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][2]["name"] = "colour"; }),
              HasSubstr("$.parameters[2].name: unknown parameter name (allowed: hardness, "
                        "roughness, contact_time, rolling_resistance, friction, vegetation) (found "
                        "\"colour\")"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["value"] = 0.8; }),
              HasSubstr("$.parameters[0].value: expected a value within its bounds [0.1, 0.7] "
                        "(found 0.8)"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["upper"] = 0.1; }),
              HasSubstr("$.parameters[0].upper: expected upper > lower"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["lower"] = -0.1; }),
              HasSubstr("$.parameters[0].lower: expected a number in [0, 1] (found -0.1)"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][1]["std_error"] = -1; }),
              HasSubstr("$.parameters[1].std_error: expected a number >= 0 (found -1)"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][1]["std_error"] = "n/a"; }),
              HasSubstr("$.parameters[1].std_error: expected a standard error >= 0 or null"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][1]["upper"] = 2.0; }),
              HasSubstr("$.parameters[1].upper: expected a roughness bound <= half the grid "
                        "spacing (1.8288 m)"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][2] = j["parameters"][0]; }),
              HasSubstr("$.parameters[2]: parameter talus.hardness given twice"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"][0]["colour"] = "red"; }),
              HasSubstr("$.parameters[0].colour: unknown key 'colour'"));
  EXPECT_THAT(ReadError([](Json& j) { j.erase("site"); }),
              HasSubstr("$: missing required key 'site'"));
  EXPECT_THAT(ReadError([](Json& j) { j["parameters"] = Json::array(); }),
              HasSubstr("$.parameters: expected an array of at least 1 entries"));
  EXPECT_THAT(ReadError([](Json& j) { j["evaluations"] = 2.5; }),
              HasSubstr("$.evaluations: expected a whole number"));
}

// ParametersFile() with a posterior per parameter, as calibrate --posterior writes it.
Json WithPosterior() {
  Json json = ParametersFile();
  json["parameters"][0]["posterior"] = {{"median", 0.3}, {"p05", 0.2}, {"p95", 0.5}, {"determined", true}};
  json["parameters"][1]["posterior"] = {{"median", 0.5}, {"p05", 0.3}, {"p95", 1.2}, {"determined", false}};
  json["parameters"][2]["posterior"] = {{"median", 0.006}, {"p05", 0.004}, {"p95", 0.008}, {"determined", true}};
  json["posterior_samples"] = "posterior.csv";
  return json;
}

TEST(ReadCalibratedSite, ReadsThePosteriorAndItsSamples) {
  TempDir dir;
  const std::string folder = WriteResult(dir, "post", WithPosterior());
  dir.Write("post/posterior.csv",
            "talus.hardness,talus.roughness,soil.contact_time\n0.25,0.4,0.005\n0.3,0.6,0.007\n");
  const CalibratedSite s = ReadCalibratedSite(folder);
  ASSERT_TRUE(s.has_posterior());
  EXPECT_EQ(s.samples_file, folder + "/posterior.csv");
  ASSERT_TRUE(s.parameters[1].posterior.has_value());
  EXPECT_DOUBLE_EQ(s.parameters[1].posterior->p95, 1.2);
  EXPECT_FALSE(s.parameters[1].posterior->determined);
  const std::vector<std::vector<double>> samples = ReadPosteriorSamples(s);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[1], (std::vector<double>{0.3, 0.6, 0.007}));

  // Errors name the file, the line and column, the value and what was expected.
  dir.Write("post/posterior.csv", "talus.hardness,soil.contact_time\n0.25,0.005\n");
  EXPECT_THAT(ErrorOf([&] { ReadPosteriorSamples(s); }),
              HasSubstr(folder + "/posterior.csv: line 1: header 'talus.hardness,soil.contact_time'; "
                                 "expected 'talus.hardness,talus.roughness,soil.contact_time'"));
  dir.Write("post/posterior.csv",
            "talus.hardness,talus.roughness,soil.contact_time\n0.25,0.4,0.005\n0.9,0.4,0.005\n");
  EXPECT_THAT(ErrorOf([&] { ReadPosteriorSamples(s); }),
              HasSubstr("posterior.csv: line 3, column 1 (talus.hardness): 0.9: expected a value "
                        "within the bounds [0.1, 0.7]"));
  dir.Write("post/posterior.csv",
            "talus.hardness,talus.roughness,soil.contact_time\n0.25,x,0.005\n");
  EXPECT_THAT(ErrorOf([&] { ReadPosteriorSamples(s); }),
              HasSubstr("line 2, column 2 (talus.roughness): 'x': expected a number"));
  dir.Write("post/posterior.csv", "talus.hardness,talus.roughness,soil.contact_time\n0.25,0.4\n");
  EXPECT_THAT(ErrorOf([&] { ReadPosteriorSamples(s); }), HasSubstr("line 2"));
  dir.Write("post/posterior.csv", "talus.hardness,talus.roughness,soil.contact_time\n");
  EXPECT_THAT(ErrorOf([&] { ReadPosteriorSamples(s); }), HasSubstr("no samples"));

  // A posterior of some parameters only, or an interval out of order, is refused.
  EXPECT_THAT(ReadError([](Json& j) {
                j = WithPosterior();
                j["parameters"][2].erase("posterior");
              }),
              HasSubstr("$.parameters[2]: no \"posterior\" where other parameters have one"));
  EXPECT_THAT(ReadError([](Json& j) {
                j = WithPosterior();
                j["parameters"][0]["posterior"]["p05"] = 0.4;
              }),
              HasSubstr("$.parameters[0].posterior: expected p05 <= median <= p95"));
  EXPECT_THAT(ReadError([](Json& j) {
                j = WithPosterior();
                j["parameters"][0]["posterior"]["p95"] = 0.9;
              }),
              HasSubstr("$.parameters[0].posterior.p95: expected a value within the parameter's "
                        "bounds [0.1, 0.7]"));
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

  // One counted value without a posterior: no interval for the row, and a note.
  Json c = ParametersFile();
  c["site"] = "Third slope";
  const CalibratedSite sc = ReadCalibratedSite(WriteResult(dir, "c", c));
  const DefaultTable mixed = BuildDefaultTable({sa, sc}, {});
  for (const TableRow& r : mixed.rows) EXPECT_FALSE(r.posterior_p05.has_value()) << r.name;
  std::string notes;
  for (const std::string& n : mixed.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("scree hardness: 1 of 2 counted values have a posterior"));
}

TEST(ReadCalibratedSite, MissingFolderFileAndBadJson) {
  TempDir dir;
  const std::string none = dir.path() + "/none";
  EXPECT_THAT(ErrorOf([&] { ReadCalibratedSite(none); }),
              HasSubstr(none + ": no such result folder"));
  const std::string empty = dir.path() + "/empty";
  std::filesystem::create_directories(empty);
  EXPECT_THAT(ErrorOf([&] { ReadCalibratedSite(empty); }),
              HasSubstr(empty + "/parameters.json: missing"));
  dir.Write("broken/parameters.json", "{\"site\": \"x\",\n \"method\": }");
  EXPECT_THAT(ErrorOf([&] { ReadCalibratedSite(dir.path() + "/broken"); }),
              HasSubstr(dir.path() + "/broken/parameters.json:2:"));
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
