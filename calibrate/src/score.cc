#include "rockcal/calibrate/score.h"

#include <algorithm>

#include "rockcal/calibrate/recording.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/json_reader.h"

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
    const auto it = std::find_if(scene->materials.begin(), scene->materials.end(),
                                 [&](const core::Material& m) { return m.id == p.material; });
    if (it == scene->materials.end()) {
      std::string ids;
      for (const core::Material& m : scene->materials) ids += (ids.empty() ? "" : ", ") + m.id;
      throw InputError(where + ".material",
                       "unknown material '" + p.material + "' (the site's materials: " + ids + ")");
    }
    const std::string value = sites::FormatNumber(p.value);
    if (p.name == "hardness") {
      if (!(p.value >= 0 && p.value <= 1))
        throw InputError(where + ".value", value + ": expected a hardness in [0, 1]");
      it->hardness = p.value;
    } else if (p.name == "roughness") {
      const double max = scene->grid.spacing / 2;
      if (!(p.value >= 0 && p.value <= max * (1 + 1e-9)))
        throw InputError(where + ".value", value + " m: expected a roughness in [0, " +
                                               sites::FormatNumber(max) +
                                               "] m (half the site's grid spacing)");
      it->roughness_m = p.value;
    } else if (p.name == "contact_time") {
      if (!(p.value > 0))
        throw InputError(where + ".value", value + " s: expected a contact time > 0");
      it->contact_time_s = p.value;
    } else if (p.name == "rolling_resistance") {
      if (!(p.value >= 0 && p.value <= 1))
        throw InputError(where + ".value", value + ": expected a rolling resistance in [0, 1]");
      it->rolling_resistance = p.value;
    } else {
      throw InputError(where + ".name",
                       "unknown parameter '" + p.name +
                           "' (expected hardness, roughness, contact_time or rolling_resistance)");
    }
  }
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
  out.simulation = core::Simulate(recorded);
  out.misfit = observations::ComputeMisfit(obs, recorded, out.simulation, misfit);
  return out;
}

}  // namespace rockcal::calibrate
