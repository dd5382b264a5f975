#include "rockcal/sites/json_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "rockcal/sites/input_file.h"
#include "rockcal/sites/text_reader.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

TEST(ReadJsonFile, SyntaxErrorNamesFileLineAndColumn) {
  TempDir dir;
  const std::string path = dir.Write("bad.json", "{\n  \"a\": 1,\n  \"b\": \n}\n");
  const std::string msg = ErrorOf([&] { ReadJsonFile(path); });
  EXPECT_THAT(msg, HasSubstr(path + ":4:"));
  EXPECT_THAT(msg, HasSubstr("invalid JSON"));
}

TEST(ReadJsonFile, MissingFileIsAnInputError) {
  TempDir dir;
  const std::string path = dir.path() + "/absent.json";
  EXPECT_THAT(ErrorOf([&] { ReadJsonFile(path); }), HasSubstr(path + ": cannot open file"));
}

TEST(ReadJsonFile, NumberOverflowNamesFileAndPath) {
  TempDir dir;
  const std::string path = dir.Write("big.json", R"({"rocks": [{"size": [1, 1e400]}]})");
  const std::string msg = ErrorOf([&] { ReadJsonFile(path); });
  EXPECT_THAT(msg, HasSubstr(path + ": $.rocks[0].size[1]"));
  EXPECT_THAT(msg, HasSubstr("number '1e400' out of range"));
  const std::string top = dir.Write("top.json", R"({"a": {"b": -1e999}})");
  EXPECT_THAT(ErrorOf([&] { ReadJsonFile(top); }), HasSubstr(top + ": $.a.b: number '-1e999'"));
}

// 100,000 nested arrays crashed the reader (its stack); the depth is bounded
// before parsing and named.
TEST(ReadJsonFile, DeepNestingIsRefusedNamingTheDepth) {
  TempDir dir;
  const std::string deep =
      dir.Write("deep.json", std::string(100000, '[') + std::string(100000, ']'));
  const std::string msg = ErrorOf([&] { ReadJsonFile(deep); });
  EXPECT_THAT(msg, HasSubstr(deep + ": JSON nested 100000 levels deep"));
  EXPECT_THAT(msg, HasSubstr("at most 64"));
  // The limit itself passes; brackets inside strings do not count.
  const std::string at_limit =
      dir.Write("limit.json", std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']'));
  EXPECT_NO_THROW(ReadJsonFile(at_limit));
  const std::string quoted =
      dir.Write("quoted.json", "{\"a\": \"" + std::string(1000, '[') + "\\\"\"}");
  EXPECT_NO_THROW(ReadJsonFile(quoted));
  EXPECT_EQ(JsonDepth("[[1], {\"a\": [\"]]]\"]}]"), 3);
}

// A FIFO blocked the reader for ever; a folder was "invalid JSON" at 1:1.
TEST(ReadJsonFile, SpecialFilesAndFoldersAreRefusedWithoutOpening) {
  TempDir dir;
  const std::string fifo = dir.path() + "/fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THAT(ErrorOf([&] { ReadJsonFile(fifo); }),
              HasSubstr(fifo + ": is a FIFO (named pipe), expected a regular file"));
  EXPECT_THAT(ErrorOf([&] { LineReader reader(fifo); }), HasSubstr(fifo + ": is a FIFO"));
  EXPECT_THAT(ErrorOf([&] { ReadJsonFile("/dev/null"); }),
              HasSubstr("/dev/null: is a character device"));
  EXPECT_THAT(ErrorOf([&] { ReadJsonFile(dir.path()); }),
              HasSubstr(dir.path() + ": is a folder, expected a file"));
}

TEST(ReadJsonFile, DuplicateKeyNamesFileAndPath) {
  TempDir dir;
  const std::string path =
      dir.Write("dup.json", R"({"rocks": [{"count": 1}, {"count": 2, "count": 3}], "x": 1})");
  const std::string msg = ErrorOf([&] { ReadJsonFile(path); });
  EXPECT_THAT(msg, HasSubstr(path + ": $.rocks[1].count"));
  EXPECT_THAT(msg, HasSubstr("duplicate key 'count'"));
  // The same key in two objects is no duplicate.
  const std::string ok =
      dir.Write("ok.json", R"({"a": {"k": 1}, "b": {"k": 2}, "c": [[{"k": 3}]]})");
  EXPECT_EQ(ReadJsonFile(ok)["c"][0][0]["k"], 3);
}

TEST(JsonNode, KeysRejectsUnknownKeyNamingPathAndAllowed) {
  const nlohmann::json j = nlohmann::json::parse(R"({"a": 1, "colour": 2})");
  const JsonNode node(&j, "site.json", "$.x");
  const std::string msg = ErrorOf([&] { node.Keys({"a", "b"}); });
  EXPECT_THAT(msg, HasSubstr("site.json: $.x.colour"));
  EXPECT_THAT(msg, HasSubstr("unknown key 'colour'"));
  EXPECT_THAT(msg, HasSubstr("allowed keys: a, b"));
}

