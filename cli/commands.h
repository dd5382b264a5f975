#ifndef ROCKCAL_CLI_COMMANDS_H_
#define ROCKCAL_CLI_COMMANDS_H_

#include <memory>
#include <string>
#include <vector>

#include "rockcal/core/rasters.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/raster_outputs.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {

// What --rasters adds to the printed list of files: "" without rasters.
std::string RastersWritten(bool asked, const sites::Site& site);

// A command's output folder (reports::OutputDir) under mpirun: rank 0
// prepares and commits it, and its error (exit 2 for a folder it may not
// replace) stops every rank alike; the other ranks write their copies of the
// files into a scratch folder of their own, which is thrown away.
class RankOutputDir final {
 public:
  RankOutputDir(const std::string& path, bool force, reports::OutputOrigin origin = {});
  std::string File(const std::string& name) const;
  const std::string& folder() const;
  void Commit();

 private:
  std::unique_ptr<reports::OutputDir> dir_;  // rank 0
  std::string scratch_;                      // the other ranks
};

int Simulate(const std::vector<std::string>& args);
int Validate(const std::vector<std::string>& args);
int Calibrate(const std::vector<std::string>& args);
// rockcal campaign CAMPAIGN.json: the joint calibration of several sites.
int Campaign(const std::vector<std::string>& args);
int Score(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_COMMANDS_H_
