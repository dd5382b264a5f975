// rockcal calibrate: search the calibrated parameters of a site until its
// simulation matches the observations, and write the tables and the trace.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "args.h"
#include "commands.h"
#include "progress.h"
#include "rockcal/calibrate/calibration.h"
#include "rockcal/core/error.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// Prepares DIR: a new folder, or (with --resume) the folder of a stopped run,
// or (with --force) a replaced one. Nothing is removed without --force, and
// --force replaces only a folder rockcal wrote that holds none of `inputs`
// (reports::CheckOutputFolder). Files a killed run left half-written are
// removed, and so is calibration.json, which marks the folder complete: it is
// written again, after parameters.json, when the calibration finishes.
void PrepareFolder(const std::string& out, bool resume, bool force, const sites::Site& site,
                   const std::string& obs_path) {
  std::vector<std::string> inputs = site.input_files;
  inputs.push_back(obs_path);
  std::error_code ec;
  if (resume) {
    if (out.empty() || !fs::exists(out + "/evaluations.jsonl", ec))
      throw InputError(out, "nothing to resume: no evaluations.jsonl in this folder");
    reports::CheckOutputAgainstInputs(out, inputs);
    reports::RemoveStaleTemporaries(out, "");
    fs::remove(out + "/calibration.json", ec);
    if (ec) throw InputError(out, "cannot remove the old calibration.json: " + ec.message());
    reports::WriteOutputMarker(out, "calibrate", std::nullopt);
    return;
  }
  if (!force && fs::exists(out, ec))
    throw InputError(out,
                     "output folder exists already (give --force to replace it, or "
                     "--resume to continue the calibration it holds)");
  reports::CheckOutputFolder(out, force, inputs);
  if (fs::exists(out, ec)) {
    fs::remove_all(out, ec);
    if (ec) throw InputError(out, "cannot remove the old output folder: " + ec.message());
  }
  if (!fs::create_directory(out, ec))
    throw InputError(out, "cannot create the output folder: " + ec.message());
  reports::WriteOutputMarker(out, "calibrate", std::nullopt);
}

}  // namespace

