// The files of calibrate's results: `rockcal study stability|convergence|
// reach`, `rockcal sensitivity` and `rockcal score`. Each result is a struct
// (calibrate/) whose JSON file is its to_json; its CSV table is written
// here, its report.html by study_report.h or reach_report.h from the same
// struct. The Write*Files functions build every file of a command first and
// then write them into `folder`, each through a temporary file.
#ifndef ROCKCAL_REPORTS_RESULT_FILES_H_
#define ROCKCAL_REPORTS_RESULT_FILES_H_

#include <nlohmann/json.hpp>
#include <string>

#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/reports/study_report.h"

namespace rockcal::reports {

// A result's JSON file: its to_json, indented by 2, with a final newline.
template <typename Result>
std::string JsonText(const Result& result) {
  return nlohmann::json(result).dump(2) + "\n";
}

// stability.csv: one row per case (SI units).
std::string StabilityCsv(const calibrate::StabilityStudy& study);
// convergence.csv: one row per setting and quantity, plus a "max" row per setting.
std::string ConvergenceCsv(const calibrate::ConvergenceResult& result);
// sensitivity.csv: one row per parameter and output.
std::string SensitivityCsv(const calibrate::SensitivityResult& result);
// reach.csv: one row per statistic (SI units).
std::string ReachCsv(const calibrate::ReachResult& result);

// stability.json, stability.csv, report.html.
void WriteStabilityFiles(const std::string& folder, const StudyReportInput& in,
                         const calibrate::StabilityStudy& study);
// convergence.json, convergence.csv, convergence.svg, report.html.
void WriteConvergenceFiles(const std::string& folder, const StudyReportInput& in,
                           const calibrate::ConvergenceResult& result);
// sensitivity.json, sensitivity.csv, report.html.
void WriteSensitivityFiles(const std::string& folder, const StudyReportInput& in,
                           const calibrate::SensitivityResult& result);
// reach.json, reach.csv, report.html.
void WriteReachFiles(const std::string& folder, const StudyReportInput& in,
                     const calibrate::ReachResult& result);
// score.json (rockcal score writes the simulation's files and report.html
// beside it: simulation_outputs.h, html_report.h).
void WriteScoreFile(const std::string& folder, const calibrate::ScoreResult& score);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_RESULT_FILES_H_
