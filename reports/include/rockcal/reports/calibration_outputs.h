// The record of a calibration: parameter tables (JSON, CSV, Markdown), the
// trace of every evaluation (error against run time), calibration.json and
// the comparison of methods.
#ifndef ROCKCAL_REPORTS_CALIBRATION_OUTPUTS_H_
#define ROCKCAL_REPORTS_CALIBRATION_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports {

// Everything a calibration produced, as the outputs need it.
struct CalibrationRecord {
  std::string site;
  sites::Units units = sites::Units::kSI;
  double grid_spacing_m = 0.0;  // the terrain grid's spacing (0: not known)
  calibrate::ParameterSpace space;
  std::vector<double> start;           // physical values before
  observations::Misfit misfit_before;  // at start
  observations::Misfit misfit_after;   // at the calibrated values
  std::vector<calibrate::MethodResult> methods;  // in the order run
  int best = 0;                        // index into methods
  int rocks = 0;
  std::uint64_t seed = 1;
  double wall_seconds = 0.0;           // whole command
};

// parameters.json of DESIGN.md (SI), for the best method, with each
// parameter's material "class" and the grid's "grid_spacing_m" (when known)
// added: a roughness means the same virtual spheres only at the same spacing.
nlohmann::json ParametersJson(const CalibrationRecord& record);
// parameters.csv: material,class,name,value,lower,upper,std_error,unit.
std::string ParametersCsv(const CalibrationRecord& record);
// parameters.md: a Markdown table ready for a report (site units beside SI).
std::string ParametersMarkdown(const CalibrationRecord& record);
// trace.csv: method,evaluation,wall_seconds,misfit,best_misfit,<parameters>,replayed.
std::string TraceCsv(const CalibrationRecord& record);
// calibration.json: methods, terminations, budgets, misfit before and after,
// per-observation fit, uncertainties.
nlohmann::json CalibrationJson(const CalibrationRecord& record);
// The lowest misfit any method evaluated: the target of "time to within
// 10 %" in the comparison of methods.
double LowestMisfitOfAll(const CalibrationRecord& record);
// The comparison of methods on the same site and budget (error against run
// time): misfit, evaluations, wall seconds, time to within 10 % of the best.
std::string ComparisonCsv(const CalibrationRecord& record);
std::string ComparisonMarkdown(const CalibrationRecord& record);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_CALIBRATION_OUTPUTS_H_
