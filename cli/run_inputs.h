// Every file and folder a run reads, collected once per command: the site
// and every data file it names, the observations and their CSV files, the
// --parameters file or folder, the result folders of `table`, the campaign
// file and its members. The output folder is refused (exit 2, naming both)
// when it is, holds or lies inside any of them, before anything is written
// (reports::CheckOutputAgainstInputs, through reports::OutputDir and
// reports::ResumableOutputDir).
#ifndef ROCKCAL_CLI_RUN_INPUTS_H_
#define ROCKCAL_CLI_RUN_INPUTS_H_

#include <string>
#include <vector>

#include "rockcal/calibrate/campaign.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {

class RunInputs final {
 public:
  // A file or folder as given (an empty path is ignored).
  RunInputs& Add(const std::string& path);
  // The site file and every data file it names.
  RunInputs& Add(const sites::Site& site);
  // The observations file and the CSV files it names.
  RunInputs& Add(const observations::Observations& obs);
  // The campaign file, each member's site and observation files.
  RunInputs& Add(const calibrate::Campaign& campaign);

  const std::vector<std::string>& paths() const { return paths_; }
  // The origin of the output folder of `command` ("simulate", ...).
  reports::OutputOrigin Origin(const std::string& command) const { return {command, paths_}; }

 private:
  std::vector<std::string> paths_;
};

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_RUN_INPUTS_H_
