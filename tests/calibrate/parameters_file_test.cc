#include "rockcal/calibrate/parameters_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
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
using testing::ParametersFile;
using testing::WithPosterior;
using testing::WriteResult;
using Json = nlohmann::json;

// What the writer writes, the reader reads back: every field of a site with
// a posterior (and one without a standard error), and its samples.
TEST(ParametersFile, WhatIsWrittenIsReadBack) {
  CalibratedSite site;
  site.site = "Round trip";
  site.stage = Stage{Method::kBobyqa};
  site.misfit = 3.25;
  site.evaluations = 17;
  site.wall_seconds = 1.5;
  site.grid_spacing_m = 2.0;
  site.parameters = {testing::P("talus", "scree", "hardness", 0.123456789012345, 0.1, 0.7),
                     testing::P("soil", "soil", "roughness", 0.3, 0.05, 0.9)};
  site.parameters[0].std_error = 0.0125;
  site.parameters[0].posterior = CalibratedParameter::Interval{0.12, 0.11, 0.2, true};
  site.parameters[1].posterior = CalibratedParameter::Interval{0.4, 0.1, 0.8, false};
  site.samples_file = "posterior.csv";
  const std::vector<std::vector<double>> samples = {{0.125, 0.3}, {0.15, 0.55}};

  TempDir dir;
  const std::string folder = WriteResult(dir, "rt", ParametersFileJson(site));
  dir.Write("rt/posterior.csv", PosteriorSamplesCsv(site.parameters, samples));
  const CalibratedSite back = ReadCalibratedSite(folder);
  EXPECT_EQ(back.site, site.site);
  EXPECT_EQ(back.stage, site.stage);
  EXPECT_EQ(back.misfit, site.misfit);
  EXPECT_EQ(back.evaluations, site.evaluations);
  EXPECT_EQ(back.wall_seconds, site.wall_seconds);
  EXPECT_EQ(back.grid_spacing_m, site.grid_spacing_m);
  EXPECT_EQ(back.samples_file, folder + "/posterior.csv");
  ASSERT_EQ(back.parameters.size(), site.parameters.size());
  for (std::size_t k = 0; k < site.parameters.size(); ++k) {
    const CalibratedParameter &a = site.parameters[k], &b = back.parameters[k];
    EXPECT_EQ(b.material, a.material);
    EXPECT_EQ(b.material_class, a.material_class);
    EXPECT_TRUE(b.class_given);
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.value, a.value) << "a value is written to the last digit";
    EXPECT_EQ(b.lower, a.lower);
    EXPECT_EQ(b.upper, a.upper);
    EXPECT_EQ(b.std_error, a.std_error);
    ASSERT_TRUE(b.posterior.has_value());
    EXPECT_EQ(b.posterior->median, a.posterior->median);
    EXPECT_EQ(b.posterior->p05, a.posterior->p05);
    EXPECT_EQ(b.posterior->p95, a.posterior->p95);
    EXPECT_EQ(b.posterior->determined, a.posterior->determined);
  }
  EXPECT_EQ(ReadPosteriorSamples(back), samples);

  // Without a posterior, no samples file is named and none is looked for.
  CalibratedSite plain = site;
  for (CalibratedParameter& p : plain.parameters) p.posterior.reset();
  plain.samples_file.clear();
  plain.grid_spacing_m.reset();
  const Json json = ParametersFileJson(plain);
  EXPECT_FALSE(json.contains("posterior_samples"));
  EXPECT_FALSE(json.contains("grid_spacing_m"));
  const CalibratedSite plain_back = ReadCalibratedSite(WriteResult(dir, "plain", json));
  EXPECT_FALSE(plain_back.has_posterior());
  EXPECT_FALSE(plain_back.grid_spacing_m.has_value());
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
  EXPECT_THAT(
      ErrorOf([&] { ReadPosteriorSamples(s); }),
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

}  // namespace
}  // namespace rockcal::calibrate
