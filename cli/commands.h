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

class Args;

// The output folder: --out, or when it is omitted a new folder in the
// working directory named after `input` (the site or campaign file, or ""
// for none) and `command`: "<name>-<command>", where <name> is the file's
// stem, or its folder's name for a file called site.json or campaign.json
// (sites/examples/tutorial/site.json -> tutorial-simulate); then -2, -3, ...
// until the name is free, so that nothing is ever overwritten. A default
// folder is announced on stdout ("output folder: ..."), even with --quiet.
// --resume needs --out (exit 2 without it).
std::string OutFolder(const Args& args, const std::string& input, const std::string& command);

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
