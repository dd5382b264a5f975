#include "rockcal/calibrate/score.h"

#include "rockcal/calibrate/recording.h"
#include "rockcal/core/error.h"
#include "rockcal/parallel/parallel.h"
#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

core::Scene RunScene(const sites::Site& site, int rocks, std::optional<std::uint64_t> seed,
                     int threads) {
  core::Scene scene = site.scene;
  if (rocks > 0) scene.SetTotalRocks(rocks);
  if (seed) scene.options.seed = *seed;
  scene.options.threads = threads;
  return scene;
}

void ApplyParameters(const CalibratedSite& parameters, core::Scene* scene) {
  for (std::size_t k = 0; k < parameters.parameters.size(); ++k) {
    const CalibratedParameter& p = parameters.parameters[k];
    const std::string where = parameters.file + ": $.parameters[" + std::to_string(k) + "]";
    std::string message;
    // parameters.json is in SI units.
    switch (
        sites::SetMaterialValue(p.material, p.name, p.value, sites::Units::kSI, scene, &message)) {
      case sites::MaterialValueFault::kNone:
        break;
      case sites::MaterialValueFault::kMaterial:
        throw InputError(where + ".material", message);
      case sites::MaterialValueFault::kField:
        throw InputError(where + ".name", message);
      case sites::MaterialValueFault::kValue:
        throw InputError(where + ".value", sites::FormatNumber(p.value) + ": " + message);
    }
  }
}

void ApplyParametersFile(const std::string& path, core::Scene* scene) {
  ApplyParameters(ReadParametersFile(path), scene);
}

core::Scene ScoreScene(const sites::Site& site, const ScoreOptions& options) {
  core::Scene scene = RunScene(site, options.rocks, options.seed, options.threads);
  if (!options.parameters_file.empty()) ApplyParametersFile(options.parameters_file, &scene);
  std::string error;
  if (!scene.options.IsValid(&error)) throw InputError(site.path, error);
  return scene;
}

ScoreSummary Score(const core::Scene& scene, const observations::Observations& obs,
                   const observations::MisfitOptions& misfit) {
  ScoreSummary out;
  out.scene = scene;
  RecordingNeeds needs;
  needs.observations = &obs;
  needs.partitions = true;
  needs.energy_check = true;
  out.scene.options.record = RecordingFor(out.scene, needs);
  core::Scene recorded = out.scene;
  needs.report = true;
  recorded.options.record = RecordingFor(recorded, needs);
  out.simulation = parallel::Simulate(recorded);
  out.misfit = observations::ComputeMisfit(obs, recorded, out.simulation, misfit);
  return out;
}

ScoreResult ScoreResultOf(const ScoreSummary& score, const std::string& observations_file,
                          const std::string& parameters_file) {
  ScoreResult out;
  out.site = score.scene.name;
  out.observations_file = observations_file;
  out.parameters_file = parameters_file;
  out.rocks = score.scene.total_rocks();
  out.seed = score.scene.options.seed;
  out.stopped = score.simulation.count(core::Outcome::kStopped);
  out.left = score.simulation.count(core::Outcome::kLeft);
  out.timeout = score.simulation.count(core::Outcome::kTimeout);
  out.misfit = score.misfit;
  out.groups = GroupIds(score.scene);
  return out;
}

}  // namespace rockcal::calibrate
