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
  EXPECT_THAT(run.err, HasSubstr("nope"));
  run = Rockcal("study convergence " + Example("profile2d") + " --rocks 5 --out " + out);
  EXPECT_EQ(run.status, 2);
  EXPECT_THAT(run.err, HasSubstr("--rock-counts"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace rockcal::cli
