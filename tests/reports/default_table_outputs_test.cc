#include "rockcal/reports/default_table_outputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "../calibrate/default_table_fixture.h"

namespace rockcal::reports {
namespace {

using calibrate::CalibratedParameter;
using calibrate::CalibratedSite;
using calibrate::DefaultTable;
using ::testing::HasSubstr;
using ::testing::Not;

using calibrate::testing::P;

// Two sites: talus hardness 0.3 and 0.5, talus roughness 0.2 m and 0.5 m (at
// its upper bound), soil contact time 6 ms with a standard error of 0.5 ms.
DefaultTable Table(bool include_at_bound = false) {
  CalibratedSite a;
  a.site = "Site A";
  a.result_dir = "out/a";
  a.file = "out/a/parameters.json";
  a.stage = calibrate::Stage{calibrate::Method::kBobyqa};
  a.grid_spacing_m = 1.0;
  a.parameters = {P("talus", "talus", "hardness", 0.3, 0.1, 0.7),
                  P("talus", "talus", "roughness", 0.2, 0.05, 0.5)};
  CalibratedSite b = a;
  b.site = "Site B";
  b.result_dir = "out/b,c";  // a comma the CSV must quote
  b.file = "out/b,c/parameters.json";
  b.stage = calibrate::Stage{calibrate::Method::kCeres};
  b.parameters = {P("red", "talus", "hardness", 0.5, 0.1, 0.8),
                  P("red", "talus", "roughness", 0.5, 0.05, 0.5),
                  P("blue", "soil", "contact_time", 0.006, 0.002, 0.01)};
  b.parameters[2].std_error = 0.0005;
  calibrate::DefaultTableOptions options;
  options.include_at_bound = include_at_bound;
  return calibrate::BuildDefaultTable({a, b}, options);
}

TEST(DefaultTableJson, RowsStatisticsAndEntries) {
  const nlohmann::json j = DefaultTableJson(Table());
  EXPECT_EQ(j["bound_fraction"], 0.01);
  EXPECT_EQ(j["include_at_bound"], false);
  ASSERT_EQ(j["result_folders"].size(), 2u);
  EXPECT_EQ(j["result_folders"][1]["folder"], "out/b,c");
  EXPECT_EQ(j["result_folders"][1]["site"], "Site B");
  EXPECT_EQ(j["result_folders"][0]["grid_spacing_m"], 1.0);
  const nlohmann::json& rows = j["rows"];
  ASSERT_EQ(rows.size(), 3u);
  // soil contact time, talus hardness, talus roughness.
  EXPECT_EQ(rows[0]["class"], "soil");
  EXPECT_EQ(rows[0]["parameter"], "contact_time");
  EXPECT_EQ(rows[0]["unit"], "s");
  EXPECT_EQ(rows[0]["entries"][0]["std_error"], 0.0005);
  const nlohmann::json& h = rows[1];
  EXPECT_EQ(h["parameter"], "hardness");
  EXPECT_EQ(h["sites"], 2);
  EXPECT_EQ(h["values"], 2);
  EXPECT_DOUBLE_EQ(h["median"].get<double>(), 0.4);
  EXPECT_DOUBLE_EQ(h["min"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(h["max"].get<double>(), 0.5);
  EXPECT_EQ(h["at_bound"], 0);
  EXPECT_TRUE(h["entries"][0]["std_error"].is_null());
  EXPECT_TRUE(h["entries"][0]["at_bound"].is_null());
  EXPECT_EQ(h["entries"][1]["material"], "red");
  EXPECT_EQ(h["entries"][1]["folder"], "out/b,c");
  const nlohmann::json& r = rows[2];
  EXPECT_EQ(r["unit"], "m");
  EXPECT_EQ(r["values"], 1);
  EXPECT_DOUBLE_EQ(r["median"].get<double>(), 0.2);
  EXPECT_EQ(r["at_bound"], 1);
  EXPECT_EQ(r["all"]["values"], 2);
  EXPECT_DOUBLE_EQ(r["all"]["median"].get<double>(), 0.35);
  EXPECT_EQ(r["entries"][1]["at_bound"], "upper");
  EXPECT_EQ(r["entries"][1]["counted"], false);
  EXPECT_FALSE(j["notes"].empty());
}

TEST(DefaultTableCsv, OneRowPerClassAndParameter) {
  std::istringstream in(DefaultTableCsv(Table()));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0],
            "class,parameter,unit,sites,values,median,min,max,at_bound,"
            "sites_all,values_all,median_all,min_all,max_all");
  EXPECT_EQ(lines[1], "soil,contact_time,s,1,1,0.006,0.006,0.006,0,1,1,0.006,0.006,0.006");
  EXPECT_EQ(lines[2], "talus,hardness,,2,2,0.4,0.3,0.5,0,2,2,0.4,0.3,0.5");
  EXPECT_EQ(lines[3], "talus,roughness,m,1,1,0.2,0.2,0.2,1,2,2,0.35,0.2,0.5");
}

TEST(DefaultTableValuesCsv, OneRowPerValueWithItsFolderQuoted) {
  const std::string csv = DefaultTableValuesCsv(Table());
  EXPECT_THAT(csv, HasSubstr("class,parameter,unit,site,folder,material,value,pooled,lower,upper,"
                             "std_error,at_bound,counted\n"));
  EXPECT_THAT(csv, HasSubstr("soil,contact_time,s,Site B,\"out/b,c\",blue,0.006,0.006,0.002,0.01,"
                             "0.0005,,1\n"));
  EXPECT_THAT(csv,
              HasSubstr("talus,roughness,m,Site B,\"out/b,c\",red,0.5,0.5,0.05,0.5,,upper,0\n"));
}

TEST(DefaultTableMarkdown, ATableToPasteWithFeet) {
  const std::string md = DefaultTableMarkdown(Table());
  EXPECT_THAT(md, HasSubstr("| class | parameter | sites | values | median | min – max | at a "
                            "bound |\n|---|---|---|---|---|---|---|\n"));
  EXPECT_THAT(md, HasSubstr("| talus | hardness | 2 | 2 | 0.4 | 0.3 – 0.5 | 0 of 2 |"));
  // 0.2 m = 0.656 ft.
  EXPECT_THAT(md, HasSubstr("| talus | roughness | 1 | 1 | 0.2 m (0.656 ft) | 0.2 – 0.2 m "
                            "(0.656 – 0.656 ft) | 1 of 2 |"));
  EXPECT_THAT(md, HasSubstr("| soil | contact time | 1 | 1 | 6 ms | 6 – 6 ms | 0 of 1 |"));
  // The statistics with the value at a bound: 0.2 and 0.5 m (1.64 ft).
  EXPECT_THAT(md, HasSubstr("### With the values at a bound"));
  EXPECT_THAT(md, HasSubstr("| talus | roughness | 2 | 2 | 0.35 m (1.15 ft) | 0.2 – 0.5 m "
                            "(0.656 – 1.64 ft) | 1 of 2 |"));
  EXPECT_THAT(md, HasSubstr("are left out (--include-at-bound counts them)"));
  EXPECT_THAT(md, HasSubstr("| talus | roughness | Site B | out/b,c | red | 0.5 m (1.64 ft) | - | "
                            "[0.05, 0.5] m | upper, left out |"));
  EXPECT_THAT(md, HasSubstr("| soil | contact time | Site B | out/b,c | blue | 6 ms | 0.5 ms | "
                            "[2, 10] ms |  |"));
  EXPECT_THAT(md, HasSubstr("### Result folders\n\n| folder | site | method | evaluations | "
                            "misfit | sphere spacing |\n|---|---|---|---|---|---|\n"
                            "| out/a | Site A | nlopt:bobyqa | 0 | 0 | 1 m |\n"));
  EXPECT_THAT(md, HasSubstr("### Notes\n\n- talus roughness: Site B (out/b,c, material red) is "
                            "at its upper bound"));
}

TEST(DefaultTableMarkdown, APosteriorMedianIsPooledAndShownBesideTheSearchValue) {
  CalibratedSite a;
  a.site = "Site A";
  a.result_dir = "out/a";
  a.file = "out/a/parameters.json";
  a.stage = calibrate::Stage{calibrate::Method::kBobyqa};
  a.parameters = {P("talus", "talus", "hardness", 0.3, 0.1, 0.7)};
  a.parameters[0].posterior = CalibratedParameter::Interval{0.42, 0.35, 0.5, true};
  const DefaultTable t = calibrate::BuildDefaultTable({a}, {});
  const std::string md = DefaultTableMarkdown(t);
  EXPECT_THAT(md,
              HasSubstr("| talus | hardness | 1 | 1 | 0.42 | 0.42 – 0.42 | 0.35 – 0.5 | 0 of 1 |"));
  EXPECT_THAT(md, HasSubstr("enters with its posterior median"));
  EXPECT_THAT(md, HasSubstr("| search value | std. error | posterior 5 % – 95 % | pooled |"));
  EXPECT_THAT(md, HasSubstr("| talus | hardness | Site A | out/a | talus | 0.3 | - | 0.35 – 0.5 | "
                            "0.42 | [0.1, 0.7] |  |"));
  const nlohmann::json j = DefaultTableJson(t);
  EXPECT_DOUBLE_EQ(j["rows"][0]["median"].get<double>(), 0.42);
  EXPECT_DOUBLE_EQ(j["rows"][0]["entries"][0]["value"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(j["rows"][0]["entries"][0]["pooled"].get<double>(), 0.42);
  EXPECT_THAT(
      DefaultTableValuesCsv(t),
      HasSubstr("talus,hardness,,Site A,out/a,talus,0.3,0.42,0.1,0.7,,,1,0.42,0.35,0.5,yes\n"));
}

TEST(DefaultTableMarkdown, IncludeAtBoundHasOneSummary) {
  const std::string md = DefaultTableMarkdown(Table(true));
  EXPECT_THAT(md, Not(HasSubstr("### With the values at a bound")));
  EXPECT_THAT(md, HasSubstr("| talus | roughness | 2 | 2 | 0.35 m (1.15 ft) |"));
  EXPECT_THAT(md, HasSubstr("are counted (--include-at-bound)"));
  EXPECT_THAT(md, HasSubstr("| upper |"));
}

}  // namespace
}  // namespace rockcal::reports
