// What `rockcal study stability|convergence` and `rockcal sensitivity` leave:
// their JSON (the result's to_json) and CSV tables; report.html, built on
// the same page as the simulation report (html_page.h), its numbers read
// from the result's fields and marked with their place in the JSON;
// convergence.svg, the error-against-run-time plot that the convergence
// report shows inline; and the sensitivity report's bar charts. See
// reports/README.md.
#ifndef ROCKCAL_REPORTS_STUDY_REPORT_H_
#define ROCKCAL_REPORTS_STUDY_REPORT_H_

#include <string>
#include <vector>

#include "rockcal/calibrate/sensitivity.h"
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
// Its numbers are marked with their place in stability.json (the study's
// to_json). Throws std::invalid_argument when in.scene is missing.
std::string StabilityHtmlReport(const StudyReportInput& in, const calibrate::StabilityStudy& study);

// report.html of the convergence study: sections `site` and `convergence`
// (the plot of ConvergenceSvg, the table of every setting, the quantities and
// the recommendation). Its numbers are marked with their place in
// convergence.json (the result's to_json). Throws
// std::invalid_argument when in.scene is missing or the result has no
// reference row.
std::string ConvergenceHtmlReport(const StudyReportInput& in,
                                  const calibrate::ConvergenceResult& result);

// convergence.svg: the largest error estimate of each setting against its
// wall seconds, log-log, one line per N_c through its rock counts (points
// labelled with the count), the target as a dashed red line and the
// recommendation circled; titled with the result's site. Self-contained
// SVG, no scripts.
std::string ConvergenceSvg(const calibrate::ConvergenceResult& result);

// report.html of the sensitivity study: sections `site` and `sensitivity`
// (the design and its cost, the parameters, each output with its value and
// Monte Carlo noise, one bar chart per output, the table of every parameter
// and output, the notes). Its numbers are marked with their place in
// sensitivity.json (the result's to_json). Throws std::invalid_argument when
// in.scene is missing.
std::string SensitivityHtmlReport(const StudyReportInput& in,
                                  const calibrate::SensitivityResult& result);

// The bar chart of one output (index into result.outputs): per parameter,
// Morris mu* with a whisker of +-sigma and the noise of one elementary effect
// as a dashed line; Sobol S_i and ST_i side by side with their intervals.
// Self-contained SVG, no scripts.
std::string SensitivitySvg(const calibrate::SensitivityResult& result, int output);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_STUDY_REPORT_H_
