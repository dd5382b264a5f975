// rockcal table end to end: result folders in, table.{json,csv,md} out.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::Example;
using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;
using Json = nlohmann::json;

// A result folder holding `parameters` as its parameters.json.
std::string ResultDir(const std::string& name, const Json& parameters) {
  const std::string dir = FreshDir(name);
  fs::create_directories(dir);
  std::ofstream(dir + "/parameters.json") << parameters.dump(2);
  return dir;
}

// Site "A": talus hardness 0.3 and roughness 0.4 m at its upper bound, with class.
Json SiteA() {
  return Json::parse(R"({
    "site": "A", "method": "nlopt:bobyqa", "misfit": 3.0, "evaluations": 20,
    "wall_seconds": 1.0, "grid_spacing_m": 1.0,
    "parameters": [
      {"material": "red", "class": "talus", "name": "hardness", "value": 0.3,
       "lower": 0.1, "upper": 0.8, "std_error": 0.02},
      {"material": "red", "class": "talus", "name": "roughness", "value": 0.4,
       "lower": 0.05, "upper": 0.4, "std_error": null}
    ]})");
}

// Site "B", written before classes: talus hardness 0.5 and 0.6 (two materials
// whose ids are not the class: they become classes of their own).
Json SiteB() {
  return Json::parse(R"({
    "site": "B", "method": "ceres", "misfit": 4.0, "evaluations": 30, "wall_seconds": 2.0,
    "parameters": [
      {"material": "talus", "name": "hardness", "value": 0.5,
       "lower": 0.1, "upper": 0.7, "std_error": null},
      {"material": "scree", "name": "hardness", "value": 0.6,
       "lower": 0.1, "upper": 0.7, "std_error": null}
    ]})");
}