TEST(JsonNode, GetMissingKeyNamesIt) {
  const nlohmann::json j = nlohmann::json::parse(R"({"a": 1})");
  const JsonNode node(&j, "f.json", "$");
  EXPECT_THAT(ErrorOf([&] { node.Get("b"); }), HasSubstr("f.json: $: missing required key 'b'"));
  EXPECT_TRUE(node.Find("a").has_value());
  EXPECT_FALSE(node.Find("b").has_value());
  EXPECT_EQ(node.Get("a").path(), "$.a");
}

TEST(JsonNode, NumbersCheckTypeAndRange) {
  const nlohmann::json j = nlohmann::json::parse(R"({"s": "x", "n": 1.5, "neg": -1, "i": 2.5})");
  const JsonNode node(&j, "f.json", "$");
  EXPECT_THAT(ErrorOf([&] { node.Get("s").Number(); }),
              HasSubstr("f.json: $.s: expected a number (found \"x\")"));
  EXPECT_DOUBLE_EQ(node.Get("n").Number(0, 2), 1.5);
  EXPECT_THAT(ErrorOf([&] { node.Get("n").Number(0, 1); }),
              HasSubstr("$.n: expected a number in [0, 1] (found 1.5)"));
  EXPECT_THAT(ErrorOf([&] { node.Get("neg").Positive(); }), HasSubstr("expected a number > 0"));
  EXPECT_THAT(ErrorOf([&] { node.Get("neg").NonNegative(); }), HasSubstr("expected a number >= 0"));
  EXPECT_THAT(ErrorOf([&] { node.Get("i").Integer(0, 9); }), HasSubstr("expected a whole number"));
}

// Issue 56: a NUL in a site's name was accepted and written raw into
// report.html. Names, ids and file names hold no control character (the
// message escapes it); a description or a CRS may hold tabs and line breaks.
TEST(JsonNode, StringsHoldNoControlCharacters) {
  const nlohmann::json j = nlohmann::json::parse(
      R"({"nul": "mi\u0000ni", "tab": "a\tb", "del": "x\u007f", "ok": "Col de l'Ours \u00e9"})");
  const JsonNode node(&j, "f.json", "$");
  const std::string nul = ErrorOf([&] { node.Get("nul").String(); });
  EXPECT_THAT(nul, HasSubstr("f.json: $.nul: holds the control character U+0000 at character 3; "
                             "expected printable text"));
  EXPECT_THAT(nul, HasSubstr("(found \"mi\\u0000ni\")"));
  EXPECT_EQ(nul.find('\0'), std::string::npos) << "the message holds no NUL itself";
  EXPECT_THAT(ErrorOf([&] { node.Get("tab").String(); }),
              HasSubstr("$.tab: holds the control character U+0009 at character 2"));
  EXPECT_THAT(ErrorOf([&] { node.Get("del").String(); }),
              HasSubstr("$.del: holds the control character U+007F at character 2"));
  EXPECT_EQ(node.Get("ok").String(), "Col de l'Ours \xc3\xa9");
  EXPECT_EQ(node.Get("tab").Text(), "a\tb");
  EXPECT_THAT(ErrorOf([&] { node.Get("nul").Text(); }), HasSubstr("U+0000"));
}

TEST(JsonNode, ArraysNameTheirElements) {
  const nlohmann::json j = nlohmann::json::parse(R"({"p": [[1, 2], [3, "y"]]})");
  const JsonNode node(&j, "f.json", "$");
  const std::vector<JsonNode> items = node.Get("p").Array(2);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[1].path(), "$.p[1]");
  EXPECT_EQ(items[0].Numbers(2), (std::vector<double>{1, 2}));
  EXPECT_THAT(ErrorOf([&] { items[1].Numbers(2); }), HasSubstr("$.p[1][1]: expected a number"));
  EXPECT_THAT(ErrorOf([&] { items[0].Numbers(3); }), HasSubstr("expected an array of 3 numbers"));
  EXPECT_THAT(ErrorOf([&] { node.Get("p").Array(3); }),
              HasSubstr("expected an array of at least 3 entries"));
}

TEST(Units, ReadAndConvert) {
  const nlohmann::json j = nlohmann::json::parse(R"({"a": "us", "b": "si", "c": "metric"})");
  const JsonNode node(&j, "f.json", "$");
  EXPECT_EQ(ReadUnits(node.Get("a")), Units::kUS);
  EXPECT_EQ(ReadUnits(node.Get("b")), Units::kSI);
  EXPECT_THAT(ErrorOf([&] { ReadUnits(node.Get("c")); }),
              HasSubstr("$.c: unknown units (allowed: us, si)"));
  EXPECT_DOUBLE_EQ(LengthToSI(12.0, Units::kUS), 3.6576);
  EXPECT_DOUBLE_EQ(LengthToSI(12.0, Units::kSI), 12.0);
  // 165 lbf/ft^3 is about 25.92 kN/m^3.
  EXPECT_NEAR(UnitWeightToSI(165.0, Units::kUS), 25919.43, 0.01);
  EXPECT_DOUBLE_EQ(UnitWeightToSI(26.0, Units::kSI), 26000.0);
}

TEST(FormatNumber, ShortAndExact) {
  EXPECT_EQ(FormatNumber(12.0), "12");
  EXPECT_EQ(FormatNumber(0.3048), "0.3048");
  EXPECT_EQ(FormatNumber(-2.5), "-2.5");
}

}  // namespace
}  // namespace rockcal::sites
