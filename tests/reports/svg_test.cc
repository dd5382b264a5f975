#include "rockcal/reports/svg.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "xml_check.h"

namespace rockcal::reports::svg {
namespace {

TEST(SvgTest, EscapesXmlCharacters) {
  EXPECT_EQ(Escape("a < b & c > \"d\" 'e'"), "a &lt; b &amp; c &gt; &quot;d&quot; &#39;e&#39;");
}

TEST(SvgTest, NumbersAreShortAndWithoutExponents) {
  EXPECT_EQ(Px(12.34), "12.3");
  EXPECT_EQ(Px(4.0), "4");
  EXPECT_EQ(Px(-0.01), "0");
  EXPECT_EQ(Px(1234.5), "1234.5");
  EXPECT_EQ(Label(0.0), "0");
  EXPECT_EQ(Label(2.5), "2.5");
  EXPECT_EQ(Label(12000.0), "12000");
  EXPECT_EQ(Label(0.00125), "0.00125");
  EXPECT_EQ(Label(1e-7), "1e-07");
}

TEST(SvgTest, TicksAreNiceAndInsideTheRange) {
  const std::vector<double> t = Ticks(0.3, 9.7, 5);
  ASSERT_FALSE(t.empty());
  for (double v : t) {
    EXPECT_GE(v, 0.3);
    EXPECT_LE(v, 9.7);
    EXPECT_NEAR(std::remainder(v, 2.0), 0.0, 1e-12) << v;  // step 2 for a span of 9.4 in 5
  }
  EXPECT_EQ(Ticks(-1.0, 1.0, 4), (std::vector<double>{-1.0, -0.5, 0.0, 0.5, 1.0}));
  EXPECT_DOUBLE_EQ(NiceStep(100.0, 5), 20.0);
  EXPECT_DOUBLE_EQ(NiceStep(7.0, 10), 0.5);
  EXPECT_EQ(LogTicks(0.5, 2000.0), (std::vector<double>{1.0, 10.0, 100.0, 1000.0}));
  EXPECT_EQ(LogTicks(3.0, 40.0), (std::vector<double>{5.0, 10.0, 20.0}));
}

TEST(SvgTest, PlotMapsDataAndIsWellFormed) {
  Plot::Options o;
  o.width = 200, o.height = 100, o.left = 20, o.right = 10, o.top = 10, o.bottom = 20;
  o.title = "t & <u>";
  Plot plot(0.0, 10.0, 0.0, 5.0, o);
  EXPECT_DOUBLE_EQ(plot.X(0.0), 20.0);
  EXPECT_DOUBLE_EQ(plot.X(10.0), 190.0);
  EXPECT_DOUBLE_EQ(plot.Y(0.0), 80.0);
  EXPECT_DOUBLE_EQ(plot.Y(5.0), 10.0);
  plot.Axes("x [m] & more", "y");
  plot.TopAxis(1 / 0.3048, "x [ft]");
  plot.RightAxis(2.0, "y2");
  plot.Bars({0, 2, 4}, {1, 3}, "#123456");
  plot.Polyline({0, 1, NAN, 3, 4}, {1, 2, 3, 4, 5}, "stroke=\"#000\"");
  plot.Steps({0, 1, 2}, {3, 2, 1}, "stroke=\"#f00\"");
  plot.Points({1, 2, 50}, {1, 2, 1}, 2, "fill=\"#0f0\"");
  plot.VLine(5, "stroke=\"#00f\"", "fence <3 m>");
  plot.HLine(2, "stroke=\"#00f\"", "z");
  plot.Legend({{"#000", "a", "line"}, {"#f00", "b", "point"}});
  const std::string svg = plot.Svg();
  std::string error;
  const auto root = testing::ParseXml(svg, &error);
  ASSERT_NE(root, nullptr) << error;
  EXPECT_EQ(root->name, "svg");
  int polylines = 0, circles = 0;
  root->Visit([&](const testing::XmlNode& n) {
    polylines += n.name == "polyline";
    circles += n.name == "circle";
  });
  EXPECT_EQ(polylines, 3) << "the NaN splits the first line in two, plus the step line";
  EXPECT_EQ(circles, 3) << "two points inside the plot and one legend marker";
  EXPECT_NE(svg.find("fence &lt;3 m&gt;"), std::string::npos);
}

TEST(SvgTest, CategoryTicksReplaceTheNumbersOnX) {
  Plot::Options o;
  o.x_ticks = {{1.0, "slope.hardness"}, {2.0, "a & <b>"}};
  Plot plot(0.5, 2.5, 0.0, 1.0, o);
  plot.Axes("parameter", "index");
  const std::string svg = plot.Svg();
  std::string error;
  ASSERT_NE(testing::ParseXml(svg, &error), nullptr) << error;
  EXPECT_NE(svg.find(">slope.hardness</text>"), std::string::npos);
  EXPECT_NE(svg.find(">a &amp; &lt;b&gt;</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">1.5</text>"), std::string::npos) << "no numeric x ticks";
  EXPECT_NE(svg.find(">0</text>"), std::string::npos) << "the y ticks stay";
}

TEST(SvgTest, LogPlotWidensBadRanges) {
  Plot::Options o;
  o.log_y = true;
  Plot plot(0.0, 1.0, 0.0, 100.0, o);
  EXPECT_GT(plot.ylo(), 0.0);
  EXPECT_TRUE(std::isfinite(plot.Y(1e-9)));
  EXPECT_NEAR(plot.Y(100.0), plot.top(), 1e-9);
}

TEST(SvgTest, LogLogPlotMapsDecadesEvenlyAndSkipsNonPositivePoints) {
  Plot::Options o;
  o.width = 200, o.height = 100, o.left = 20, o.right = 10, o.top = 10, o.bottom = 20;
  o.log_x = o.log_y = true;
  Plot plot(0.1, 10.0, 1.0, 100.0, o);
  EXPECT_DOUBLE_EQ(plot.X(0.1), 20.0);
  EXPECT_DOUBLE_EQ(plot.X(1.0), 105.0);
  EXPECT_DOUBLE_EQ(plot.X(10.0), 190.0);
  EXPECT_DOUBLE_EQ(plot.Y(10.0), 45.0);
  plot.Axes("t [s]", "error [%]");
  plot.TopAxis(2.0, "not on a log axis");
  plot.Polyline({0.2, 0.0, 1.0, 2.0}, {5.0, 5.0, 20.0, 30.0}, "stroke=\"#000\"");
  plot.Points({0.2, -1.0, 1.0}, {5.0, 5.0, 20.0}, 2, "fill=\"#0f0\"");
  const std::string svg = plot.Svg();
  std::string error;
  const auto root = testing::ParseXml(svg, &error);
  ASSERT_NE(root, nullptr) << error;
  int polylines = 0, circles = 0;
  std::vector<std::string> labels;
  root->Visit([&](const testing::XmlNode& n) {
    polylines += n.name == "polyline";
    circles += n.name == "circle";
    if (n.name == "text") labels.push_back(n.AllText());
  });
  EXPECT_EQ(polylines, 1) << "x = 0 breaks the line; a single point is no line";
  EXPECT_EQ(circles, 2) << "x = -1 is not drawn";
  for (const char* tick : {"0.1", "1", "10", "100"})
    EXPECT_NE(std::find(labels.begin(), labels.end(), tick), labels.end()) << tick;
  EXPECT_EQ(svg.find("not on a log axis"), std::string::npos);
  // A bad lower bound is replaced, as on a log y axis.
  Plot bad(0.0, 10.0, 1.0, 10.0, o);
  EXPECT_GT(bad.xlo(), 0.0);
  EXPECT_TRUE(std::isfinite(bad.X(1e-9)));
}

}  // namespace
}  // namespace rockcal::reports::svg
