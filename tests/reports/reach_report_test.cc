// report.html of the reach check and its section: well-formed,
// self-contained, every shown number equal to reach.json, verdicts coloured.
#include "rockcal/reports/reach_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "report_check.h"
#include "rockcal/sites/site.h"
#include "xml_check.h"

namespace rockcal::reports {
namespace {

using testing::CheckNumbers;
using testing::ExpectSelfContained;
using testing::FindSection;
using testing::Parsed;
using testing::ParseReport;
using testing::ParseXml;
using testing::XmlNode;

calibrate::ReachStatistic Stat(const observations::ResidualId& id, double observed, double sigma,
                               double min, double max, calibrate::ReachVerdict verdict) {
  calibrate::ReachStatistic s;
  s.id = id;
  s.observed = observed;
  s.sigma = sigma;
  s.min = min;
  s.max = max;
  s.min_point = 0;
  s.max_point = 1;
  s.closest_point = 1;
  s.closest_simulated = max;
  s.closest_sigmas = (max - observed) / sigma;
  s.points_with_value = 2;
  s.verdict = verdict;
  return s;
}

// Two points, four statistics by hand: one in reach, one far above the
// range (beyond the plot's 10 sigmas), one with no value at any point, and
// one in reach by its sigma only (at the edge).
calibrate::ReachResult HandResult() {
  calibrate::ReachResult r;
  r.candidates = 10;
  r.design_seed = 4;
  r.simulation_seed = 1;
  r.rocks = 41;
  calibrate::Parameter p;
  p.material = "talus";
  p.lower = 0.1;
  p.upper = 0.7;
  r.parameters = {p};
  using observations::ObservationKind;
  using observations::ResidualId;
  using observations::Statistic;
  const ResidualId distance = ResidualId::Of(ObservationKind::kRunoutDistance);
  r.statistics = {
      Stat(distance.With(Statistic::kQuantile, 0.5), 40.0, 2.5, 31.0, 57.0,
           calibrate::ReachVerdict::kInReach),
      Stat(distance.With(Statistic::kMax), 500.0, 3.0, 60.0, 95.0, calibrate::ReachVerdict::kAbove),
      Stat(ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] <P&1>")
               .With(Statistic::kFraction),
           0.3, 0.05, NAN, NAN, calibrate::ReachVerdict::kNoValue),
      Stat(ResidualId::Of(ObservationKind::kRunoutLateral).With(Statistic::kQuantile, 0.9), 10.0,
           2.0, 1.0, 9.0, calibrate::ReachVerdict::kInReach)};
  calibrate::ReachStatistic& none = r.statistics[2];
  none.min_point = none.max_point = none.closest_point = -1;
  none.points_with_value = 0;
  none.closest_simulated = none.closest_sigmas = NAN;
  for (int k = 0; k < 2; ++k) {
    calibrate::ReachPoint point;
    point.unit = {0.25 + 0.5 * k};
    point.physical = {0.25 + 0.3 * k};
    point.misfit = 80.0 - 30.0 * k;
    point.simulated = {k ? 57.0 : 31.0, k ? 95.0 : 60.0, NAN, k ? 9.0 : 1.0};
    point.sigma = {2.5, 3.0, NAN, 2.0};
    r.points.push_back(point);
  }
  r.best_point = 1;
  r.wall_seconds = 1.25;
  return r;
}

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
  const calibrate::ReachResult r = HandResult();
  const Parsed p = ParseReport(ReachHtmlReport(in, r));
  ExpectSelfContained(p);
  EXPECT_EQ(p.sections, (std::vector<std::string>{"site", "reach"}));
  const nlohmann::json json = calibrate::ReachJson(site.scene.name, r);
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
  const std::string svg = ReachSvg(HandResult());
  std::string error;
  ASSERT_NE(ParseXml(svg, &error), nullptr) << error;
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  // The max bar runs from (60 - 500) / 3 to (95 - 500) / 3 sigmas: cut at -10.
  EXPECT_NE(svg.find("from -147"), std::string::npos);
  EXPECT_NE(svg.find("no value"), std::string::npos);
  EXPECT_NE(svg.find("runout distance p50"), std::string::npos);
}

TEST(ReachReport, SectionRefersToTheGivenJsonFile) {
  const std::string html = ReachSection(HandResult(), "calibration.json");
  EXPECT_NE(html.find("data-json=\"calibration.json#/statistics/0/observed\""), std::string::npos);
  EXPECT_EQ(html.find("reach.json"), std::string::npos);
}

}  // namespace
}  // namespace rockcal::reports
