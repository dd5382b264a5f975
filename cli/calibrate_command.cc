// rockcal calibrate: search the calibrated parameters of a site until its
// simulation matches the observations, and write the tables and the trace.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "args.h"
#include "calibrate_common.h"
#include "commands.h"
#include "progress.h"
#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/rasters.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/parallel/parallel.h"
#include "rockcal/reports/calibration_folder.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/impact_outputs.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/raster_outputs.h"
#include "rockcal/reports/result_files.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;

}  // namespace

void PrepareCalibrationFolder(const Args& args, const std::string& out, const RunInputs& inputs,
                              const std::string& command, const std::string& complete_file,
                              const std::function<void()>& check_resume,
                              std::optional<reports::ResumableOutputDir>* dir,
                              calibrate::CalibrationCallbacks* callbacks) {
  parallel::OnRoot([&] {
    dir->emplace(out, args.Flag("resume"), args.Flag("force"), inputs.Origin(command),
                 "evaluations.jsonl", complete_file);
    if (args.Flag("resume")) check_resume();
  });
  callbacks->log_opened = [dir] {
    if (*dir) (*dir)->Continue();
  };
}

void ContinuableRun(const std::string& out, const std::function<void()>& work) {
  try {
    work();
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + "; " + out +
                             " keeps the evaluations logged so far: mend the cause (e.g. free "
                             "space) and run the same command with --resume to continue it");
  }
}

void MethodsFromArgs(const Args& args, std::vector<calibrate::Method>* methods) {
  if (args.Has("method") && args.Has("methods"))
    throw InputError("arguments", "give --method or --methods, not both");
  if (!args.Has("method") && !args.Has("methods")) return;
  const std::string flag = args.Has("methods") ? "methods" : "method";
  const std::vector<std::string> names =
      args.Has("methods") ? args.List("methods") : std::vector<std::string>{args.Get("method")};
  methods->clear();
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    if (name.empty())
      throw InputError("argument --" + flag,
                       "'" + args.Get(flag) + "' has an empty name (item " + std::to_string(k + 1) +
                           "); expected a comma separated list of methods (allowed: " +
                           calibrate::MethodNames() + ")");
    calibrate::Method m;
    if (!calibrate::StringToMethod(name, &m))
      throw InputError("argument --" + flag,
                       "unknown method '" + name + "' (allowed: " + calibrate::MethodNames() + ")");
    if (std::find(methods->begin(), methods->end(), m) != methods->end())
      throw InputError("argument --" + flag, "'" + args.Get(flag) + "' names " +
                                                 calibrate::MethodToString(m) +
                                                 " twice; expected each method once");
    methods->push_back(m);
  }
}

calibrate::CalibrationOptions OptionsFromArgs(const Args& args, const std::string& out,
                                              calibrate::CalibrationOptions base) {
  calibrate::CalibrationOptions options = std::move(base);
  if (args.Has("rocks") && args.Has("refine"))
    throw InputError("arguments",
                     "give --rocks N (every evaluation at N rocks, one stage) or "
                     "--refine F (a refining stage at F times the rocks), not both");
  // --rocks N: every evaluation at N rocks, in one stage.
  if (args.Has("rocks")) {
    options.rocks = static_cast<int>(args.Integer("rocks", 0, 1, 10000000));
    options.refine_factor = 1;
    options.noise_raise = 1;  // the count given is kept; the noise check only advises
  }
  if (args.Has("noise-raise"))
    options.noise_raise = static_cast<int>(args.Integer("noise-raise", 0, 1, 100));
  if (args.Has("seed"))
    options.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  if (args.Has("threads")) options.threads = static_cast<int>(args.Integer("threads", 0, 0, 1024));
  if (args.Has("max-evals"))
    options.method.max_evals = static_cast<int>(
        args.Integer("max-evals", 0, calibrate::MethodOptions::kMinEvals, 1000000));
  if (args.Has("max-seconds"))
    options.method.max_seconds = args.Number("max-seconds", 0.0, 0.0, 1e9);
  if (args.Has("loss") &&
      !calibrate::StringToCeresLoss(args.Get("loss"), &options.method.ceres_loss))
    throw InputError("argument --loss", "unknown loss '" + args.Get("loss") +
                                            "' (allowed: " + calibrate::CeresLossNames() + ")");
  if (args.Has("estimate") &&
      !calibrate::StringToEstimate(args.Get("estimate"), &options.method.estimate))
    throw InputError("argument --estimate", "unknown estimate '" + args.Get("estimate") +
                                                "' (allowed: " + calibrate::EstimateNames() + ")");
  options.log_path = out + "/evaluations.jsonl";
  options.resume = args.Flag("resume");
  if (args.Has("refine"))
    options.refine_factor = static_cast<int>(args.Integer("refine", 0, 1, 1000));
  if (args.Has("reach")) {
    options.reach_points = static_cast<int>(args.Integer("reach", 0, 0, 100000));
    if (options.reach_points == 1)
      throw InputError("argument --reach", "1: expected 0 (no reach check) or at least 2 points");
  }
  if (args.Has("race")) options.race_points = static_cast<int>(args.Integer("race", 0, 0, 100000));
  return options;
}

