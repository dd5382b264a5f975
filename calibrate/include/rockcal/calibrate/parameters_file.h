// The calibrated values of a calibration folder: parameters.json and the
// posterior samples beside it (posterior.csv). One typed record
// (CalibratedSite), built from a calibration or a campaign's site, written and
// read back by the functions of this file only, so that what `calibrate` and
// `campaign` write is what `simulate --parameters`, `score` and `table` read
// (docs/reference/outputs.md).
#ifndef ROCKCAL_CALIBRATE_PARAMETERS_FILE_H_
#define ROCKCAL_CALIBRATE_PARAMETERS_FILE_H_

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"

namespace rockcal::calibrate {

struct CalibrationSummary;
struct CampaignSummary;

// One entry of a parameters.json, SI units (roughness m, contact time s).
struct CalibratedParameter {
  std::string material;        // material id at its site
  std::string material_class;  // "class", or the material id when the file has none
  bool class_given = true;     // false: the file has no "class" (written before classes)
  std::string name;            // a material field's name (core::MaterialFields())
  double value = 0.0, lower = 0.0, upper = 0.0;
  std::optional<double> std_error;  // null in the file: not computed
  // "posterior" (rockcal calibrate --posterior): the posterior's median and
  // 5-95 % interval (SI) and whether the data determine the value.
  struct Interval {
    double median = 0.0, p05 = 0.0, p95 = 0.0;
    bool determined = true;
  };
  std::optional<Interval> posterior;  // absent: no posterior
};

// One calibrated site: RESULT_DIR/parameters.json.
struct CalibratedSite {
  std::string result_dir;  // as given
  std::string file;        // result_dir + "/parameters.json"
  std::string site;        // the site's name
  Stage stage;             // "method": the best method, at a refining stage's rocks
  double misfit = 0.0;
  int evaluations = 0;
  double wall_seconds = 0.0;             // the best method's
  std::optional<double> grid_spacing_m;  // absent in files written before it
  std::vector<CalibratedParameter> parameters;
  // The posterior samples' file (every parameter has a posterior): the
  // "posterior_samples" key, relative to the file's folder, or else
  // posterior.csv beside it; empty without a posterior.
  std::string samples_file;
  bool has_posterior() const { return !samples_file.empty(); }
};

// Reads RESULT_DIR/parameters.json strictly: a missing folder or file, bad
// JSON, a missing, unknown or mistyped key, an unknown parameter name, bounds
// with lower >= upper, a value outside its bounds, a negative standard error,
// a method no rockcal names (Stage::FromName) or a parameter given twice are
// each an InputError naming the file, the JSON
// path, the value and what was expected.
CalibratedSite ReadCalibratedSite(const std::string& result_dir);
// The same for a parameters.json named by its path, or by its folder
// (result_dir is its folder).
CalibratedSite ReadParametersFile(const std::string& file);

// The posterior samples of `site` (site.samples_file, as rockcal calibrate
// --posterior writes it: a header of the parameters' labels
// material.name in the order of site.parameters, one sample per line, SI):
// sample k is samples[k], one value per parameter. A missing file, a header
// naming other parameters, a line of another length, a value that is not a
// number or lies outside its bounds, or no sample at all is an InputError
// naming the file, the line (and column) and what was expected.
std::vector<std::vector<double>> ReadPosteriorSamples(const CalibratedSite& site);

// The SI unit of a parameter's values ("", "m", "s", "Pa"); a campaign's
// offset ("hardness_offset") has its field's.
const char* SiUnitOf(const CalibratedParameter& parameter);

// The calibrated values of a calibration (its best method's), with their
// standard errors and posterior intervals when computed; samples_file is
// "posterior.csv" with a posterior. result_dir and file are empty.
CalibratedSite CalibratedSiteOf(const CalibrationSummary& summary);
// Site `site` of a campaign at the joint values (the campaign's best method,
// the site's own misfit and posterior; no standard errors).
CalibratedSite CalibratedSiteOf(const CampaignSummary& summary, std::size_t site);

// The "parameters" list of parameters.json (and of a campaign's
// summary.json): per parameter its material, class, name, value, bounds,
// standard error (null: not computed) and posterior interval.
nlohmann::json ParameterListJson(const CalibratedSite& site);
// The whole parameters.json (ReadParametersFile reads it back).
nlohmann::json ParametersFileJson(const CalibratedSite& site);
// posterior.csv: a header of the parameters' labels material.name in the
// order of `parameters`, one sample per line, SI (ReadPosteriorSamples
// reads it back).
std::string PosteriorSamplesCsv(const std::vector<CalibratedParameter>& parameters,
                                const std::vector<std::vector<double>>& samples);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_PARAMETERS_FILE_H_
