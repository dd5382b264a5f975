// Default tables: the calibrated parameters of many sites (each a
// `rockcal calibrate` result folder with its parameters.json) pooled per
// material class and parameter into a median, a range and a count of sites.
#ifndef ROCKCAL_CALIBRATE_DEFAULT_TABLE_H_
#define ROCKCAL_CALIBRATE_DEFAULT_TABLE_H_

#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"

namespace rockcal::calibrate {

// Where a calibrated value sits against the bounds it was searched within.
enum class BoundPosition { kInside, kAtLower, kAtUpper };

// kAtLower (kAtUpper) when `value` is within `fraction` of the range
// (upper - lower) of the lower (upper) bound, else kInside. A value pinned at
// a bound was stopped by the bound, not by the data: it is no calibrated value.
BoundPosition AtBound(double value, double lower, double upper, double fraction);
const char* BoundName(BoundPosition position);  // "", "lower", "upper"

// One entry of a parameters.json, SI units (roughness m, contact time s).
struct CalibratedParameter {
  std::string material;        // material id at its site
  std::string material_class;  // "class", or the material id when the file has none
  bool class_given = true;     // false: the file has no "class" (written before classes)
  std::string name;            // "hardness", "roughness" or "contact_time"
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

struct DefaultTableOptions {
  // A value within this fraction of its range from a bound is "at a bound".
  // In [0, 0.5). Default 1 %.
  double bound_fraction = 0.01;
  // false (default): the headline statistics leave out values at a bound;
  // true: they count every value. Both sets are always computed.
  bool include_at_bound = false;

  // Checks the fields; on failure sets *error (field, value, rule).
  bool IsValid(std::string* error) const;
};

// Median (mean of the two middle values for an even count), min and max.
struct ValueStatistics {
  int values = 0;                             // entries counted
  int sites = 0;                              // distinct site names among them
  double median = 0.0, min = 0.0, max = 0.0;  // meaningless when values == 0
};

// The statistics of `values`, whose k-th entry came from site `sites[k]`.
ValueStatistics Statistics(const std::vector<double>& values,
                           const std::vector<std::string>& sites);

// One value in a row, with where it came from.
struct TableValue {
  std::string site;        // site name
  std::string result_dir;  // the folder it was read from
  std::string material;    // material id at that site
  double value = 0.0, lower = 0.0, upper = 0.0;
  std::optional<double> std_error;
  std::optional<double> grid_spacing_m;
  std::optional<CalibratedParameter::Interval> posterior;  // the calibration's, when it has one
  BoundPosition bound = BoundPosition::kInside;
  bool counted = true;  // in the headline statistics
};

// One (class, parameter) row.
struct TableRow {
  std::string material_class;
  std::string name;                // "hardness", "roughness", "contact_time"
  std::vector<TableValue> values;  // in the order of the result folders
  ValueStatistics headline;        // the values counted (see options)
  ValueStatistics all;             // every value, at a bound or not
  int at_bound = 0;                // values at a bound
  // When every counted value has a posterior (rockcal calibrate
  // --posterior): the lowest of their 5 % quantiles and the highest of
  // their 95 % quantiles (the envelope of the sites' 90 % intervals: the
  // values some site's posterior holds), and how many were pooled.
  std::optional<double> posterior_p05, posterior_p95;
  int posterior_values = 0;
};

struct DefaultTable {
  DefaultTableOptions options;
  std::vector<CalibratedSite> sites;  // as given, in order
  // Sorted by class, then hardness, roughness, contact_time.
  std::vector<TableRow> rows;
  // What a user should know: old files without classes, a site met in
  // several folders, values at a bound, roughness from different grid spacings.
  std::vector<std::string> notes;
  bool any_posterior = false;  // some value has a posterior: the outputs show the intervals
};

// Pools the calibrated sites (in the order given) into the table. The same
// result folder twice is an InputError (it would count one calibration twice).
DefaultTable BuildDefaultTable(const std::vector<CalibratedSite>& sites,
                               const DefaultTableOptions& options);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_DEFAULT_TABLE_H_