calibrate::CalibrationCallbacks ProgressCallbacks(bool quiet, int max_evals,
                                                  std::optional<Progress>* progress,
                                                  const std::string& stages) {
  calibrate::CalibrationCallbacks callbacks;
  callbacks.started = [quiet, stages](const calibrate::CalibrationSummary& s) {
    if (!quiet)
      std::printf(
          "%s: %d parameters, %d rocks per evaluation%s, misfit at the start %.4g (at %d "
          "rocks)\n",
          s.site.c_str(), s.space.size(), s.rocks, stages.c_str(), s.misfit_before.value, s.rocks);
  };
  callbacks.reach_done = [quiet](const calibrate::ReachResult& r) {
    const std::vector<std::string> warnings = calibrate::OutOfReachWarnings(r, false);
    if (!quiet)
      std::printf("reach before fit: %zu design points, %zu of %zu observed statistics in reach\n",
                  r.points.size(), r.statistics.size() - warnings.size(), r.statistics.size());
    for (const std::string& w : warnings) std::printf("OUT OF REACH: %s\n", w.c_str());
    if (!warnings.empty()) std::printf("  %s\n", calibrate::OutOfReachAdvice(r).c_str());
  };
  callbacks.noise_checked = [quiet](const calibrate::CalibrationSummary& s) {
    if (s.noise_check.still_dominates())
      std::printf("NOISE: %s\n", s.noise_check.message.c_str());
    else if (!quiet)
      std::printf("%s\n", s.noise_check.message.c_str());
  };
  callbacks.method_started = [quiet, progress](const calibrate::Stage& stage) {
    progress->emplace("calibrate " + stage.name(), quiet);
  };
  callbacks.evaluated = [max_evals, progress](const calibrate::Evaluation& e, double best) {
    char extra[96];
    std::snprintf(extra, sizeof extra, " best misfit %.4g, %.0f s", best, e.elapsed);
    (*progress)->Update(e.index, max_evals, extra);
  };
  callbacks.method_finished = [quiet, progress](const calibrate::MethodResult& result) {
    progress->reset();
    if (!quiet)
      std::printf("  %-18s misfit %.4g after %d evaluations (%d simulated) in %.1f s: %s\n",
                  result.stage.name().c_str(), result.best_misfit, result.evaluations,
                  result.simulated, result.wall_seconds, result.termination.message.c_str());
  };
  return callbacks;
}

void PosteriorFromArgs(const Args& args, calibrate::CalibrationOptions* options) {
  if (!args.Flag("posterior")) {
    std::string given;
    for (const char* name : {"posterior-points", "posterior-rounds", "posterior-stage",
                             "posterior-log-sigma", "predictive"})
      if (args.Has(name) || args.Flag(name))
        given += std::string(given.empty() ? "--" : ", --") + name;
    if (!given.empty())
      throw InputError("arguments", "the posterior's options (" + given + ") need --posterior");
    return;
  }
  calibrate::PosteriorOptions p;
  p.design_points = static_cast<int>(args.Integer("posterior-points", p.design_points, 0, 100000));
  p.rounds = static_cast<int>(args.Integer("posterior-rounds", p.rounds, 0, 1000));
  p.predictive_draws = static_cast<int>(args.Integer("predictive", p.predictive_draws, 0, 100000));
  p.sigma_log_term = args.Flag("posterior-log-sigma");
  options->posterior = p;
  const std::string stage =
      args.Get("posterior-stage", calibrate::PosteriorStageToString(options->posterior_stage));
  if (!calibrate::StringToPosteriorStage(stage, &options->posterior_stage))
    throw InputError("argument --posterior-stage", "'" + stage + "': expected first or final");
}