int Calibrate(const std::vector<std::string>& argv) {
  const auto start_time = std::chrono::steady_clock::now();
  const Args args(argv, {"force", "quiet", "resume"},
                  {"observations", "method", "methods", "max-evals", "max-seconds", "rocks", "seed",
                   "threads", "loss", "estimate", "out"});
  const std::string site_path = args.OnlyPositional("SITE.json");
  const std::string out = args.Get("out");
  const std::string obs_path = args.Get("observations");
  if (args.Has("method") && args.Has("methods"))
    throw InputError("arguments", "give --method or --methods, not both");
  std::vector<std::string> methods =
      args.Has("methods") ? SplitList(args.Get("methods"))
                          : std::vector<std::string>{args.Get("method", "nlopt:bobyqa")};
  if (methods.empty()) throw InputError("argument --methods", "expected a comma separated list");
  for (const std::string& m : methods)
    if (!calibrate::IsMethod(m))
      throw InputError("argument --method" + std::string(args.Has("methods") ? "s" : ""),
                       "unknown method '" + m + "' (allowed: " + calibrate::MethodList() + ")");
  if (args.Flag("resume") && args.Flag("force"))
    throw InputError("arguments", "give --resume or --force, not both");

  sites::Site site = sites::LoadSite(site_path);
  core::Scene& scene = site.scene;
  if (args.Has("rocks")) scene.SetTotalRocks(static_cast<int>(args.Integer("rocks", 0, 1, 10000000)));
  if (args.Has("seed"))
    scene.options.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, 1L << 62));
  scene.options.threads = static_cast<int>(args.Integer("threads", 0, 0, 1024));
  const observations::Observations obs = observations::LoadObservations(obs_path, scene);
  const calibrate::ParameterSpace space = calibrate::ParameterSpace::FromSite(site);

  calibrate::MethodOptions options;
  options.max_evals = static_cast<int>(args.Integer("max-evals", 100, 2, 1000000));
  options.max_seconds = args.Number("max-seconds", 0.0, 0.0, 1e9);
  options.seed = scene.options.seed;
  options.ceres_loss = args.Get("loss", "none");
  options.estimate = args.Get("estimate", "lowest");
  std::string error;
  if (!options.IsValid(&error)) throw InputError("arguments", error);

  PrepareFolder(out, args.Flag("resume"), args.Flag("force"), site, obs_path);
  const calibrate::Objective objective(scene, space, obs, observations::MisfitOptions{});
  calibrate::EvaluationLog log(out + "/evaluations.jsonl", args.Flag("resume"), space,
                               scene.options.seed, scene.total_rocks());

  reports::CalibrationRecord record;
  record.site = scene.name;
  record.units = site.units;
  record.grid_spacing_m = scene.grid.spacing;
  record.space = space;
  record.rocks = scene.total_rocks();
  record.seed = scene.options.seed;
  record.start = space.Current(scene);
  record.misfit_before = objective.Evaluate(record.start);
  const bool quiet = args.Flag("quiet");
  if (!quiet)
    std::printf("%s: %d parameters, %d rocks per evaluation, misfit at the start %.4g\n",
                scene.name.c_str(), space.size(), record.rocks, record.misfit_before.value);
  for (const std::string& method : methods) {
    Progress progress("calibrate " + method, quiet);
    const calibrate::MethodResult result = calibrate::RunMethod(
        method, objective, record.start, options, &log,
        [&](const calibrate::Evaluation& e, double best) {
          char extra[96];
          std::snprintf(extra, sizeof extra, " best misfit %.4g, %.0f s", best, e.elapsed);
          progress.Update(e.index, options.max_evals, extra);
        });
    if (!quiet)
      std::printf("  %-18s misfit %.4g after %d evaluations (%d simulated) in %.1f s: %s\n",
                  method.c_str(), result.best_misfit, result.evaluations, result.simulated,
                  result.wall_seconds, result.termination.c_str());
    record.methods.push_back(result);
  }
  for (std::size_t k = 1; k < record.methods.size(); ++k)
    if (record.methods[k].best_misfit < record.methods[static_cast<std::size_t>(record.best)].best_misfit)
      record.best = static_cast<int>(k);
  const calibrate::MethodResult& best = record.methods[static_cast<std::size_t>(record.best)];
  if (best.best.empty()) throw std::runtime_error("no evaluation finished; nothing to report");

  // The full simulation at the calibrated values (everything recorded).
  core::Scene calibrated = scene;
  space.Apply(best.best, &calibrated);
  calibrated.options.record = observations::RequiredRecording(obs, calibrated.options.record);
  calibrated.options.record.partitions = true;
  calibrated.options.record.passages = true;  // the report's density map
  calibrated.options.record.trajectories = std::min(calibrated.total_rocks(), 30);  // its profile
  const core::SimulationResult sim = core::Simulate(calibrated);
  record.misfit_after = observations::ComputeMisfit(obs, calibrated, sim);
  record.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();

  core::Scene written = calibrated;  // no trajectories.csv: the trajectories are for the report
  written.options.record.trajectories = 0;
  reports::WriteSimulationFiles(out, written, sim);
  reports::WriteFileAtomically(out + "/parameters.json", reports::ParametersJson(record).dump(2) + "\n");
  reports::WriteFileAtomically(out + "/parameters.csv", reports::ParametersCsv(record));
  reports::WriteFileAtomically(out + "/parameters.md", reports::ParametersMarkdown(record));
  reports::WriteFileAtomically(out + "/trace.csv", reports::TraceCsv(record));
  reports::WriteFileAtomically(out + "/calibration.json",
                               reports::CalibrationJson(record).dump(2) + "\n");
  reports::ReportInput report = SiteReport(site, calibrated, sim);
  report.calibration = &record;
  report.observations = &obs;
  reports::WriteFileAtomically(out + "/report.html", reports::HtmlReport(report));
  if (record.methods.size() > 1) {
    reports::WriteFileAtomically(out + "/comparison.csv", reports::ComparisonCsv(record));
    reports::WriteFileAtomically(out + "/comparison.md", reports::ComparisonMarkdown(record));
  }
  if (!quiet) {
    std::printf("\n%s", reports::ParametersMarkdown(record).c_str());
    if (record.methods.size() > 1) std::printf("\n%s", reports::ComparisonMarkdown(record).c_str());
    std::printf("\nwrote %s/ in %.1f s: parameters.{json,csv,md}, trace.csv, calibration.json, "
                "evaluations.jsonl, summary.json, rocks.csv, report.html%s\n",
                out.c_str(), record.wall_seconds,
                record.methods.size() > 1 ? ", comparison.{csv,md}" : "");
  }
  return 0;
}

}  // namespace rockcal::cli
