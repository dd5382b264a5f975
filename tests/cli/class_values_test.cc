// rockcal simulate of a site whose materials take values from a class table
// (docs/reference/site-file.md#material-classes): the medians exactly with
// --class-values median, draws within the table's intervals the same at any
// thread count, the errors; and the shipped table is rockcal table of the
// shipped calibrations (sites/tables/make_default_table.sh).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using ::testing::HasSubstr;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;
using Json = nlohmann::json;

// The tutorial slope with its talus of class "meadow" from a table of the
// test's own (hardness 0.4 in a posterior envelope [0.2, 0.7], roughness
// 0.3 m in a range [0.25, 0.5] m); returns the site file.
std::string ClassSite(const std::string& talus_class = "meadow") {
  const std::string dir = FreshDir("class_site");
  fs::create_directories(dir);
  const std::string tutorial = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  fs::copy_file(tutorial + "/points.csv", dir + "/points.csv");
  std::ofstream(dir + "/table.json") << R"({"rows": [
    {"class": "meadow", "parameter": "hardness", "sites": 2, "values": 2, "median": 0.4,
     "min": 0.35, "max": 0.45, "posterior": {"p05": 0.2, "p95": 0.7, "values": 2}},
    {"class": "meadow", "parameter": "roughness", "sites": 2, "values": 2, "median": 0.3,
     "min": 0.25, "max": 0.5, "posterior": null}]})";
  std::ifstream in(tutorial + "/site.json");
  Json site = Json::parse(in);
  Json& talus = site["materials"][1];
  talus.erase("hardness");
  talus.erase("roughness");
  talus.erase("calibrate");
  talus["class"] = talus_class;
  talus["table"] = "table.json";
  std::ofstream(dir + "/site.json") << site.dump(2);
  return dir + "/site.json";
}

Json Summary(const std::string& dir) {
  std::ifstream in(dir + "/summary.json");
  return Json::parse(in);
}

