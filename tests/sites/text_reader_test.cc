#include "rockcal/sites/text_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_files.h"

namespace rockcal::sites {
namespace {

using ::testing::ElementsAre;
using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

TEST(ParseNumber, AcceptsDecimals) {
  double v = 0;
  ASSERT_TRUE(ParseNumber("12", &v));
  EXPECT_EQ(v, 12.0);
  ASSERT_TRUE(ParseNumber(" -1.5e2 ", &v));
  EXPECT_EQ(v, -150.0);
  ASSERT_TRUE(ParseNumber("+.5", &v));
  EXPECT_EQ(v, 0.5);
  ASSERT_TRUE(ParseNumber("3.", &v));
  EXPECT_EQ(v, 3.0);
}

TEST(ParseNumber, RejectsEverythingElse) {
  double v = 7;
  for (const char* bad : {"", " ", "x", "1x", "nan", "NaN", "inf", "-Infinity", "1e999", "0x10",
                          "1e", ".", "-", "1 2", "1,5"}) {
    EXPECT_FALSE(ParseNumber(bad, &v)) << "accepted '" << bad << "'";
  }
  EXPECT_EQ(v, 7);
}

TEST(SplitFields, CommasOrBlanks) {
  EXPECT_THAT(SplitFields("1 2\t3"), ElementsAre("1", "2", "3"));
  EXPECT_THAT(SplitFields("  1   2  "), ElementsAre("1", "2"));
  EXPECT_THAT(SplitFields("1, 2 ,3\r"), ElementsAre("1", "2", "3"));
  EXPECT_THAT(SplitFields("1,,3"), ElementsAre("1", "", "3"));
  EXPECT_TRUE(SplitFields("   ").empty());
  EXPECT_TRUE(IsBlank(" \t\r"));
  EXPECT_FALSE(IsBlank(" a"));
}

TEST(LineReader, CountsLinesAndNamesBadFields) {
  TempDir dir;
  const std::string path = dir.Write("a.txt", "first\r\nsecond\n1,,3\n4 y 6\n");
  LineReader r(path);
  std::string line;
  ASSERT_TRUE(r.Next(&line));
  EXPECT_EQ(line, "first");
  EXPECT_EQ(r.where(), path + ":1");
  ASSERT_TRUE(r.Next(&line));
  ASSERT_TRUE(r.Next(&line));
  EXPECT_THAT(ErrorOf([&] { r.Numbers(SplitFields(line)); }),
              HasSubstr(path + ":3: value 2 is missing"));
  ASSERT_TRUE(r.Next(&line));
  EXPECT_THAT(ErrorOf([&] { r.Numbers(SplitFields(line)); }),
              HasSubstr(path + ":4: value 2 'y' is not a finite number"));
  EXPECT_FALSE(r.Next(&line));
}

// Issue 14: messages quoted whole lines of other files, control bytes and all.
TEST(Excerpt, ShortPrintableAndEscaped) {
  EXPECT_EQ(Excerpt("abc"), "'abc'");
  // Issue 56: a quote in the text doubled the closing one ('foo'').
  EXPECT_EQ(Excerpt("foo'"), "'foo\\x27'");
  EXPECT_EQ(Excerpt(std::string("a\0b\x1b[2J\n", 8)), "'a\\x00b\\x1B[2J\\x0A'");
  const std::string excerpt = Excerpt(std::string(5000, 'x'));
  EXPECT_EQ(excerpt, "'" + std::string(kMaxExcerpt, 'x') + "...'");
}

TEST(LineReader, QuotesAtMostAnExcerptAndCapsTheLineLength) {
  TempDir dir;
  const std::string path = dir.Write("b.txt", "1 " + std::string(10000, 'y') + "\x07 3\n" +
                                                  std::string(kMaxLineBytes + 1, '7') + "\n");
  LineReader r(path);
  std::string line;
  ASSERT_TRUE(r.Next(&line));
  const std::string msg = ErrorOf([&] { r.Numbers(SplitFields(line)); });
  EXPECT_THAT(msg, HasSubstr(path + ":1: value 2 'yyy"));
  EXPECT_LT(msg.size(), path.size() + 150) << msg;
  EXPECT_THAT(ErrorOf([&] { r.Next(&line); }),
              HasSubstr(path + ":2: line 2 longer than 1048576 bytes"));
}

TEST(LineReader, MissingFile) {
  TempDir dir;
  const std::string path = dir.path() + "/none.txt";
  EXPECT_THAT(ErrorOf([&] { LineReader r(path); }), HasSubstr(path + ": cannot open file"));
}

}  // namespace
}  // namespace rockcal::sites
