// rockcal study stability / convergence end to end, as a user runs them: the
// files each writes (report.html among them), what it prints, and bad input.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::Example;
using testing::FreshDir;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

TEST(Study, StabilityWritesTablesAndReport) {
  const std::string out = FreshDir("stability");
  const RunResult run = Rockcal("study stability " + Example("profile2d") +
                                " --rocks 2 --cases site,flat_runout --threads 2 --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("wrote " + out + "/stability.json, stability.csv, report.html"));
  const nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/stability.json"));
  EXPECT_EQ(j["cases"].size(), 2u);
  EXPECT_TRUE(fs::exists(out + "/stability.csv"));
  const std::string html = ReadFile(out + "/report.html");
  EXPECT_THAT(html, HasSubstr("<section id=\"site\">"));
  EXPECT_THAT(html, HasSubstr("<section id=\"stability\">"));
  EXPECT_THAT(html,
              HasSubstr("data-json=\"stability.json#/cases/1/name\" data-value=\"flat_runout\""));
}

TEST(Study, ConvergenceWritesTablesPlotAndReport) {
  const std::string out = FreshDir("convergence");
  const RunResult run = Rockcal(
      "study convergence " + Example("profile2d") +
      " --steps-per-contact 10,20 --rock-counts 12,24 --bootstrap 20 --threads 2 --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("wrote " + out +
                                 "/convergence.json, convergence.csv, convergence.svg, "
                                 "report.html"));
  for (const char* file : {"convergence.json", "convergence.csv", "convergence.svg"})
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  const std::string svg = ReadFile(out + "/convergence.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  const std::string html = ReadFile(out + "/report.html");
  EXPECT_THAT(html, HasSubstr("<section id=\"convergence\">"));
  EXPECT_THAT(html, HasSubstr(svg.substr(0, svg.size() - 1))) << "the plot is inline";
}

TEST(Study, BadInputExitsTwoAndLeavesNothing) {
  const std::string out = FreshDir("bad");
  RunResult run = Rockcal("study stability " + Example("profile2d") + " --cases nope --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("argument --cases: unknown case 'nope' (allowed: site, "));
  run = Rockcal("study convergence " + Example("profile2d") + " --rocks 5 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--rock-counts"));
  EXPECT_FALSE(fs::exists(out));
}

// The observations file of a bundled example.
std::string ExampleObservations(const std::string& name) {
  return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/" + name + "/observations.json";
}

TEST(Study, ReachWritesTablesAndReportAndNamesWhatIsOutOfReach) {
  const std::string out = FreshDir("reach");
  const RunResult run =
      Rockcal("study reach " + Example("twin") + " --observations " + ExampleObservations("twin") +
              " --points 4 --rocks 6 --threads 2 --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("wrote " + out + "/reach.json, reach.csv, report.html"));
  EXPECT_THAT(run.out, HasSubstr("runout distance p50"));
  const nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/reach.json"));
  EXPECT_EQ(j["points"].size(), 4u);
  EXPECT_EQ(j["rocks"], 6);
  ASSERT_FALSE(j["statistics"].empty());
  // Every out-of-reach statistic is printed plainly, by name.
  for (const auto& s : j["statistics"]) {
    if (!s["in_reach"].get<bool>()) {
      EXPECT_THAT(run.out, HasSubstr("OUT OF REACH: " + s["name"].get<std::string>() + " is"));
    }
  }
  EXPECT_TRUE(fs::exists(out + "/reach.csv"));
  const std::string html = ReadFile(out + "/report.html");
  EXPECT_THAT(html, HasSubstr("<section id=\"reach\">"));
  EXPECT_THAT(html, HasSubstr("data-json=\"reach.json#/statistics/0/observed\""));
}

TEST(Study, ReachReportsARunoutTheSlopeCannotProduce) {
  const std::string dir = FreshDir("far");
  fs::create_directories(dir);
  const std::string obs = dir + "/far.json";
  // The twin slope ends 90 m from the release; these rocks "stopped" 500 m on.
  std::ofstream(obs) << R"({"units": "si", "runout": {"stop_points": [[500, 10], [510, 9],
      [520, 11], [530, 10], [540, 10]]}, "error": {"runout": 1.0}})";
  const std::string out = dir + "/out";
  const RunResult run = Rockcal("study reach " + Example("twin") + " --observations " + obs +
                                " --points 3 --rocks 4 --quiet --out " + out);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("OUT OF REACH: runout distance p50 is out of reach: observed"));
  EXPECT_THAT(run.out, HasSubstr("above the range"));
  const nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/reach.json"));
  for (const auto& s : j["statistics"]) {
    // A quantile above the share of rocks that stopped may be reached by a
    // rock that left the slope: it is censored at or beyond the farthest
    // observed stop (it may have gone that far). At some points of the box
    // half the rocks run off the twin's 90 m.
    const std::string q = s["quantity"];
    if (s["observation"] == "runout distance" && q.size() == 3 && q[0] == 'p' &&
        std::stoi(q.substr(1)) <= 50) {
      EXPECT_EQ(s["verdict"], "out of reach (above)") << s["name"];
    }
  }
}

TEST(Study, ReachBadInputExitsTwoAndLeavesNothing) {
  const std::string out = FreshDir("reach_bad");
  RunResult run = Rockcal("study reach " + Example("twin") + " --points 4 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--observations"));
  const std::string obs = ExampleObservations("twin");
  run = Rockcal("study reach " + Example("twin") + " --observations " + obs + " --points 1 --out " +
                out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--points"));
  run = Rockcal("study reach " + Example("twin") + " --observations " + obs +
                " --design sobol --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("sobol"));
  EXPECT_THAT(run.err, HasSubstr("lhs, halton"));
  run = Rockcal("study reach " + Example("twin") + " --observations " + obs +
                " --cases site --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("a stability option"));
  run = Rockcal("study stability " + Example("twin") + " --points 3 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("a reach option"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace rockcal::cli
