// What `rockcal study reach` leaves besides reach.json (the result's
// to_json) and reach.csv (result_files.h): report.html, built on the page of
// html_page.h, with the table of every statistic and the plot of the reached
// ranges. ReachSection is the same table and plot for another report (the
// calibration's first stage).
#ifndef ROCKCAL_REPORTS_REACH_REPORT_H_
#define ROCKCAL_REPORTS_REACH_REPORT_H_

#include <string>

#include "rockcal/calibrate/reach.h"
#include "rockcal/reports/study_report.h"

namespace rockcal::reports {

// The plot: one row per statistic, a horizontal bar from the smallest to the
// largest value the design reached, in sigmas from the observed value (the
// dot at 0, with the +-1 sigma band of the verdict shaded); green when in
// reach, red when not. Bars beyond +-10 sigma are cut there and labelled
// with their true extent. Self-contained SVG, no scripts.
std::string ReachSvg(const calibrate::ReachResult& result);

// The section's body (HTML): the verdict, the rule, the table (statistic,
// observed +- sigma, reached min to max, closest point, verdict, coloured),
// the plot, the best design point and the design. Every shown number is the
// result's field, marked data-json="json_file#/pointer" with its place in
// reach.json (the result's to_json), so a caller that writes reach.json under
// another name passes that name.
std::string ReachSection(const calibrate::ReachResult& result,
                         const std::string& json_file = "reach.json");

// report.html of the reach study: sections `site` and `reach`. Throws
// std::invalid_argument when in.scene is missing.
std::string ReachHtmlReport(const StudyReportInput& in, const calibrate::ReachResult& result);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_REACH_REPORT_H_
