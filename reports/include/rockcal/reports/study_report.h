// What `rockcal study stability|convergence` leave besides their JSON and CSV
// tables: report.html, built on the same page as the simulation report
// (html_page.h), and convergence.svg, the error-against-run-time plot that
// the convergence report shows inline. See reports/README.md.
#ifndef ROCKCAL_REPORTS_STUDY_REPORT_H_
#define ROCKCAL_REPORTS_STUDY_REPORT_H_

#include <string>
#include <vector>

#include "rockcal/calibrate/study.h"
#include "rockcal/core/scene.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports {

// The site a study ran on, for the report's `site` section.
struct StudyReportInput {
  const core::Scene* scene = nullptr;  // the site's scene as the study took it (after --set)
  std::string site_file;               // shown as given
  sites::Units units = sites::Units::kSI;
  std::vector<std::string> notes;  // what the site reader found and did
};

// report.html of the stability suite: sections `site` and `stability` (the
// limits and criteria, one row per case with PASS or FAIL, and the verdict).
// Its numbers refer to stability.json as calibrate::StabilityJson(scene name,
// options, cases) writes it. Throws std::invalid_argument when in.scene is
// missing.
std::string StabilityHtmlReport(const StudyReportInput& in,
                                const calibrate::StabilityOptions& options,
                                const std::vector<calibrate::StabilityCase>& cases);

// report.html of the convergence study: sections `site` and `convergence`
// (the plot of ConvergenceSvg, the table of every setting, the quantities and
// the recommendation). Its numbers refer to convergence.json as
// calibrate::ConvergenceJson(scene name, result) writes it. Throws
// std::invalid_argument when in.scene is missing or the result has no
// reference row.
std::string ConvergenceHtmlReport(const StudyReportInput& in,
                                  const calibrate::ConvergenceResult& result);

// convergence.svg: the largest error estimate of each setting against its
// wall seconds, log-log, one line per N_c through its rock counts (points
// labelled with the count), the target as a dashed red line and the
// recommendation circled. Self-contained SVG, no scripts.
std::string ConvergenceSvg(const std::string& site_name,
                           const calibrate::ConvergenceResult& result);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_STUDY_REPORT_H_
