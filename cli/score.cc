// rockcal score: one simulation of a site (optionally at an earlier
// calibration's values) scored against observations.
#include "rockcal/calibrate/score.h"

#include <cstdio>

#include "args.h"
#include "commands.h"
#include "progress.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/rasters.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/impact_outputs.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/result_files.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/sites/site.h"
#include "run_inputs.h"

namespace rockcal::cli {

int Score(const std::vector<std::string>& argv) {
  const Args args(argv, FlagsOf("score"));
  const std::string site_path = args.OnlyPositional("SITE.json");
  const sites::Site site = sites::LoadSite(site_path);
  const observations::Observations obs =
      observations::LoadObservations(args.Get("observations"), site.scene);
  calibrate::ScoreOptions options;
  if (args.Has("rocks")) options.rocks = static_cast<int>(args.Integer("rocks", 0, 1, 100000000));
  if (args.Has("seed"))
    options.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  options.threads = static_cast<int>(args.Integer("threads", options.threads, 0, 1024));
  if (args.Has("parameters")) options.parameters_file = args.Get("parameters");
  const core::Scene scene = calibrate::ScoreScene(site, options);
  PrintNotes(site.resampled, args.Flag("quiet"));

  const std::string out = OutFolder(args, site_path, "score");
  RunInputs inputs;
  inputs.Add(site).Add(obs).Add(options.parameters_file);
  RankOutputDir dir(out, args.Flag("force"), inputs.Origin("score"));
  const calibrate::ScoreSummary score = calibrate::Score(scene, obs);
  const core::SimulationResult& sim = score.simulation;
  const observations::FitVerdict fit = observations::AssessFit(score.misfit);
  reports::WriteSimulationFiles(dir.folder(), score.scene, sim);
  reports::WriteBarriersFile(dir.folder(), score.scene, sim, site.units);
  reports::WriteScoreFile(dir.folder(),
                          calibrate::ScoreResultOf(score, obs.path, options.parameters_file));
  if (!score.misfit.impacts.empty())
    reports::WriteFileAtomically(
        dir.File("impacts.csv"),
        reports::ImpactsCsv(score.misfit, score.scene, 1.0 / sites::LengthToSI(1.0, site.units)));
  const core::RasterSet rasters = core::ComputeRasters(score.scene, sim);
  reports::ReportInput report = reports::SiteReport(site, score.scene, sim, &rasters);
  report.observations = &obs;
  reports::WriteFileAtomically(dir.File("report.html"), reports::HtmlReport(report));
  dir.Commit();
  if (!args.Flag("quiet")) {
    std::printf("%s: misfit %.4g with %d rocks, seed %llu (%d stopped, %d left, %d timeout)\n",
                scene.name.c_str(), score.misfit.value, scene.total_rocks(),
                static_cast<unsigned long long>(scene.options.seed),
                sim.count(core::Outcome::kStopped), sim.count(core::Outcome::kLeft),
                sim.count(core::Outcome::kTimeout));
    std::printf("fit %s\n", fit.Sentence().c_str());
    if (const std::string tracks = observations::TracksVerdictSentence(score.misfit);
        !tracks.empty())
      std::printf("%s\n", tracks.c_str());
    if (!score.misfit.impacts.empty())
      std::printf("impacts: %s (impacts.csv)\n", observations::ImpactVerdict(score.misfit).c_str());
    std::printf("wrote %s/score.json, summary.json, rocks.csv, diagnostics.json, report.html\n",
                out.c_str());
  }
  return 0;
}

}  // namespace rockcal::cli
