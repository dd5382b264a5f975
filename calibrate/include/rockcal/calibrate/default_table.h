// Default tables: the calibrated parameters of many sites (each a
// `rockcal calibrate` result folder with its parameters.json) pooled per
// material class and parameter into a median, a range and a count of sites.
#ifndef ROCKCAL_CALIBRATE_DEFAULT_TABLE_H_
#define ROCKCAL_CALIBRATE_DEFAULT_TABLE_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/calibrate/parameters_file.h"

namespace rockcal::calibrate {

// Where a calibrated value sits against the bounds it was searched within.
enum class BoundPosition { kInside, kAtLower, kAtUpper };

// kAtLower (kAtUpper) when `value` is within `fraction` of the range
// (upper - lower) of the lower (upper) bound, else kInside. A value pinned at
// a bound was stopped by the bound, not by the data: it is no calibrated value.
BoundPosition AtBound(double value, double lower, double upper, double fraction);
const char* BoundName(BoundPosition position);  // "", "lower", "upper"

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
  double value = 0.0, lower = 0.0, upper = 0.0;  // the search's value and bounds
  std::optional<CalibratedParameter::Interval> posterior;  // the calibration's, when it has one
  // The value the row's statistics pool: the calibration's posterior median
  // when it has a posterior (the search's point may lie outside the
  // posterior: a minimum of the misfit is not the centre of what the data
  // allow), else the search's value.
  double pooled() const { return posterior ? posterior->median : value; }
  std::optional<double> std_error;
  std::optional<double> grid_spacing_m;
  // Where pooled() sits against the bounds: a value at a bound is left out
  // of the headline statistics (unless include_at_bound).
  BoundPosition bound = BoundPosition::kInside;
  bool counted = true;  // in the headline statistics
};

// One (class, parameter) row.
struct TableRow {
  std::string material_class;
  std::string name;                // "hardness", "roughness", "contact_time"
  std::vector<TableValue> values;  // in the order of the result folders
  // Statistics of the values' pooled().
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

// What a table says about itself (rockcal table --about FILE): per class a
// description an engineer recognises, per site where its data came from.
// docs/default-table.md gives the file.
struct ClassAbout {
  std::string description;  // one line: what ground this is
  std::string surface_cover, grain_size, vegetation;
  std::vector<std::string> references;  // the descriptive tables the class maps to
};
struct SiteAbout {
  std::string data;     // the data source (dataset, paper)
  std::string licence;  // the data's licence
  std::string command;  // the calibration command
  std::string observed;  // what was observed ("41 stop points")
  int observations = 0;  // how many observations
  std::string rockcal_version;  // of the calibration
};
struct TableAbout {
  std::string file;  // the file read
  std::string title;
  std::map<std::string, ClassAbout> classes;  // by class name
  std::map<std::string, SiteAbout> sites;     // by site name
};

// Reads an about file strictly (unknown, missing or mistyped keys are an
// InputError naming the file and JSON path).
TableAbout ReadTableAbout(const std::string& file);

struct DefaultTable {
  DefaultTableOptions options;
  std::optional<TableAbout> about;  // rockcal table --about
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
// The same with what the table says about itself: every class of the rows
// must be described and every site's data named (an InputError naming the
// about file and the class or site otherwise).
DefaultTable BuildDefaultTable(const std::vector<CalibratedSite>& sites,
                               const DefaultTableOptions& options, const TableAbout& about);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_DEFAULT_TABLE_H_
