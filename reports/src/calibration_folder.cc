// Every file of a finished calibration's folder (calibration_folder.h).
#include "rockcal/reports/calibration_folder.h"

#include <nlohmann/json.hpp>

#include "rockcal/calibrate/posterior.h"
#include "rockcal/core/rasters.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/impact_outputs.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/raster_outputs.h"
#include "rockcal/reports/result_files.h"
#include "rockcal/reports/simulation_outputs.h"

namespace rockcal::reports {

void WriteCalibrationFolder(const std::string& out, const sites::Site& site,
                            const observations::Observations& obs,
                            const calibrate::CalibrationSummary& summary,
                            const std::optional<calibrate::HoldoutSummary>& holdout, bool rasters) {
  // One set of maps for rasters.tif and the report's plan view.
  const core::RasterSet maps = core::ComputeRasters(summary.calibrated, summary.simulation);
  WriteSimulationFiles(out, summary.calibrated, summary.simulation);
  WriteBarriersFile(out, summary.calibrated, summary.simulation, site.units);
  if (rasters) WriteRasterFiles(out, maps, SiteRasterFrame(site));
  WriteFileAtomically(out + "/parameters.json", ParametersJson(summary).dump(2) + "\n");
  WriteFileAtomically(out + "/parameters.csv", ParametersCsv(summary));
  WriteFileAtomically(out + "/parameters.md", ParametersMarkdown(summary));
  WriteFileAtomically(out + "/trace.csv", TraceCsv(summary));
  if (!summary.misfit_after.impacts.empty())
    WriteFileAtomically(out + "/impacts.csv", ImpactsCsv(summary.misfit_after, summary.calibrated,
                                                         1.0 / sites::LengthToSI(1.0, site.units)));
  if (summary.posterior)
    WriteFileAtomically(out + "/posterior.csv", calibrate::PosteriorCsv(*summary.posterior));
  nlohmann::json calibration = CalibrationJson(summary);
  if (holdout) {
    calibration["holdout"] = HoldoutJson(*holdout, summary);
    WriteFileAtomically(out + "/holdout.json", calibration["holdout"].dump(2) + "\n");
    WriteFileAtomically(out + "/holdout.csv", HoldoutCsv(*holdout, summary));
  }
  if (summary.reach) WriteFileAtomically(out + "/reach.json", JsonText(*summary.reach));
  ReportInput report = SiteReport(site, summary.calibrated, summary.simulation, &maps);
  report.calibration = &summary;
  report.observations = &obs;
  if (holdout) report.holdout = &*holdout;
  WriteFileAtomically(out + "/report.html", HtmlReport(report));
  if (summary.methods.size() > 1) {
    WriteFileAtomically(out + "/comparison.csv", ComparisonCsv(summary));
    WriteFileAtomically(out + "/comparison.md", ComparisonMarkdown(summary));
  }
  // Last: calibration.json marks the folder complete (PrepareFolder).
  WriteFileAtomically(out + "/calibration.json", calibration.dump(2) + "\n");
}

}  // namespace rockcal::reports
