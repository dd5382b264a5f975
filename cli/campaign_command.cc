// rockcal campaign: the joint calibration of several sites whose materials
// share classes (calibrate::RunCampaign), with calibrate's search, methods,
// evaluation log, resume and posterior.
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

#include "args.h"
#include "calibrate_common.h"
#include "commands.h"
#include "progress.h"
#include "rockcal/calibrate/campaign.h"
#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/limits.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/parallel/parallel.h"
#include "rockcal/reports/calibration_folder.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/campaign_outputs.h"
#include "rockcal/reports/output_dir.h"

namespace rockcal::cli {
namespace {

void PrintCampaign(const std::string& out, const calibrate::CampaignSummary& summary,
                   double wall_seconds) {
  const calibrate::CalibrationSummary& cal = summary.calibration;
  std::printf("\njoint misfit %.4g at the start, %.4g at the calibrated values\n",
              cal.misfit_before.value, cal.misfit_after.value);
  for (const calibrate::CampaignSiteFit& fit : summary.sites)
    std::printf("  %-16s misfit %.4g at its own start, %.4g at the joint values; fit %s\n",
                fit.name.c_str(), fit.misfit_start.value, fit.misfit_joint.value,
                observations::AssessFit(fit.misfit_joint).Sentence().c_str());
  std::printf("\n%s", reports::ParametersMarkdown(cal).c_str());
  const calibrate::Uncertainty& u = cal.best_method().uncertainty;
  if (u.computed && !u.rank_deficient) std::printf("Standard errors: %s.\n", u.message.c_str());
  if (cal.methods.size() > 1) std::printf("\n%s", reports::ComparisonMarkdown(cal).c_str());
  if (cal.posterior) {
    for (const calibrate::CampaignSiteFit& fit : summary.sites) {
      std::printf(
          "  %-16s predictive check: %d of %zu observed statistics inside the 5-95 %% "
          "band of a new observation\n",
          fit.name.c_str(), fit.posterior->BandsInside(), fit.posterior->bands.size());
    }
  }
  std::printf(
      "\nwrote %s/ in %.1f s: parameters.{json,csv,md}, sites.csv, trace.csv, "
      "summary.json, evaluations.jsonl%s%s, and each site's parameters.{json,csv}%s in "
      "sites/\n",
      out.c_str(), wall_seconds, cal.methods.size() > 1 ? ", comparison.{csv,md}" : "",
      cal.posterior ? ", posterior.csv" : "", cal.posterior ? " and posterior.csv" : "");
}

}  // namespace

int Campaign(const std::vector<std::string>& argv) {
  const auto start_time = std::chrono::steady_clock::now();
  const Args args(argv, FlagsOf("campaign"));
  const std::string path = args.OnlyPositional("CAMPAIGN.json");
  std::vector<calibrate::Method> methods = calibrate::CalibrationOptions::SingleStage().methods;
  MethodsFromArgs(args, &methods);
  if (args.Flag("resume") && args.Flag("force"))
    throw InputError("arguments", "give --resume or --force, not both");
  const calibrate::Campaign campaign = calibrate::LoadCampaign(path);
  const std::string out = OutFolder(args, path, "campaign");
  // A campaign searches in one stage, at the rocks it is given.
  calibrate::CalibrationOptions options =
      OptionsFromArgs(args, out, calibrate::CalibrationOptions::SingleStage());
  options.methods = methods;
  PosteriorFromArgs(args, &options);
  calibrate::CheckCampaign(campaign, options);

  const bool quiet = args.Flag("quiet");
  if (!quiet) {
    std::printf("campaign %s: %zu sites\n", campaign.name.c_str(), campaign.sites.size());
    const calibrate::JointSpace joint(campaign);
    for (const std::string& note : joint.notes()) std::printf("  %s\n", note.c_str());
  }
  std::optional<Progress> progress;
  calibrate::CalibrationCallbacks callbacks =
      ProgressCallbacks(quiet, options.method.max_evals, &progress);
  std::optional<reports::ResumableOutputDir> dir;  // locked for the life of the run
  PrepareCalibrationFolder(
      args, out, RunInputs().Add(campaign), "campaign", "summary.json",
      [&] { calibrate::CheckCampaignResume(campaign, options); }, &dir, &callbacks);
  const std::string folder = RankCalibrationFolder(out);
  options.log_path = folder + "/evaluations.jsonl";
  callbacks.posterior = PosteriorProgressPrinter(quiet, &progress);
  calibrate::CampaignSummary summary;
  ContinuableRun(out, [&] {
    summary = calibrate::RunCampaign(campaign, options, callbacks);
    reports::WriteCampaignFolder(folder, summary);
  });
  if (!quiet)
    PrintCampaign(
        out, summary,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count());
  return 0;
}

}  // namespace rockcal::cli
