// Every file of a finished calibration's folder, written by one function
// (docs/reference/outputs.md): the simulation at the calibrated values, the
// parameter tables, the trace, impacts.csv, posterior.csv, holdout.json and
// holdout.csv, reach.json, report.html, the comparison and, last,
// calibration.json, which marks the folder complete.
#ifndef ROCKCAL_REPORTS_CALIBRATION_FOLDER_H_
#define ROCKCAL_REPORTS_CALIBRATION_FOLDER_H_

#include <optional>
#include <string>

#include "rockcal/calibrate/calibration_run.h"
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

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_CALIBRATION_FOLDER_H_