TEST(ClassValues, MedianTakesTheTablesMediansAndSaysSo) {
  const std::string site = ClassSite(), out = FreshDir("median");
  const RunResult r =
      Rockcal("simulate " + site + " --rocks 6 --class-values median --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("class values: the medians of "));
  EXPECT_THAT(r.out, HasSubstr("a calibration of this site against field data would narrow "
                               "them"));
  const Json summary = Summary(out);
  EXPECT_FALSE(summary.contains("parameters")) << summary.dump();
  const Json& classes = summary["classes"];
  EXPECT_EQ(classes["use"], "medians");
  EXPECT_THAT(classes["note"].get<std::string>(), HasSubstr("would narrow them"));
  const Json& m = classes["materials"].at(0);
  EXPECT_EQ(m["material"], "talus");
  EXPECT_EQ(m["class"], "meadow");
  EXPECT_EQ(m["values"][0]["parameter"], "hardness");
  EXPECT_EQ(m["values"][0]["median"].get<double>(), 0.4);
  EXPECT_EQ(m["values"][0]["interval"]["kind"], "posterior envelope");
  EXPECT_FALSE(m["values"][0]["drawn"].get<bool>());
  EXPECT_EQ(m["values"][1]["median"].get<double>(), 0.3);
  const std::string report = ReadFile(out + "/report.html");
  EXPECT_THAT(report, HasSubstr("Values from the class table"));
  EXPECT_THAT(report, HasSubstr("would narrow them"));
}

TEST(ClassValues, DrawsStayInTheIntervalsTheSameAtAnyThreadCount) {
  const std::string site = ClassSite();
  const std::string one = FreshDir("one"), two = FreshDir("two");
  RunResult r = Rockcal("simulate " + site + " --rocks 12 --draws 4 --threads 1 --quiet --out " + one);
  ASSERT_EQ(r.status, 0) << r.err;
  r = Rockcal("simulate " + site + " --rocks 12 --draws 4 --threads 2 --quiet --out " + two);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(ReadFile(one + "/rocks.csv"), ReadFile(two + "/rocks.csv"));
  EXPECT_EQ(ReadFile(one + "/draws.csv"), ReadFile(two + "/draws.csv"));
  const Json summary = Summary(one);
  EXPECT_EQ(summary["parameters"]["use"], "class draws") << summary["parameters"].dump();
  EXPECT_EQ(summary["parameters"]["draws"].get<int>(), 4);
  EXPECT_EQ(summary["classes"]["use"], "draws");
  EXPECT_TRUE(summary["classes"]["materials"][0]["values"][0]["drawn"].get<bool>());
  // draws.csv: draw,sample,rocks,talus.hardness,talus.roughness (SI), each
  // value within its interval, and not all the same.
  std::istringstream draws(ReadFile(one + "/draws.csv"));
  std::string line;
  std::getline(draws, line);
  EXPECT_EQ(line, "draw,sample,rocks,talus.hardness,talus.roughness");
  int rows = 0;
  double first = -1.0;
  bool differ = false;
  while (std::getline(draws, line)) {
    double h = 0, rough = 0;
    int d = 0, s = 0, n = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%d,%d,%lf,%lf", &d, &s, &n, &h, &rough), 5) << line;
    EXPECT_GE(h, 0.2) << line;
    EXPECT_LE(h, 0.7) << line;
    EXPECT_GE(rough, 0.25) << line;
    EXPECT_LE(rough, 0.5) << line;
    EXPECT_EQ(n, 3) << line;
    if (rows == 0) first = h;
    differ = differ || h != first;
    ++rows;
  }
  EXPECT_EQ(rows, 4);
  EXPECT_TRUE(differ);
  EXPECT_THAT(ReadFile(one + "/report.html"), HasSubstr("Draws from the class table and bands"));
  // Another seed draws other sets.
  const std::string three = FreshDir("three");
  r = Rockcal("simulate " + site + " --rocks 12 --draws 4 --seed 9 --quiet --out " + three);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(ReadFile(one + "/draws.csv"), ReadFile(three + "/draws.csv"));
}

TEST(ClassValues, BadClassesAndOptionsExitTwo) {
  RunResult r = Rockcal("simulate " + ClassSite("medow") + " --rocks 4 --out " + FreshDir("bad"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("site.json: $.materials[1].class: unknown class in the table "));
  EXPECT_THAT(r.err, HasSubstr("table.json; expected one of its classes: meadow (found \"medow\")"));
  const std::string site = ClassSite();
  r = Rockcal("simulate " + site + " --rocks 4 --class-values mean --out " + FreshDir("mean"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("--class-values: 'mean' is not a choice; expected draws or median"));
  r = Rockcal("simulate " + testing::Example("tutorial") + " --rocks 4 --class-values median --out " +
              FreshDir("none"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("the site has no material that takes its values from a class"));
}

// The shipped table is what rockcal table makes of the shipped calibrations
// and about.json (as sites/tables/make_default_table.sh runs it).
TEST(ClassValues, TheShippedTableIsTheTableOfTheShippedCalibrations) {
  const std::string tables = std::string(ROCKCAL_SOURCE_DIR) + "/sites/tables";
  const std::string out = FreshDir("table");
  const RunResult r = testing::Run("cd " + tables + " && " + ROCKCAL_EXE +
                          " table calibrations/authume calibrations/tschamut --about about.json "
                          "--quiet --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Json::parse(ReadFile(out + "/table.json")),
            Json::parse(ReadFile(tables + "/default.json")));
  EXPECT_EQ(ReadFile(out + "/table.md"), ReadFile(tables + "/default.md"));
}

// --about must describe every class and name every site's data.
TEST(ClassValues, AnAboutFileMissingAClassOrASiteExitsTwo) {
  const std::string tables = std::string(ROCKCAL_SOURCE_DIR) + "/sites/tables";
  Json about = Json::parse(ReadFile(tables + "/about.json"));
  about["classes"].erase("meadow");
  const std::string dir = FreshDir("about");
  fs::create_directories(dir);
  std::ofstream(dir + "/about.json") << about.dump(2);
  RunResult r = Rockcal("table " + tables + "/calibrations/tschamut --about " + dir +
                        "/about.json --quiet --out " + dir + "/out");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr(dir + "/about.json: $.classes: no class 'meadow'; expected a "
                               "description of every class of the table"));
  about = Json::parse(ReadFile(tables + "/about.json"));
  about["sites"].erase("Tschamut 2014");
  std::ofstream(dir + "/about.json") << about.dump(2);
  r = Rockcal("table " + tables + "/calibrations/tschamut --about " + dir + "/about.json --quiet --out " +
              dir + "/out");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.err, HasSubstr("$.sites: no site 'Tschamut 2014'"));
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

}  // namespace
}  // namespace rockcal::cli