calibrate::PosteriorProgress PosteriorProgressPrinter(bool quiet,
                                                      std::optional<Progress>* progress) {
  auto last = std::make_shared<std::string>();
  return [quiet, progress, last](const std::string& stage, int done, int total) {
    if (stage != *last) {
      progress->reset();
      if (!quiet) {
        std::printf("posterior: %s%s\n", stage.c_str(),
                    total > 1 ? (" (" + std::to_string(total) + " simulations)").c_str() : "");
        std::fflush(stdout);
      }
      *last = stage;
      progress->emplace("posterior " + stage, quiet);
    }
    (*progress)->Update(done, total);
    if (done == total && total > 1) progress->reset();
  };
}

std::string RankCalibrationFolder(const std::string& out) {
  const std::string folder = parallel::IsRoot() ? out : parallel::ScratchFolder();
  parallel::ShareFiles(
      out,
      [](const std::string& name) {
        return name.rfind("evaluations", 0) == 0 && name.size() > 6 &&
               name.compare(name.size() - 6, 6, ".jsonl") == 0;
      },
      folder);
  return folder;
}

namespace {

// The closing lines: the rocks at the calibrated values, the verdict on the
// fit, the parameter table and what was written.
void PrintCalibration(const std::string& out, const calibrate::CalibrationSummary& summary,
                      bool holdout, const std::string& rasters, double wall_seconds) {
  const core::SimulationResult& sim = summary.simulation;
  if (summary.race_winner >= 0) {
    std::printf("\nrace of the refining stage's start at %d rocks (misfit):", summary.final_rocks);
    for (const auto& entry : summary.race)
      std::printf("%s %s %.4g", &entry == &summary.race.front() ? "" : ",", entry.from.c_str(),
                  entry.misfit);
    std::printf("\nrefining from %s\n",
                summary.race[static_cast<std::size_t>(summary.race_winner)].from.c_str());
  }
  std::printf(
      "\nat the calibrated values: %d of %zu rocks stopped, %d left the terrain, %d timed "
      "out\nfit %s\n",
      sim.count(core::Outcome::kStopped), sim.rocks.size(), sim.count(core::Outcome::kLeft),
      sim.count(core::Outcome::kTimeout),
      observations::AssessFit(summary.misfit_after).Sentence().c_str());
  if (const std::string tracks = observations::TracksVerdictSentence(summary.misfit_after);
      !tracks.empty())
    std::printf("%s\n", tracks.c_str());
  if (!summary.misfit_after.impacts.empty())
    std::printf("impacts: %s\n", observations::ImpactVerdict(summary.misfit_after).c_str());
  if (!summary.misfit_after.runs.empty())
    std::printf(
        "tracked runs: %zu, mean |median simulated - observed| runout %.3g m, %d simulated "
        "rocks stuck at their release\n",
        summary.misfit_after.runs.size(), summary.misfit_after.MeanRunError(),
        summary.misfit_after.StuckRocks());
  // The noise check's NOISE line was printed once, when it was made.
  std::printf("\n%s", reports::ParametersMarkdown(summary).c_str());
  if (summary.methods.size() > 1) std::printf("\n%s", reports::ComparisonMarkdown(summary).c_str());
  std::printf(
      "\nwrote %s/ in %.1f s: parameters.{json,csv,md}, trace.csv, calibration.json, "
      "evaluations.jsonl, summary.json, rocks.csv, report.html%s%s%s\n",
      out.c_str(), wall_seconds, summary.methods.size() > 1 ? ", comparison.{csv,md}" : "",
      holdout ? ", holdout.{json,csv}, evaluations-fold-*.jsonl" : "", rasters.c_str());
  if (summary.posterior)
    std::printf("  and posterior.csv (%zu posterior samples)\n", summary.posterior->samples.size());
}

}  // namespace

