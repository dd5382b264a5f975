#include "rockcal/core/format.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace rockcal::core {
namespace {

TEST(FormatNumber, DefaultIsShortestWithTenDigits) {
  EXPECT_EQ(FormatNumber(12.0), "12");
  EXPECT_EQ(FormatNumber(0.3048), "0.3048");
  EXPECT_EQ(FormatNumber(1e-5), "1e-05");
  EXPECT_EQ(FormatNumber(1.0 / 3.0), "0.3333333333");
}

TEST(FormatNumber, TakesAPrintfConversion) {
  EXPECT_EQ(FormatNumber(2.345, "%.1f"), "2.3");
  EXPECT_EQ(FormatNumber(0.25, "%.3g %%"), "0.25 %");
  EXPECT_EQ(FormatNumber(-1.5, "%.6g"), "-1.5");
}

TEST(FormatNumber, WritesInfinitiesAndNanAsPrintfDoes) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(FormatNumber(inf), "inf");
  EXPECT_EQ(FormatNumber(-inf, "%.3f"), "-inf");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::quiet_NaN()), "nan");
}

TEST(FormatNumber, LongOutputIsNotCut) {
  const std::string s = FormatNumber(1e100, "%.1f");
  EXPECT_EQ(s.size(), 103u) << s;
  EXPECT_EQ(s.substr(s.size() - 2), ".0") << s;
}

TEST(CsvField, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(CsvField("plain text"), "plain text");
  EXPECT_EQ(CsvField(""), "");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvField("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(CsvField("cr\r"), "\"cr\r\"");
}

}  // namespace
}  // namespace rockcal::core
