#ifndef ROCKCAL_CLI_COMMANDS_H_
#define ROCKCAL_CLI_COMMANDS_H_

#include <string>
#include <vector>

#include "rockcal/core/rasters.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/raster_outputs.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {

// The report of `result` (simulated from `scene`) with what the site file
// gives it: the file, its units, the reader's notes and the barrier; its plan
// view draws `rasters` (the maps of `result`, as written to rasters.tif).
reports::ReportInput SiteReport(const sites::Site& site, const core::Scene& scene,
                                const core::SimulationResult& result,
                                const core::RasterSet* rasters);

// Where the maps lie: the site's CRS and the unit of its coordinates.
reports::RasterFrame SiteRasterFrame(const sites::Site& site);

// What --rasters adds to the printed list of files: "" without rasters.
std::string RastersWritten(bool asked, const sites::Site& site);

int Simulate(const std::vector<std::string>& args);
int Validate(const std::vector<std::string>& args);
int Calibrate(const std::vector<std::string>& args);
int Score(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_COMMANDS_H_