int Calibrate(const std::vector<std::string>& argv) {
  const auto start_time = std::chrono::steady_clock::now();
  const Args args(argv, FlagsOf("calibrate"));
  const std::string site_path = args.OnlyPositional("SITE.json");
  const std::string obs_path = args.Get("observations");
  std::vector<calibrate::Method> methods = calibrate::CalibrationOptions{}.methods;
  MethodsFromArgs(args, &methods);
  if (args.Flag("resume") && args.Flag("force"))
    throw InputError("arguments", "give --resume or --force, not both");

  sites::Site site = sites::LoadSite(site_path);
  // --no-forest: the same site bare, its scar trees compared as trees off
  // the forest (docs/reference/observations-file.md).
  if (args.Flag("no-forest")) {
    site.scene.forest = core::Forest{};
    site.calibrate.erase(std::remove_if(site.calibrate.begin(), site.calibrate.end(),
                                        [](const sites::ParameterBound& b) {
                                          return core::FindMaterialField(b.name)->forest;
                                        }),
                         site.calibrate.end());
  }
  const std::string out = OutFolder(args, site_path, "calibrate");
  calibrate::CalibrationOptions options = OptionsFromArgs(args, out);
  options.methods = methods;
  const observations::Observations obs = observations::LoadObservations(obs_path, site.scene);
  PrintWarnings(sites::IdenticalCopyWarnings(site.scene));
  PrintWarnings(observations::DuplicateRunWarnings(obs));
  PrintNotes(site.resampled, args.Flag("quiet"));
  PosteriorFromArgs(args, &options);
  calibrate::CheckCalibration(site, options);  // before the folder is made
  const int folds = args.Has("holdout") ? static_cast<int>(args.Integer("holdout", 0, 2, 1000)) : 0;
  if (folds > 0) observations::MakeFolds(obs, folds, 0);  // enough values for the folds?

  // Rank 0 prepares the folder; under mpirun the other ranks replay the
  // same evaluation logs from copies in a scratch folder of their own and
  // write their (discarded) files there.
  RunInputs inputs;
  inputs.Add(site).Add(obs);
  const bool quiet = args.Flag("quiet");
  std::optional<Progress> progress;
  calibrate::CalibrationCallbacks callbacks =
      ProgressCallbacks(quiet, options.method.max_evals, &progress,
                        args.Has("rocks") ? " in one stage (--rocks: no refining stage)" : "");
  std::optional<reports::ResumableOutputDir> dir;  // locked for the life of the run
  PrepareCalibrationFolder(
      args, out, inputs, "calibrate", "calibration.json",
      [&] { calibrate::CheckResume(site, obs, options, folds); }, &dir, &callbacks);
  const std::string folder = RankCalibrationFolder(out);
  options.log_path = folder + "/evaluations.jsonl";
  callbacks.posterior = PosteriorProgressPrinter(quiet, &progress);
  calibrate::CalibrationSummary summary;
  std::optional<calibrate::HoldoutSummary> holdout;
  ContinuableRun(out, [&] {
    summary = calibrate::Calibrate(site, obs, options, callbacks);
    // The folds after the full calibration: its log exists first, so that a
    // stopped run resumes.
    if (folds > 0) {
      holdout = calibrate::CrossValidate(site, obs, options, folds, callbacks);
      if (!quiet) {
        std::printf("holdout, %d folds: misfit in sample %.4g, held out %.4g (means)", folds,
                    holdout->mean_in_sample_misfit, holdout->mean_held_out_misfit);
        if (holdout->mean_runout_error_m)
          std::printf("; runout error held out %.3g m", *holdout->mean_runout_error_m);
        std::printf("\n");
        if (holdout->repeat_scatter)
          std::printf("  %s\n", holdout->repeat_scatter->Sentence().c_str());
      }
    }
    // The rasters: asked for, or by default for a site read from GIS files.
    reports::WriteCalibrationFolder(folder, site, obs, summary, holdout,
                                    args.Flag("rasters") || site.gis);
  });
  if (!quiet)
    PrintCalibration(
        out, summary, holdout.has_value(), RastersWritten(args.Flag("rasters"), site),
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count());
  return 0;
}

}  // namespace rockcal::cli
