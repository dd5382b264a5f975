// One simulation of a site scored against observations: the path every
// misfit at given values takes (the end of a calibration, a held-out fold,
// rockcal score).
#ifndef ROCKCAL_CALIBRATE_SCORE_H_
#define ROCKCAL_CALIBRATE_SCORE_H_

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/default_table.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// The site's scene as a run takes it: `rocks` spread over the rock groups (0
// keeps the site's counts), `seed` (unset: the site file's), `threads` (0:
// OpenMP's default).
core::Scene RunScene(const sites::Site& site, int rocks, std::optional<std::uint64_t> seed,
                     int threads);

// Applies the values of a parameters.json (ReadParametersFile) to `scene`
// (its contact time, hardness and roughness; rebuild the terrain after).
// A material the site lacks, or a value the site cannot take (hardness
// outside [0, 1], roughness outside [0, half the grid spacing], contact time
// <= 0) is an InputError naming `parameters.file`, the JSON path
// ($.parameters[k].material or .value), the value and what was expected.
void ApplyParameters(const CalibratedSite& parameters, core::Scene* scene);

// Reads the parameters.json at `path` (or in the folder `path`:
// ReadParametersFile) and applies its values to `scene` (ApplyParameters).
void ApplyParametersFile(const std::string& path, core::Scene* scene);

// What `rockcal score` simulates. Defaults in brackets.
struct ScoreOptions {
  int rocks = 0;  // spread over the rock groups; 0 keeps the site's counts [0], >= 0
  std::optional<std::uint64_t> seed;  // unset: the site file's [unset]
  int threads = 0;                    // 0: OpenMP's default [0], >= 0
  // An earlier calibration's parameters.json (or its folder) whose values
  // the site takes; empty: the site's own values [empty].
  std::string parameters_file;
};

// The site's scene as `options` set it (RunScene, then the parameters
// file). Throws InputError for a parameters file the site cannot take, or
// simulation options that are not valid (naming the site file).
core::Scene ScoreScene(const sites::Site& site, const ScoreOptions& options);

struct ScoreSummary {
  // The scene simulated, recording what a simulation's files need
  // (summary.json, rocks.csv, the misfit); no trajectories.
  core::Scene scene;
  // Its simulation, recorded also for the report (passages, a few trajectories).
  core::SimulationResult simulation;
  observations::Misfit misfit;  // of `simulation` against the observations
};

// Simulates `scene` once (its parameters, rocks and seed as given) and
// computes the misfit against `observations`.
ScoreSummary Score(const core::Scene& scene, const observations::Observations& observations,
                   const observations::MisfitOptions& misfit = {});

// What `rockcal score` records of a score: score.json (to_json and
// from_json below; reports/ writes the file).
struct ScoreResult {
  std::string site;               // the scene's name
  std::string observations_file;  // as given
  // The parameters.json whose values the site took, as given; empty: the
  // site's own values (null in score.json).
  std::string parameters_file;
  int rocks = 0;
  std::uint64_t seed = 0;
  int stopped = 0, left = 0, timeout = 0;  // the rocks' outcomes
  // Its value, penalised and message, the residuals and the measured
  // impacts' fits (the runs' figures and each replay's ratios are not in
  // score.json).
  observations::Misfit misfit;
  // The ids of the rock groups misfit.impacts[i].group indexes (GroupIds of
  // the scene); read back, the groups the impacts name, in order of first mention.
  std::vector<std::string> groups;
};

// The record of `score` with the files it was given (ScoreOptions::parameters_file).
ScoreResult ScoreResultOf(const ScoreSummary& score, const std::string& observations_file,
                          const std::string& parameters_file);

// score.json (calibrate/src/results_json.cc).
void to_json(nlohmann::json& j, const ScoreResult& result);
void from_json(const nlohmann::json& j, ScoreResult& result);
// The residuals of `misfit` as score.json and calibration.json list them:
// observation, quantity, simulated, observed, sigma and residual of each.
nlohmann::json ResidualsJson(const observations::Misfit& misfit);
// The measured impacts' fits as score.json and calibration.json hold them
// ("impacts", SI; docs/reference/outputs.md#impactscsv): {"verdict":
// observations::ImpactVerdict, "per_impact": [{id, group, incidence_deg,
// normal, observed_mps, simulated_median_mps, speed_sd_mps, draws, left,
// normal_ratio: {observed, simulated, spread, sigma}, tangential_ratio:
// {...}}]}; null figures where undefined; `group` is group_ids[group] (the
// index where that id is empty or missing).
nlohmann::json ImpactsJson(const observations::Misfit& misfit,
                           const std::vector<std::string>& group_ids);
// The ids of the scene's rock groups, in order.
std::vector<std::string> GroupIds(const core::Scene& scene);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_SCORE_H_
