// The files of `rockcal table`: the default table per material class and
// parameter (calibrate/default_table.h) as JSON, CSV and Markdown.
#ifndef ROCKCAL_REPORTS_DEFAULT_TABLE_OUTPUTS_H_
#define ROCKCAL_REPORTS_DEFAULT_TABLE_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>

#include "rockcal/calibrate/default_table.h"

namespace rockcal::reports {

// table.json (SI): the options, the result folders read, one row per class
// and parameter with its headline statistics, the statistics of every value,
// and each value with its site, folder, bounds, standard error and bound
// flag; the notes. The schema is in the README (Outputs).
nlohmann::json DefaultTableJson(const calibrate::DefaultTable& table);
// table.csv: one row per class and parameter, SI:
// class,parameter,unit,sites,values,median,min,max,at_bound,
// sites_all,values_all,median_all,min_all,max_all (median/min/max empty when
// no value is counted).
std::string DefaultTableCsv(const calibrate::DefaultTable& table);
// values.csv: one row per value, SI:
// class,parameter,unit,site,folder,material,value,lower,upper,std_error,at_bound,counted.
std::string DefaultTableValuesCsv(const calibrate::DefaultTable& table);
// table.md: the table a user pastes (class, parameter, sites, median,
// min - max; roughness in m and ft, contact time in ms), then every value, the
// result folders (site, method, evaluations, misfit, grid spacing) and the
// notes.
std::string DefaultTableMarkdown(const calibrate::DefaultTable& table);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_DEFAULT_TABLE_OUTPUTS_H_
