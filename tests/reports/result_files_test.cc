// The files of the studies and of a score: the CSV tables, and each
// command's files written together. A result read back from its JSON file
// (from_json) writes the same CSV and report.html: every value they show
// comes from a field the JSON file holds.
#include "rockcal/reports/result_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "hand_results.h"
#include "rockcal/reports/reach_report.h"

namespace rockcal::reports {
namespace result_files_test {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::Case;
using testing::Example;
using testing::HandCases;
using testing::HandConvergence;
using testing::HandReach;
using testing::Input;
using testing::SmallStudy;
using testing::Study;

long Lines(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh folder for one test.
std::string Folder() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir = ::testing::TempDir() + "/rockcal_result_files_" + info->name() + "_" +
                          std::to_string(::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The result of type Result read from `folder`/`file` (its from_json).
template <typename Result>
Result ReadBack(const std::string& folder, const std::string& file) {
  return nlohmann::json::parse(Read(folder + "/" + file)).get<Result>();
}

TEST(ResultFiles, StabilityCsvHasOneRowPerCase) {
  const sites::Site site = Example("profile2d");
  calibrate::StabilityStudy study =
      Study(site, {}, {Case("site", true), Case("hardness_1", false)});
  study.cases[0].figures.rocks = 3;
  study.cases[1].reason = "1 rocks tunneled";
  study.cases[1].warning = "overlap, \"deep\"";
  std::istringstream lines(StabilityCsv(study));
  std::string header, row1, row2;
  std::getline(lines, header);
  std::getline(lines, row1);
  std::getline(lines, row2);
  EXPECT_EQ(header.rfind("case,rocks,max_time_s,dt_min_s,dt_max_s,", 0), 0u) << header;
  EXPECT_EQ(row1.rfind("site,3,", 0), 0u) << row1;
  EXPECT_NE(row2.find(",FAIL,1 rocks tunneled,\"overlap, \"\"deep\"\"\""), std::string::npos)
      << row2;
}

TEST(ResultFiles, ConvergenceAndReachCsvHaveOneRowPerQuantity) {
  const calibrate::ConvergenceResult r = HandConvergence(true);
  EXPECT_EQ(Lines(ConvergenceCsv(r)),
            static_cast<long>(1 + r.rows.size() * (r.quantities.size() + 1)));
  const calibrate::ReachResult reach = HandReach();
  const std::string csv = ReachCsv(reach);
  EXPECT_EQ(Lines(csv), static_cast<long>(reach.statistics.size() + 1));
  EXPECT_THAT(csv, HasSubstr("runout distance p50,runout distance,p50,"));
  EXPECT_THAT(csv, HasSubstr("passing[0] <P&1> fraction,passing[0] <P&1>,fraction,0.3,0.05,,,"));
}

TEST(ResultFiles, StabilityFilesReadBackAsTheStudy) {
  const sites::Site site = Example("profile2d");
  const std::string dir = Folder();
  const calibrate::StabilityStudy study = Study(site, {}, HandCases());
  WriteStabilityFiles(dir, Input(site), study);
  calibrate::StabilityStudy back = ReadBack<calibrate::StabilityStudy>(dir, "stability.json");
  back.seed = study.seed;  // the footer's, not in the file
  EXPECT_EQ(Read(dir + "/stability.json"), JsonText(back));
  EXPECT_EQ(Read(dir + "/stability.csv"), StabilityCsv(back));
  EXPECT_EQ(Read(dir + "/report.html"), StabilityHtmlReport(Input(site), back));
  fs::remove_all(dir);
}

TEST(ResultFiles, ConvergenceFilesReadBackAsTheResult) {
  const sites::Site site = Example("profile2d");
  const std::string dir = Folder();
  WriteConvergenceFiles(dir, Input(site), HandConvergence(true));
  const auto back = ReadBack<calibrate::ConvergenceResult>(dir, "convergence.json");
  EXPECT_EQ(Read(dir + "/convergence.json"), JsonText(back));
  EXPECT_EQ(Read(dir + "/convergence.csv"), ConvergenceCsv(back));
  EXPECT_EQ(Read(dir + "/convergence.svg"), ConvergenceSvg(back));
  EXPECT_EQ(Read(dir + "/report.html"), ConvergenceHtmlReport(Input(site), back));
  fs::remove_all(dir);
}

TEST(ResultFiles, SensitivityFilesReadBackAsTheResult) {
  sites::Site site = Example("profile2d");
  site.scene.SetTotalRocks(2);
  site.scene.options.max_time = 15.0;
  site.calibrate.resize(1);
  const std::string dir = Folder();
  for (const auto method :
       {calibrate::SensitivityMethod::kMorris, calibrate::SensitivityMethod::kSobol}) {
    const calibrate::SensitivityResult r = SmallStudy(site, method);
    WriteSensitivityFiles(dir, Input(site), r);
    const auto back = ReadBack<calibrate::SensitivityResult>(dir, "sensitivity.json");
    EXPECT_EQ(Read(dir + "/sensitivity.json"), JsonText(back));
    EXPECT_EQ(Read(dir + "/sensitivity.csv"), SensitivityCsv(back));
    EXPECT_EQ(Lines(SensitivityCsv(back)),
              static_cast<long>(1 + r.parameters.size() * r.outputs.size()));
    EXPECT_EQ(Read(dir + "/report.html"), SensitivityHtmlReport(Input(site), back));
  }
  fs::remove_all(dir);
}

TEST(ResultFiles, ReachFilesReadBackAsTheResult) {
  const sites::Site site = Example("profile2d");
  const std::string dir = Folder();
  WriteReachFiles(dir, Input(site), HandReach());
  const auto back = ReadBack<calibrate::ReachResult>(dir, "reach.json");
  EXPECT_EQ(Read(dir + "/reach.json"), JsonText(back));
  EXPECT_EQ(Read(dir + "/reach.csv"), ReachCsv(back));
  EXPECT_EQ(Read(dir + "/report.html"), ReachHtmlReport(Input(site), back));
  fs::remove_all(dir);
}

TEST(ResultFiles, ScoreFileReadsBackAsTheScore) {
  calibrate::ScoreResult score;
  score.site = "profile2d";
  score.observations_file = "observations.json";
  score.rocks = 40;
  score.seed = 1;
  score.stopped = 39, score.timeout = 1;
  score.misfit.value = 8.25;
  score.misfit.residuals.resize(1);
  score.misfit.residuals[0].id =
      observations::ResidualId::Of(observations::ObservationKind::kRunoutDistance)
          .With(observations::Statistic::kQuantile, 0.5);
  const std::string dir = Folder();
  WriteScoreFile(dir, score);
  const auto back = ReadBack<calibrate::ScoreResult>(dir, "score.json");
  EXPECT_EQ(Read(dir + "/score.json"), JsonText(back));
  ASSERT_EQ(back.misfit.residuals.size(), 1u);
  EXPECT_EQ(back.misfit.residuals[0].id, score.misfit.residuals[0].id);
  EXPECT_EQ(nlohmann::json::parse(Read(dir + "/score.json"))["parameters"], nullptr);
  fs::remove_all(dir);
}

}  // namespace result_files_test
}  // namespace rockcal::reports
