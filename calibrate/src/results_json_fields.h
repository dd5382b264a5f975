// The fields calibrate's result files share (results_json.cc,
// sensitivity_json.cc, reach_json.cc): numbers that may be null, the verdict,
// parameters and residual identities from their texts, a run's step figures.
// Private to calibrate/src.
#ifndef ROCKCAL_CALIBRATE_SRC_RESULTS_JSON_FIELDS_H_
#define ROCKCAL_CALIBRATE_SRC_RESULTS_JSON_FIELDS_H_

#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::calibrate::json_fields {

// The number at `key` of `j`; `unknown` where the file holds null.
double Number(const nlohmann::json& j, const char* key,
              double unknown = std::numeric_limits<double>::quiet_NaN());
// A list of numbers written with text::JsonNum (null for a non-finite one),
// and back (NaN for null).
nlohmann::json Numbers(const std::vector<double>& v);
std::vector<double> Numbers(const nlohmann::json& j);
// The verdict as score.json's fit (read back, it follows from the residuals).
nlohmann::json FitJson(const observations::FitVerdict& fit);
nlohmann::json Outcomes(int stopped, int left, int timeout);
// The parameter of `material` called `name` (a field's name, with "_offset"
// after it for an offset).
Parameter ParameterOf(const std::string& material, std::string name);
// The parameter labelled "<material>.<name>" (Parameter::label).
Parameter ParameterOfLabel(const std::string& label);
// The time steps and work of a run (RunFigures) as the stability cases and
// the convergence rows list them, and back.
void AddStepFigures(const core::RunFigures& f, nlohmann::json* j);
void ReadStepFigures(const nlohmann::json& j, core::RunFigures* f);

}  // namespace rockcal::calibrate::json_fields

#endif  // ROCKCAL_CALIBRATE_SRC_RESULTS_JSON_FIELDS_H_
