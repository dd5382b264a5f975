// report.html of the reach check and its section: well-formed,
// self-contained, every shown number equal to reach.json, verdicts coloured.
#include "rockcal/reports/reach_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hand_results.h"
#include "report_check.h"
#include "rockcal/sites/site.h"
#include "xml_check.h"

namespace rockcal::reports {
namespace {

using testing::CheckNumbers;
using testing::ExpectSelfContained;
using testing::FindSection;
using testing::HandReach;
using testing::Parsed;
using testing::ParseReport;
using testing::ParseXml;
using testing::XmlNode;

std::vector<const XmlNode*> Cells(const XmlNode& root, const std::string& cls) {
  std::vector<const XmlNode*> out;
  root.Visit([&](const XmlNode& n) {
    if (n.name == "td" && n.Attribute("class") == cls) out.push_back(&n);
  });
  return out;
}

TEST(ReachReport, IsSelfContainedAndItsNumbersAreReachJson) {
  const sites::Site site =
      sites::LoadSite(std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/profile2d/site.json");
  StudyReportInput in;
  in.scene = &site.scene;
  in.site_file = site.path;
  in.units = site.units;
  const calibrate::ReachResult r = HandReach();
  const Parsed p = ParseReport(ReachHtmlReport(in, r));
  ExpectSelfContained(p);
  EXPECT_EQ(p.sections, (std::vector<std::string>{"site", "reach"}));
  const nlohmann::json json = r;
  const auto seen = CheckNumbers(p, {{"reach.json", json}});
  ASSERT_TRUE(seen.count("reach.json"));
  for (const char* pointer : {"/statistics/0/observed", "/statistics/0/sigma", "/statistics/1/min",
                              "/statistics/1/max", "/points/1/misfit", "/points/1/physical/0"})
    EXPECT_TRUE(seen.at("reach.json").count(pointer)) << pointer;
  const XmlNode* section = FindSection(p, "reach");
  ASSERT_NE(section, nullptr);
  const auto ok = Cells(*section, "ok"), bad = Cells(*section, "bad");
  ASSERT_EQ(ok.size(), 1u);
  EXPECT_EQ(ok[0]->AllText(), "in reach");
  const auto edge = Cells(*section, "warn");
  ASSERT_EQ(edge.size(), 1u);
  EXPECT_EQ(edge[0]->AllText(), "in reach (at the edge)");
  EXPECT_NE(p.html.find("2 of 4 statistics in reach (1 at the edge)"), std::string::npos);
  ASSERT_EQ(bad.size(), 2u);
  EXPECT_EQ(bad[0]->AllText(), "out of reach (above)");
  EXPECT_EQ(bad[1]->AllText(), "out of reach (no value)");
  EXPECT_NE(p.html.find("out of reach: runout distance max, passing[0] &lt;P&amp;1&gt; fraction"),
            std::string::npos);
}

TEST(ReachReport, PlotCutsBarsAtTenSigmasAndMarksNoValue) {
  const std::string svg = ReachSvg(HandReach());
  std::string error;
  ASSERT_NE(ParseXml(svg, &error), nullptr) << error;
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  // The max bar runs from (60 - 500) / 3 to (95 - 500) / 3 sigmas: cut at -10.
  EXPECT_NE(svg.find("from -147"), std::string::npos);
  EXPECT_NE(svg.find("no value"), std::string::npos);
  EXPECT_NE(svg.find("runout distance p50"), std::string::npos);
}

TEST(ReachReport, SectionRefersToTheGivenJsonFile) {
  const std::string html = ReachSection(HandReach(), "calibration.json");
  EXPECT_NE(html.find("data-json=\"calibration.json#/statistics/0/observed\""), std::string::npos);
  EXPECT_EQ(html.find("reach.json"), std::string::npos);
}

}  // namespace
}  // namespace rockcal::reports
