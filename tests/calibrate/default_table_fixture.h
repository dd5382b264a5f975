// Builders shared by the default-table and parameters-file tests (calibrate
// and reports).
#ifndef ROCKCAL_TESTS_CALIBRATE_DEFAULT_TABLE_FIXTURE_H_
#define ROCKCAL_TESTS_CALIBRATE_DEFAULT_TABLE_FIXTURE_H_

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "../sites/test_files.h"
#include "rockcal/calibrate/default_table.h"

namespace rockcal::calibrate::testing {

// One calibrated parameter of a result folder.
inline CalibratedParameter P(const std::string& material, const std::string& cls,
                             const std::string& name, double value, double lower, double upper) {
  CalibratedParameter p;
  p.material = material;
  p.material_class = cls;
  p.name = name;
  p.value = value;
  p.lower = lower;
  p.upper = upper;
  return p;
}

// parameters.json as rockcal calibrate writes it.
inline nlohmann::json ParametersFile() {
  return nlohmann::json::parse(R"({
    "site": "Tutorial slope", "method": "nlopt:bobyqa", "misfit": 12.5, "evaluations": 40,
    "wall_seconds": 3.2, "grid_spacing_m": 3.6576,
    "parameters": [
      {"material": "talus", "class": "scree", "name": "hardness", "value": 0.35,
       "lower": 0.1, "upper": 0.7, "std_error": null},
      {"material": "talus", "class": "scree", "name": "roughness", "value": 0.4,
       "lower": 0.1524, "upper": 1.8288, "std_error": 0.05},
      {"material": "soil", "class": "soil", "name": "contact_time", "value": 0.006,
       "lower": 0.002, "upper": 0.01, "std_error": null}
    ]})");
}

inline std::string WriteResult(const sites::testing::TempDir& dir, const std::string& name,
                               const nlohmann::json& json) {
  return std::filesystem::path(dir.Write(name + "/parameters.json", json.dump(2)))
      .parent_path()
      .string();
}

// ParametersFile() with a posterior per parameter, as calibrate --posterior writes it.
inline nlohmann::json WithPosterior() {
  nlohmann::json json = ParametersFile();
  json["parameters"][0]["posterior"] = {{"median", 0.3}, {"p05", 0.2}, {"p95", 0.5}, {"determined", true}};
  json["parameters"][1]["posterior"] = {{"median", 0.5}, {"p05", 0.3}, {"p95", 1.2}, {"determined", false}};
  json["parameters"][2]["posterior"] = {{"median", 0.006}, {"p05", 0.004}, {"p95", 0.008}, {"determined", true}};
  json["posterior_samples"] = "posterior.csv";
  return json;
}

}  // namespace rockcal::calibrate::testing

#endif  // ROCKCAL_TESTS_CALIBRATE_DEFAULT_TABLE_FIXTURE_H_
