// Every file of a finished calibration's or campaign's folder, each folder
// written by one function (docs/reference/outputs.md). A calibration: the
// simulation at the calibrated values, the parameter tables, the trace,
// impacts.csv, posterior.csv, holdout.json and holdout.csv, reach.json,
// report.html, the comparison and, last, calibration.json, which marks the
// folder complete. A campaign: each site's parameter files, the joint ones,
// sites.csv, the trace, the comparison and, last, summary.json.
#ifndef ROCKCAL_REPORTS_CALIBRATION_FOLDER_H_
#define ROCKCAL_REPORTS_CALIBRATION_FOLDER_H_

#include <optional>
#include <string>

#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/campaign.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports {

// Every file of a finished calibration in folder `out` (with `rasters`, the
// maps of the simulation at the calibrated values that the report shows);
// calibration.json, which marks the folder complete, after every other file.
void WriteCalibrationFolder(const std::string& out, const sites::Site& site,
                            const observations::Observations& obs,
                            const calibrate::CalibrationSummary& summary,
                            const std::optional<calibrate::HoldoutSummary>& holdout, bool rasters);

// Every file of a finished campaign in folder `out`: each site's values at
// the joint calibration as a calibration's parameter files (parameters.json,
// parameters.csv, posterior.csv) in its folder (CampaignSiteFolders), for
// rockcal simulate --parameters and rockcal table; then the joint files;
// summary.json, which marks the folder complete, after every other file.
void WriteCampaignFolder(const std::string& out, const calibrate::CampaignSummary& summary);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_CALIBRATION_FOLDER_H_
