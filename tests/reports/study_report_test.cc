// report.html of the studies and convergence.svg: well-formed, self-contained,
// the sections promised, and every number marked with data-json equal to
// stability.json or convergence.json.
#include "rockcal/reports/study_report.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "hand_results.h"
#include "report_check.h"
#include "rockcal/sites/site.h"
#include "xml_check.h"

namespace rockcal::reports {
namespace {

using testing::Case;
using testing::CheckNumbers;
using testing::Example;
using testing::ExpectSelfContained;
using testing::FindSection;
using testing::HandCases;
using testing::HandConvergence;
using testing::Input;
using testing::Leaves;
using testing::Parsed;
using testing::ParseReport;
using testing::ParseXml;
using testing::SmallStudy;
using testing::Study;
using testing::Unescape;
using testing::XmlNode;

constexpr double kInf = std::numeric_limits<double>::infinity();

// The elements of `root` below section `id` with class `cls` among their classes.
std::vector<const XmlNode*> WithClass(const XmlNode& root, const std::string& cls) {
  std::vector<const XmlNode*> out;
  root.Visit([&](const XmlNode& n) {
    const std::string c = " " + n.Attribute("class") + " ";
    if (c.find(" " + cls + " ") != std::string::npos) out.push_back(&n);
  });
  return out;
}

// Every leaf of `json` under `prefix` that the report must show: numbers that
// are not null, and the strings named in `strings` (where not empty).
std::set<std::string> Expected(const nlohmann::json& json, const std::string& prefix,
                               const std::set<std::string>& strings) {
  std::set<std::string> out;
  for (const std::string& leaf : Leaves(json)) {
    if (leaf.rfind(prefix, 0) != 0) continue;
    const nlohmann::json& v = json.at(nlohmann::json::json_pointer(leaf));
    const std::string key = leaf.substr(leaf.rfind('/') + 1);
    if (v.is_number() || (v.is_string() && strings.count(key) && !v.get<std::string>().empty()))
      out.insert(leaf);
  }
  return out;
}

// ---- stability -------------------------------------------------------------------

void CheckStabilityReport(const sites::Site& site, const calibrate::StabilityStudy& study) {
  const std::vector<calibrate::StabilityCase>& cases = study.cases;
  const Parsed p = ParseReport(StabilityHtmlReport(Input(site), study));
  ExpectSelfContained(p);
  EXPECT_EQ(p.sections, (std::vector<std::string>{"site", "stability"}));
  const nlohmann::json json = study;
  auto seen = CheckNumbers(p, {{"stability.json", json}});
  std::set<std::string> expected =
      Expected(json, "/cases/", {"name", "description", "result", "reason", "warning"});
  for (const std::string& leaf : Expected(json, "/limits/", {})) expected.insert(leaf);
  for (const char* leaf : {"/site", "/passed"}) expected.insert(leaf);
  if (json["failed"] > 0) expected.insert("/failed");  // "12 cases: 12 PASS" when none failed
  for (std::size_t k = 0; k < cases.size(); ++k)       // one step shown when the steps are equal
    if (cases[k].figures.dt_min == cases[k].figures.dt_max)
      expected.erase("/cases/" + std::to_string(k) + "/dt_max_seconds");
  for (const std::string& leaf : expected)
    EXPECT_TRUE(seen["stability.json"].count(leaf)) << "stability.json" << leaf << " not shown";

  // The verdict, and PASS / FAIL visibly marked.
  const XmlNode* section = FindSection(p, "stability");
  ASSERT_NE(section, nullptr);
  int failed = 0;
  for (const auto& c : cases) failed += !c.pass;
  const std::string text = Unescape(section->AllText());
  std::string verdict =
      std::to_string(cases.size()) + " cases: " + std::to_string(cases.size() - failed) + " PASS";
  if (failed > 0) verdict += ", " + std::to_string(failed) + " FAIL (";
  EXPECT_NE(text.find(verdict), std::string::npos) << verdict;
  std::vector<const XmlNode*> results = WithClass(*section, "result");
  ASSERT_EQ(results.size(), cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string cls = results[k]->Attribute("class");
    EXPECT_NE(cls.find(cases[k].pass ? "ok" : "bad"), std::string::npos) << cases[k].name;
    EXPECT_EQ(Unescape(results[k]->AllText()).rfind(cases[k].pass ? "PASS" : "FAIL", 0), 0u);
  }
}

TEST(StudyReportTest, StabilityReportShowsTheCasesOfStabilityJson) {
  const sites::Site site = Example("profile2d");
  const calibrate::StabilityStudy study = Study(site, {}, HandCases());
  CheckStabilityReport(site, study);
  const Parsed p = ParseReport(StabilityHtmlReport(Input(site), study));
  const XmlNode* section = FindSection(p, "stability");
  // The reasons and the warning are in the table; the failing cells are marked.
  const std::string text = Unescape(section->AllText());
  EXPECT_NE(text.find("2 rocks tunneled"), std::string::npos);
  EXPECT_NE(text.find("warning: overlap reached 3.68"), std::string::npos);
  EXPECT_NE(text.find("non-finite"), std::string::npos) << "the null energy gain is shown";
  EXPECT_NE(text.find("a case & its <description>"), std::string::npos);
  EXPECT_EQ(WithClass(*section, "bad").size(), 8u)
      << "the verdict, 2 FAIL results, tunneled, energy gain 0.5 and non-finite (twice: gain "
         "and count), rocks that did not stop";
  EXPECT_EQ(WithClass(*section, "warn").size(), 2u) << "overlap cell and warning text";
  EXPECT_EQ(WithClass(*section, "fail").size(), 2u) << "failing rows";
  // The site section is the site's, without links to partition sections.
  const XmlNode* site_section = FindSection(p, "site");
  ASSERT_NE(site_section, nullptr);
  EXPECT_NE(site_section->AllText().find("P-talus"), std::string::npos);
  EXPECT_EQ(site_section->AllText().find("rocks passed"), std::string::npos);
}

TEST(StudyReportTest, StabilityReportOfAllPassingCasesSaysSo) {
  const sites::Site site = Example("tutorial");  // US units
  const calibrate::StabilityStudy study =
      Study(site, {}, {Case("site", true), Case("roughness_0", true)});
  const Parsed p = ParseReport(StabilityHtmlReport(Input(site), study));
  CheckStabilityReport(site, study);
  const XmlNode* section = FindSection(p, "stability");
  ASSERT_NE(section, nullptr);
  EXPECT_NE(Unescape(section->AllText()).find("2 cases: 2 PASS"), std::string::npos);
  EXPECT_EQ(Unescape(section->AllText()).find("FAIL"), std::string::npos);
  EXPECT_TRUE(WithClass(*section, "bad").empty());
}

// ---- convergence -----------------------------------------------------------------

void CheckConvergenceReport(const sites::Site& site, const calibrate::ConvergenceResult& r) {
  const Parsed p = ParseReport(ConvergenceHtmlReport(Input(site), r));
  ExpectSelfContained(p);
  EXPECT_EQ(p.sections, (std::vector<std::string>{"site", "convergence"}));
  const nlohmann::json json = r;
  auto seen = CheckNumbers(p, {{"convergence.json", json}});
  // Every setting's numbers (the per-quantity detail only at the reference).
  std::set<std::string> expected;
  for (const std::string& leaf : Expected(json, "/rows/", {})) {
    const bool detail = leaf.find("/quantities/") != std::string::npos;
    if (!detail) expected.insert(leaf);
  }
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const std::string row = "/rows/" + std::to_string(k) + "/";
    if (r.rows[k].figures.dt_min == r.rows[k].figures.dt_max)
      expected.erase(row + "dt_max_seconds");
    for (const char* key : {"stopped", "left", "timeout"}) expected.erase(row + "outcomes/" + key);
    expected.erase(row + "flights");
  }
  const std::string ref = "/rows/" + std::to_string(r.reference) + "/quantities/";
  for (std::size_t q = 0; q < r.quantities.size(); ++q)
    for (const char* key : {"name", "value", "count", "mc_error"}) {
      const std::string leaf = ref + std::to_string(q) + "/" + key;
      if (!json.at(nlohmann::json::json_pointer(leaf)).is_null()) expected.insert(leaf);
    }
  for (const char* leaf : {"/site", "/target", "/bootstrap", "/confidence", "/seed", "/threads",
                           "/recommendation", "/reference/steps_per_contact", "/reference/rocks"})
    expected.insert(leaf);
  for (std::size_t k = 0; k < r.notes.size(); ++k) expected.insert("/notes/" + std::to_string(k));
  for (const std::string& leaf : expected)
    EXPECT_TRUE(seen["convergence.json"].count(leaf)) << "convergence.json" << leaf << " not shown";
  // The plot inline, the same as convergence.svg.
  const XmlNode* section = FindSection(p, "convergence");
  ASSERT_NE(section, nullptr);
  std::string svg = ConvergenceSvg(r);
  while (!svg.empty() && svg.back() == '\n') svg.pop_back();
  EXPECT_NE(p.html.find(svg), std::string::npos) << "the inline plot is convergence.svg";
  int svgs = 0;
  section->Visit([&](const XmlNode& n) { svgs += n.name == "svg"; });
  EXPECT_EQ(svgs, 1);
  // The recommended row is marked; unknown errors say so.
  const std::vector<const XmlNode*> best = WithClass(*section, "best");
  EXPECT_EQ(best.size(), r.recommended >= 0 ? 1u : 0u);
  EXPECT_NE(Unescape(section->AllText()).find("Recommendation: " + r.recommendation),
            std::string::npos);
}

TEST(StudyReportTest, ConvergenceReportShowsEverySettingOfConvergenceJson) {
  const sites::Site site = Example("profile2d");
  CheckConvergenceReport(site, HandConvergence(true));
  CheckConvergenceReport(site, HandConvergence(false));
  // Errors resting on too few values are unknown (null in the JSON).
  const Parsed p = ParseReport(ConvergenceHtmlReport(Input(site), HandConvergence(true)));
  EXPECT_NE(Unescape(FindSection(p, "convergence")->AllText()).find("unknown"), std::string::npos);
}

TEST(StudyReportTest, ConvergenceSvgIsALogLogPlotWithTheTarget) {
  calibrate::ConvergenceResult r = HandConvergence(true);
  const std::string svg = ConvergenceSvg(r);
  std::string error;
  const auto root = ParseXml(svg, &error);
  ASSERT_NE(root, nullptr) << error;
  EXPECT_EQ(root->name, "svg");
  EXPECT_EQ(svg.find("<script"), std::string::npos);
  EXPECT_NE(svg.find("small &lt;slope&gt;: error estimate against run time"), std::string::npos);
  EXPECT_NE(svg.find("log scale"), std::string::npos);
  int polylines = 0, dashed = 0, rings = 0;
  std::set<std::string> labels;
  root->Visit([&](const XmlNode& n) {
    polylines += n.name == "polyline";
    if (n.name == "line" && n.Attribute("stroke-dasharray") == "6 4") ++dashed;
    if (n.name == "circle" && n.Attribute("r") == "8") ++rings;
    if (n.name == "text") labels.insert(Unescape(n.AllText()));
  });
  EXPECT_EQ(polylines, 1) << "N_c = 20; N_c = 10 has one finite estimate, a point";
  EXPECT_EQ(dashed, 1) << "the target";
  EXPECT_EQ(rings, 1) << "the recommendation";
  for (const char* label : {"N_c = 10", "N_c = 20", "target 20 %", "recommended", "50", "100"})
    EXPECT_TRUE(labels.count(label)) << label;
  // Without a recommendation no ring; with no finite estimate, an empty plot that says so.
  r.recommended = -1;
  EXPECT_EQ(ConvergenceSvg(r).find("recommended"), std::string::npos);
  for (auto& row : r.rows) row.max_estimate = kInf;
  const std::string empty = ConvergenceSvg(r);
  ASSERT_NE(ParseXml(empty, &error), nullptr) << error;
  EXPECT_NE(empty.find("no setting has a finite error estimate"), std::string::npos);
}

TEST(StudyReportTest, RejectsAMissingSceneOrReference) {
  const calibrate::ConvergenceResult r = HandConvergence(true);
  EXPECT_THROW(StabilityHtmlReport(StudyReportInput{}, calibrate::StabilityStudy{}),
               std::invalid_argument);
  EXPECT_THROW(ConvergenceHtmlReport(StudyReportInput{}, r), std::invalid_argument);
  const sites::Site site = Example("profile2d");
  calibrate::ConvergenceResult no_reference = r;
  no_reference.reference = -1;
  EXPECT_THROW(ConvergenceHtmlReport(Input(site), no_reference), std::invalid_argument);
}

// The reports of real (tiny) studies of an example site.
TEST(StudyReportTest, ReportsOfTinyStudiesOfProfile2d) {
  const auto start = std::chrono::steady_clock::now();
  const sites::Site site = Example("profile2d");
  calibrate::StabilityOptions stability;
  stability.rocks = 2;
  stability.max_time = 10.0;
  stability.threads = 2;
  stability.cases = {calibrate::StabilityCaseId::kSite, calibrate::StabilityCaseId::kFlat,
                     calibrate::StabilityCaseId::kRoughest};
  CheckStabilityReport(site, calibrate::RunStabilitySuite(site.scene, stability));

  calibrate::ConvergenceOptions convergence;
  convergence.steps_per_contact = {10, 20};
  convergence.rock_counts = {6, 12};
  convergence.bootstrap = 20;
  convergence.min_values = 3;
  convergence.threads = 2;
  core::Scene scene = site.scene;
  scene.options.max_time = 10.0;
  sites::Site short_site = site;
  short_site.scene = scene;
  CheckConvergenceReport(short_site, calibrate::RunConvergence(scene, convergence));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 20.0) << "keep this test light";
}

