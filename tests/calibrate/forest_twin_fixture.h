// The forest twin (#52): the twin slope of twin_fixture.h as a site file
// with a stand over its runout; scars at the most struck stems and stop
// points simulated through the stand at hidden runout hardness and
// roughness, then calibrated with the forest and with it left out as
// `rockcal calibrate --no-forest` leaves it. Shared by
// forest_twin_heavy_test.cc and bench/forest_twin.cc.
#ifndef ROCKCAL_TESTS_CALIBRATE_FOREST_TWIN_FIXTURE_H_
#define ROCKCAL_TESTS_CALIBRATE_FOREST_TWIN_FIXTURE_H_

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate::testing {

// The hidden runout hardness and roughness [m], and their calibrate bounds.
inline const std::vector<double> kForestHidden = {0.3, 0.3};
inline constexpr double kForestRange[2][2] = {{0.1, 0.6}, {0.1, 0.6}};

// 35 degrees from 21 m down to 0 at x = 30 m, flat to 90 m (contact 20 ms);
// spheres of 0.4-0.8 m released at rest at the top; a stand of 600
// stems/ha, DBH 22 +- 6 cm, over the runout from x = 34 m. The runout starts
// at hardness 0.5 and roughness 0.5 m.
inline std::string ForestTwinSiteJson() {
  return R"({
  "name": "forest twin", "units": "si",
  "surface": {"resolution": 2, "sphere_spacing": 2,
              "points": [[0, 0, 21.006], [30, 0, 0], [90, 0, 0],
                         [0, 20, 21.006], [30, 20, 0], [90, 20, 0]]},
  "materials": [
    {"id": "slope", "hardness": 0.65, "roughness": 0.25, "contact_time": 0.02},
    {"id": "runout", "hardness": 0.5, "roughness": 0.5, "contact_time": 0.02,
     "zone": [[30, -1], [91, -1], [91, 21], [30, 21]],
     "calibrate": {"hardness": [0.1, 0.6], "roughness": [0.1, 0.6]}}
  ],
  "rocks": [{"count": 100, "shape": "sphere", "size": [0.4, 0.8], "unit_weight": 26,
             "release": {"zone": [[1, 8], [4, 8], [4, 12], [1, 12]], "height": 0}}],
  "forest": {"stands": [{"zone": [[34, 1], [88, 1], [88, 19], [34, 19]],
                         "stems_per_ha": 600, "dbh_mean_cm": 22, "dbh_sd_cm": 6,
                         "conifer_percent": 50}]},
  "simulation": {"seed": 1, "max_time": 20}
})";
}

struct ForestTwin {
  std::string dir;
  sites::Site site, bare;    // bare: as calibrate --no-forest makes it
  std::string observations;  // the observations file
  int stems_struck = 0, scars = 0, stopped = 0;
};

// Writes the site and the observations of `hidden_rocks` rocks at the
// hidden values (seed 11) into a fresh folder of /tmp named with `tag` and
// the process id: the heights of every strike on the `scarred` most struck
// stems (ties to the lower index), at each stem's axis and radius, and the
// stop points, with errors 0.1 m and 1 m (no noise added).
inline ForestTwin MakeForestTwin(const std::string& tag, int hidden_rocks, int scarred) {
  namespace fs = std::filesystem;
  ForestTwin t;
  t.dir = (fs::temp_directory_path() / ("rockcal_" + tag + "_" + std::to_string(getpid())))
              .string();
  fs::remove_all(t.dir);
  fs::create_directories(t.dir);
  std::ofstream(t.dir + "/site.json") << ForestTwinSiteJson();
  t.site = sites::LoadSite(t.dir + "/site.json");
  t.bare = t.site;
  t.bare.scene.forest = core::Forest{};
  core::Scene scene = t.site.scene;
  ParameterSpace::FromSite(t.site).Apply(kForestHidden, &scene);
  scene.options.seed = 11;
  scene.groups[0].count = hidden_rocks;
  scene.options.record.tree_strikes = true;
  const core::SimulationResult sim = core::Simulate(scene);
  std::map<int, std::vector<double>> strikes;
  for (const core::RockRecord& r : sim.rocks)
    for (const core::TreeStrike& s : r.strikes) strikes[s.tree].push_back(s.height);
  std::vector<int> stems;
  for (const auto& [stem, heights] : strikes) stems.push_back(stem);
  std::stable_sort(stems.begin(), stems.end(), [&](int a, int b) {
    return strikes[a].size() > strikes[b].size();
  });
  stems.resize(std::min(stems.size(), static_cast<std::size_t>(scarred)));
  t.stems_struck = static_cast<int>(strikes.size());
  nlohmann::json trees = nlohmann::json::array();
  for (const int k : stems) {
    const core::Stem& s = t.site.scene.forest.stems[static_cast<std::size_t>(k)];
    trees.push_back({{"x", s.x}, {"y", s.y}, {"radius", s.dbh / 2}, {"heights", strikes[k]}});
    t.scars += static_cast<int>(strikes[k].size());
  }
  nlohmann::json stops = nlohmann::json::array();
  for (const core::RockRecord& r : sim.rocks)
    if (r.outcome == core::Outcome::kStopped) stops.push_back({r.stop.x(), r.stop.y()});
  t.stopped = static_cast<int>(stops.size());
  const nlohmann::json obs = {
      {"units", "si"},
      {"tree_scars", {{{"trees", trees}}}},
      {"runout",
       {{"stop_points", stops},
        {"from", {2.5, 10}},
        {"direction", {1, 0}},
        {"stopped_fraction", static_cast<double>(t.stopped) / hidden_rocks},
        {"observed_rocks", hidden_rocks}}},
      {"error", {{"height", 0.1}, {"runout", 1.0}}}};
  t.observations = t.dir + "/observations.json";
  std::ofstream(t.observations) << obs.dump(1);
  return t;
}

// The calibration `rockcal calibrate --rocks N --estimate smoothed` runs (a
// reach check of the box, then BOBYQA from its best point, the smoothed
// estimate) in one stage without the noise checks, at `seed`: the
// calibrated values.
inline std::vector<double> CalibrateForestTwin(const sites::Site& site,
                                               const std::string& observations, int rocks,
                                               int max_evals, std::uint64_t seed,
                                               int threads = 0) {
  CalibrationOptions options;
  options.rocks = rocks;
  options.seed = seed;
  options.threads = threads;
  options.refine_factor = 1;
  options.noise_raise = 1;
  options.noise_check_seeds = 0;
  options.noise_seeds = 0;
  options.method.max_evals = max_evals;
  options.method.estimate = Estimate::kSmoothed;
  const CalibrationSummary s =
      Calibrate(site, observations::LoadObservations(observations, site.scene), options);
  return s.methods[static_cast<std::size_t>(s.best)].best;
}

// (x[k] - hidden) / range, signed.
inline double ForestRangeError(const std::vector<double>& x, int k) {
  return (x[static_cast<std::size_t>(k)] - kForestHidden[static_cast<std::size_t>(k)]) /
         (kForestRange[k][1] - kForestRange[k][0]);
}

}  // namespace rockcal::calibrate::testing

#endif  // ROCKCAL_TESTS_CALIBRATE_FOREST_TWIN_FIXTURE_H_
