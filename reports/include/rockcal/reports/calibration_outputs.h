// The record of a calibration: parameter tables (JSON, CSV, Markdown), the
// trace of every evaluation (error against run time), calibration.json and
// the comparison of methods.
#ifndef ROCKCAL_REPORTS_CALIBRATION_OUTPUTS_H_
#define ROCKCAL_REPORTS_CALIBRATION_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/parameters_file.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports {

// The record of a calibration is calibrate::CalibrationSummary (made by
// calibrate::Calibrate); these write it.
using calibrate::CalibrationSummary;

// parameters.csv: material,class,name,value,lower,upper,std_error,unit (and
// the posterior's median, 5-95 % interval and "determined" with one); the
// same values as parameters.json (calibrate::ParametersFileJson).
std::string ParametersCsv(const calibrate::CalibratedSite& site);
// parameters.md: a Markdown table ready for a report (site units beside SI).
std::string ParametersMarkdown(const CalibrationSummary& record);
// The posterior's table (median, 5-95 % interval, share of the prior's
// width, determined or not), the strong correlations, the diagnostics and
// the predictive check, in Markdown; empty without a posterior.
// parameters.md ends with it.
std::string PosteriorMarkdown(const CalibrationSummary& record);
// Which values to carry into a design when the search's point and the
// posterior disagree: each calibrated value outside its posterior 5-95 %
// interval, named with both, and why the posterior is the one to use (the
// search's point is the lowest misfit of one set of simulated rocks, which
// their Monte Carlo noise moves; the posterior's emulator averages over it
// and carries the uncertainty). Empty without a posterior or when every
// value lies inside its interval. parameters.md, the console and the report
// print it.
std::string PosteriorAdvice(const CalibrationSummary& record);
// What the standard errors say of how well the observations determine the
// calibrated values, in plain words: the parameters whose standard error
// exceeds a quarter of their calibration range ("not determined by the
// observations"), and the pairs whose correlation is 0.9 or more in size
// ("determined only together"); or why no standard errors exist. Empty when
// every value is determined. parameters.md and the report print it.
std::string DeterminationSentence(const CalibrationSummary& record);
// trace.csv: method,evaluation,wall_seconds,misfit,best_misfit,<parameters>,replayed.
std::string TraceCsv(const CalibrationSummary& record);
// calibration.json: methods, terminations, budgets, misfit before and after,
// per-observation fit, uncertainties.
// The plain verdict on the fit at the calibrated values (observations::
// AssessFit) with the outcomes of the final simulation: calibration.json's
// "verdict".
nlohmann::json VerdictJson(const CalibrationSummary& record);
nlohmann::json CalibrationJson(const CalibrationSummary& record);
// The lowest misfit any method evaluated: the target of "time to within
// 10 %" in the comparison of methods.
double LowestMisfitOfAll(const CalibrationSummary& record);
// The comparison of methods on the same site and budget (error against run
// time): misfit, evaluations, wall seconds, time to within 10 % of the best.
std::string ComparisonCsv(const CalibrationSummary& record);
std::string ComparisonMarkdown(const CalibrationSummary& record);
// A tracked campaign's repeat scatter (observations::RunRepeatScatter):
// {"sets", "runs", "release_radius_m", "own_median_abs_error_m",
// "others_median_abs_error_m"}, or null.
nlohmann::json RepeatScatterJson(const std::optional<observations::RepeatScatter>& scatter);
// holdout.json (and the "holdout" section of calibration.json): per fold the
// in-sample and held-out misfits and the held-out runout error, their means,
// beside the full calibration's in-sample misfit.
nlohmann::json HoldoutJson(const calibrate::HoldoutSummary& holdout,
                           const CalibrationSummary& full);
// holdout.csv: fold,held_out_values,in_sample_misfit,held_out_misfit,runout_error_m,<parameters>.
std::string HoldoutCsv(const calibrate::HoldoutSummary& holdout, const CalibrationSummary& full);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_CALIBRATION_OUTPUTS_H_