TEST(Table, HandWrittenResults) {
  const std::string a = ResultDir("a", SiteA()), b = ResultDir("b", SiteB());
  const std::string out = FreshDir("out");
  const RunResult run = Rockcal("table " + a + " " + b + " --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* f : {"table.json", "table.csv", "values.csv", "table.md"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const Json j = Json::parse(ReadFile(out + "/table.json"));
  ASSERT_EQ(j["rows"].size(), 3u);
  // scree hardness (B), talus hardness (A 0.3, B 0.5), talus roughness (A, at its bound).
  EXPECT_EQ(j["rows"][0]["class"], "scree");
  const Json& h = j["rows"][1];
  EXPECT_EQ(h["class"], "talus");
  EXPECT_EQ(h["sites"], 2);
  EXPECT_DOUBLE_EQ(h["median"].get<double>(), 0.4);
  EXPECT_DOUBLE_EQ(h["min"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(h["max"].get<double>(), 0.5);
  EXPECT_EQ(h["entries"][0]["std_error"], 0.02);
  EXPECT_EQ(h["entries"][1]["folder"], b);
  const Json& r = j["rows"][2];
  EXPECT_EQ(r["values"], 0);
  EXPECT_TRUE(r["median"].is_null());
  EXPECT_EQ(r["all"]["values"], 1);
  EXPECT_EQ(r["entries"][0]["at_bound"], "upper");
  const std::string notes = j["notes"].dump();
  EXPECT_THAT(notes, HasSubstr(b + "/parameters.json: no \\\"class\\\" on talus, scree"));
  const std::string md = ReadFile(out + "/table.md");
  EXPECT_THAT(md, HasSubstr("| talus | hardness | 2 | 2 | 0.4 | 0.3 – 0.5 | 0 of 2 |"));
  EXPECT_THAT(md, HasSubstr("| talus | roughness | 0 | 0 | – | – | 1 of 1 |"));
  EXPECT_THAT(run.out, HasSubstr("| talus | hardness | 2 | 2 | 0.4 |"));

  // --include-at-bound counts the roughness at its bound: 0.4 m = 1.31 ft.
  const std::string out2 = FreshDir("out2");
  ASSERT_EQ(Rockcal("table " + a + " " + b + " --include-at-bound --quiet --out " + out2).status,
            0);
  EXPECT_THAT(ReadFile(out2 + "/table.md"),
              HasSubstr("| talus | roughness | 1 | 1 | 0.4 m (1.31 ft) |"));
}

TEST(Table, BadInputExitsTwoNamingFileAndPathAndWritesNothing) {
  const std::string a = ResultDir("a", SiteA());
  Json bad = SiteB();
  bad["parameters"][1]["value"] = "high";
  const std::string b = ResultDir("b", bad);
  const std::string out = FreshDir("out");
  RunResult run = Rockcal("table " + a + " " + b + " --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(b + "/parameters.json: $.parameters[1].value: expected a number "
                                     "(found \"high\")"));
  EXPECT_FALSE(fs::exists(out));

  bad = SiteB();
  bad["parameters"][0].erase("upper");
  const std::string c = ResultDir("c", bad);
  run = Rockcal("table " + c + " --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(c + "/parameters.json: $.parameters[0]: missing required key "
                                     "'upper'"));

  std::ofstream(c + "/parameters.json") << "{\"site\": ";
  run = Rockcal("table " + c + " --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(c + "/parameters.json:1:"));

  run = Rockcal("table " + a + " " + a + "/ --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("result folder given twice"));

  run = Rockcal("table " + a + " " + a + "_missing --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(a + "_missing: no such result folder"));

  run = Rockcal("table --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("expected at least one RESULT_DIR"));

  run = Rockcal("table " + a + " --bound-tolerance 0.5 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--bound-tolerance"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(Table, ExistingOutputIsUntouchedWithoutForce) {
  const std::string a = ResultDir("a", SiteA());
  const std::string out = FreshDir("out");
  fs::create_directories(out);
  std::ofstream(out + "/mine.txt") << "precious";
  RunResult run = Rockcal("table " + a + " --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--force"));
  EXPECT_EQ(ReadFile(out + "/mine.txt"), "precious");
  EXPECT_FALSE(fs::exists(out + "/table.json"));
  // Nor replaced by a run that fails on its input, even with --force.
  run = Rockcal("table " + a + " " + a + "_missing --force --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(ReadFile(out + "/mine.txt"), "precious");

  // Nor with --force: rockcal did not write it.
  run = Rockcal("table " + a + " --force --quiet --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr(".rockcal-output"));
  EXPECT_EQ(ReadFile(out + "/mine.txt"), "precious");
  fs::remove_all(out);
  EXPECT_EQ(Rockcal("table " + a + " --quiet --out " + out).status, 0);
  std::ofstream(out + "/mine.txt") << "stale";
  EXPECT_EQ(Rockcal("table " + a + " --force --quiet --out " + out).status, 0);
  EXPECT_FALSE(fs::exists(out + "/mine.txt"));
  EXPECT_TRUE(fs::exists(out + "/table.json"));

  // A result folder is never replaced by its table.
  run = Rockcal("table " + a + " --force --out " + a);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("is an input of this run"));
  EXPECT_TRUE(fs::exists(a + "/parameters.json"));
}

// A real calibration (tiny: 4 rocks, 2 evaluations) carries its classes into
// parameters.json, and the table pools it with a hand-written result.
TEST(Table, CalibrateThenTable) {
  const std::string cal = FreshDir("cal");
  const std::string obs =
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/observations.json";
  RunResult run = Rockcal("calibrate " + Example("tutorial") + " --observations " + obs +
                          " --rocks 4 --max-evals 2 --quiet --out " + cal);
  ASSERT_EQ(run.status, 0) << run.err;
  const Json p = Json::parse(ReadFile(cal + "/parameters.json"));
  ASSERT_EQ(p["parameters"].size(), 4u);
  for (const Json& e : p["parameters"]) EXPECT_EQ(e["class"], e["material"]) << e.dump();
  EXPECT_NEAR(p["grid_spacing_m"].get<double>(), 3.6576, 1e-12);
  EXPECT_THAT(ReadFile(cal + "/parameters.csv"), HasSubstr("material,class,name,"));

  const std::string a = ResultDir("a", SiteA());
  const std::string out = FreshDir("out");
  run = Rockcal("table " + cal + " " + a + " --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  const Json j = Json::parse(ReadFile(out + "/table.json"));
  // soil hardness, soil roughness, talus hardness, talus roughness.
  ASSERT_EQ(j["rows"].size(), 4u);
  const Json& h = j["rows"][2];
  EXPECT_EQ(h["class"], "talus");
  EXPECT_EQ(h["parameter"], "hardness");
  EXPECT_EQ(h["all"]["sites"], 2);
  EXPECT_EQ(h["entries"][0]["site"], "Tutorial slope");
  EXPECT_EQ(h["entries"][0]["value"], p["parameters"][0]["value"]);
  EXPECT_THAT(j["notes"].dump(), HasSubstr("different spacings (1 m, 3.6576 m)"));
}

}  // namespace
}  // namespace rockcal::cli