// ---- sensitivity -------------------------------------------------------------------

TEST(SensitivityReport, EveryNumberComesFromSensitivityJson) {
  sites::Site site = Example("profile2d");
  site.scene.SetTotalRocks(2);
  site.scene.options.max_time = 15.0;
  site.calibrate.resize(1);  // the talus hardness: one terrain for the whole study
  ASSERT_EQ(site.calibrate[0].name, "hardness");
  for (const auto method :
       {calibrate::SensitivityMethod::kMorris, calibrate::SensitivityMethod::kSobol}) {
    const calibrate::SensitivityResult r = SmallStudy(site, method);
    const Parsed p = ParseReport(SensitivityHtmlReport(Input(site), r));
    ExpectSelfContained(p);
    EXPECT_EQ(p.sections, (std::vector<std::string>{"site", "sensitivity"}));
    const nlohmann::json json = r;
    auto seen = CheckNumbers(p, {{"sensitivity.json", json}});
    std::set<std::string> expected = Expected(json, "/entries/", {"parameter", "output"});
    for (const std::string& leaf : Expected(json, "/outputs/", {"name", "description"}))
      expected.insert(leaf);
    for (const std::string& leaf : Expected(json, "/parameters/", {"label"}))
      if (leaf.find("/material") == std::string::npos && leaf.find("/name") == std::string::npos)
        expected.insert(leaf);
    for (const char* leaf : {"/site", "/summary", "/simulations", "/wall_seconds",
                             "/simulations_per_second", "/seed", "/rocks"})
      expected.insert(leaf);
    for (const std::string& leaf : expected)
      EXPECT_TRUE(seen["sensitivity.json"].count(leaf))
          << "sensitivity.json" << leaf << " not shown";
    // One chart per output, each a well-formed SVG naming every parameter.
    for (std::size_t o = 0; o < r.outputs.size(); ++o) {
      const std::string svg = SensitivitySvg(r, static_cast<int>(o));
      std::string error;
      EXPECT_NE(ParseXml(svg, &error), nullptr) << error;
      EXPECT_NE(p.html.find(svg), std::string::npos) << "chart " << o << " is inline";
      for (const auto& param : r.parameters)
        EXPECT_NE(svg.find(param.label()), std::string::npos) << param.label();
    }
  }
}

}  // namespace
}  // namespace rockcal::reports
