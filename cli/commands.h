#ifndef ROCKCAL_CLI_COMMANDS_H_
#define ROCKCAL_CLI_COMMANDS_H_

#include <string>
#include <vector>

#include "rockcal/reports/html_report.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {

// The report of `result` (simulated from `scene`) with what the site file
// gives it: the file, its units, the reader's notes and the barrier.
reports::ReportInput SiteReport(const sites::Site& site, const core::Scene& scene,
                                const core::SimulationResult& result);

int Simulate(const std::vector<std::string>& args);
int Validate(const std::vector<std::string>& args);
int Calibrate(const std::vector<std::string>& args);
int Score(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_COMMANDS_H_
