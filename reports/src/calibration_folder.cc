// Every file of a finished calibration's folder (calibration_folder.h).
#include "rockcal/reports/calibration_folder.h"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "rockcal/calibrate/parameters_file.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/core/rasters.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/campaign_outputs.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/impact_outputs.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/raster_outputs.h"
#include "rockcal/reports/result_files.h"
#include "rockcal/reports/simulation_outputs.h"

namespace rockcal::reports {
namespace {

// parameters.json, parameters.csv and, with a posterior, posterior.csv:
// what rockcal simulate --parameters, score and table read back.
void WriteParameterFiles(const std::string& dir, const calibrate::CalibratedSite& values,
                         const std::optional<calibrate::PosteriorResult>& posterior) {
  if (posterior)
    WriteFileAtomically(dir + "/posterior.csv",
                        calibrate::PosteriorSamplesCsv(values.parameters, posterior->samples));
  WriteFileAtomically(dir + "/parameters.csv", ParametersCsv(values));
  WriteFileAtomically(dir + "/parameters.json",
                      calibrate::ParametersFileJson(values).dump(2) + "\n");
}

}  // namespace

void WriteCalibrationFolder(const std::string& out, const sites::Site& site,
                            const observations::Observations& obs,
                            const calibrate::CalibrationSummary& summary,
                            const std::optional<calibrate::HoldoutSummary>& holdout, bool rasters) {
  // One set of maps for rasters.tif and the report's plan view.
  const core::RasterSet maps = core::ComputeRasters(summary.calibrated, summary.simulation);
  WriteSimulationFiles(out, summary.calibrated, summary.simulation);
  WriteBarriersFile(out, summary.calibrated, summary.simulation, site.units);
  if (rasters) WriteRasterFiles(out, maps, SiteRasterFrame(site));
  WriteParameterFiles(out, calibrate::CalibratedSiteOf(summary), summary.posterior);
  WriteFileAtomically(out + "/parameters.md", ParametersMarkdown(summary));
  WriteFileAtomically(out + "/trace.csv", TraceCsv(summary));
  if (!summary.misfit_after.impacts.empty())
    WriteFileAtomically(out + "/impacts.csv", ImpactsCsv(summary.misfit_after, summary.calibrated,
                                                         1.0 / sites::LengthToSI(1.0, site.units)));
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

void WriteCampaignFolder(const std::string& out, const calibrate::CampaignSummary& summary) {
  const calibrate::CalibrationSummary& cal = summary.calibration;
  const std::vector<std::string> folders = CampaignSiteFolders(summary);
  for (std::size_t k = 0; k < folders.size(); ++k) {
    const std::string dir = out + "/" + folders[k];
    std::filesystem::create_directories(dir);
    WriteParameterFiles(dir, calibrate::CalibratedSiteOf(summary, k), summary.sites[k].posterior);
  }
  WriteParameterFiles(out, calibrate::CalibratedSiteOf(cal), cal.posterior);
  WriteFileAtomically(out + "/parameters.md", CampaignMarkdown(summary));
  WriteFileAtomically(out + "/trace.csv", TraceCsv(cal));
  WriteFileAtomically(out + "/sites.csv", CampaignSitesCsv(summary));
  if (cal.methods.size() > 1) {
    WriteFileAtomically(out + "/comparison.csv", ComparisonCsv(cal));
    WriteFileAtomically(out + "/comparison.md", ComparisonMarkdown(cal));
  }
  // Last: summary.json marks the folder complete (PrepareCalibrationFolder).
  WriteFileAtomically(out + "/summary.json", CampaignJson(summary).dump(2) + "\n");
}

}  // namespace rockcal::reports
