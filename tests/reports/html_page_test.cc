// The page of the HTML reports: numbers as shown and as marked for machines,
// the document skeleton, and the site tables that need only the scene.
#include "rockcal/reports/html_page.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "report_check.h"
#include "rockcal/sites/site.h"
#include "xml_check.h"

namespace rockcal::reports::html {
namespace {

using testing::ExpectSelfContained;
using testing::FindSection;
using testing::Parsed;
using testing::ParseReport;
using testing::ParseXml;
using testing::Unescape;

TEST(HtmlPageTest, NumbersAreShownWithThreeDigitsAndMarkedExactly) {
  EXPECT_EQ(Show(1234.4), "1234");
  EXPECT_EQ(Show(56.71), "56.7");
  EXPECT_EQ(Show(8.9), "8.90");
  EXPECT_EQ(Show(0.012345), "0.0123");
  EXPECT_EQ(Show(0.0), "0");
  EXPECT_EQ(Show(std::nan("")), "-");
  EXPECT_EQ(ShowPercent(0.02354), "2.35 %");
  EXPECT_EQ(ShowPercent(0.000412), "0.0412 %");
  EXPECT_EQ(Percent(0.125), "12.5 %");
  EXPECT_EQ(Exact(0.1 + 0.2), "0.3");
  EXPECT_EQ(Exact(1.0 / 3.0), "0.3333333333");
  EXPECT_EQ(Ref("a.json", "/b/0"), "a.json#/b/0");
  EXPECT_EQ(RefCell("a.json#/x", 2.0 / 3.0, "0.667"),
            "<td class=\"n\" data-json=\"a.json#/x\" data-value=\"0.6666666667\">0.667</td>");
  EXPECT_EQ(RefSpan("a.json#/x", 5, "5"),
            "<span data-json=\"a.json#/x\" data-value=\"5\">5</span>");
  EXPECT_EQ(RefText("a.json#/name", "A & <B>"),
            "<span data-json=\"a.json#/name\" data-value=\"A &amp; &lt;B&gt;\">A &amp; "
            "&lt;B&gt;</span>");
  EXPECT_EQ(Td("1 < 2", true), "<td class=\"n\">1 &lt; 2</td>");
  // In the site's units: SI alone, or SI with US beside.
  EXPECT_EQ(Length(3.048, sites::Units::kUS), "3.05 m (10.0 ft)");
  EXPECT_EQ(Length(3.048, sites::Units::kSI), "3.05 m");
  EXPECT_EQ(Energy(500e3, sites::Units::kSI), "500 kJ");
  EXPECT_EQ(Energy(10.0 * kFtTon, sites::Units::kUS), "27.1 kJ (10.0 ft-tons)");
  EXPECT_EQ(Speed(3.048, sites::Units::kUS), "3.05 m/s (10.0 ft/s)");
  // A coordinate rounded one way, never converted for an SI site.
  EXPECT_EQ(CoordinateNumber(6671517.5), "6671517.5");
  EXPECT_EQ(CoordinateNumber(6671517.96), "6671518.0");
  EXPECT_EQ(CoordinateNumber(12.25), "12.25");
  EXPECT_EQ(Coordinate(888630.0, sites::Units::kSI), "888630.0 m");
  EXPECT_EQ(Coordinate(121.92, sites::Units::kUS), "121.9 m (400 ft)");
}

TEST(HtmlPageTest, PageIsSelfContainedWithNumberedSections) {
  Page page;
  page.title = "a <title>";
  page.heading_html = "Heading <span>x</span>";
  page.lead_html = "Lead &amp; more";
  page.sections = {{"one", "First & only", "", "<p>body</p>"},
                   {"two", "Second", "Second <em>styled</em>", "<p>more</p>"}};
  page.footer_html = "foot";
  const Parsed p = ParseReport(PageHtml(page));
  ExpectSelfContained(p);
  EXPECT_EQ(p.sections, (std::vector<std::string>{"one", "two"}));
  EXPECT_NE(p.html.find("<h2>1. First &amp; only</h2>\n<p>body</p>"), std::string::npos);
  EXPECT_EQ(Unescape(FindSection(p, "one")->AllText()), "\n1. First & only\nbody\n")
      << "text in document order";
  EXPECT_NE(p.html.find("<h2>2. Second <em>styled</em></h2>"), std::string::npos);
  EXPECT_NE(p.html.find("<title>a &lt;title&gt;</title>"), std::string::npos);
  EXPECT_NE(p.html.find("<a href=\"#two\">Second</a>"), std::string::npos);
  EXPECT_EQ(p.html.find("<p class=\"note\">"), std::string::npos) << "no note given";
  EXPECT_NE(p.html.find("@media print"), std::string::npos);
  page.note_html = "a note";
  EXPECT_NE(PageHtml(page).find("<p class=\"note\">a note</p>"), std::string::npos);
}

// The site tables, with and without the rocks passed per partition.
TEST(HtmlPageTest, SiteTablesNeedOnlyTheScene) {
  const sites::Site site =
      sites::LoadSite(std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial/site.json");
  std::string error;
  const std::string plain = "<div>" + SiteTables(site.scene, site.path, site.units) + "</div>";
  const auto root = ParseXml(plain, &error);
  ASSERT_NE(root, nullptr) << error;
  const std::string text = Unescape(root->AllText());
  EXPECT_NE(text.find(site.scene.name), std::string::npos);
  EXPECT_NE(text.find("US (ft, lbf/ft"), std::string::npos);
  for (const auto& m : site.scene.materials) EXPECT_NE(text.find(m.id), std::string::npos);
  EXPECT_NE(text.find("BP-1"), std::string::npos);
  EXPECT_EQ(text.find("rocks passed"), std::string::npos);
  EXPECT_EQ(plain.find("href"), std::string::npos) << "no partition sections to link to";

  PartitionPassage passage;
  passage.passed = {3, 4};
  passage.rocks = 4;
  const std::string linked =
      "<div>" + SiteTables(site.scene, site.path, site.units, &passage) + "</div>";
  ASSERT_NE(ParseXml(linked, &error), nullptr) << error;
  EXPECT_NE(linked.find("rocks passed"), std::string::npos);
  EXPECT_NE(linked.find("<a href=\"#partition-BP-1\">BP-1</a>"), std::string::npos);
  EXPECT_NE(linked.find("3 (75.0 %)"), std::string::npos);

  EXPECT_EQ(SiteNotes({}), "");
  EXPECT_EQ(SiteNotes({"a < b"}),
            "<h3>What the site reader did</h3><ul class=\"notes\"><li>a &lt; b</li></ul>");
}

}  // namespace
}  // namespace rockcal::reports::html
