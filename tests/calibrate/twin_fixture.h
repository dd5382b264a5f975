// A small synthetic site for calibration tests: a 35-degree slope ("slope")
// onto a flat runout ("runout"), spheres released at the top, a partition on
// the slope. Observations are drawn from a simulation at known parameters.
#ifndef ROCKCAL_TESTS_CALIBRATE_TWIN_FIXTURE_H_
#define ROCKCAL_TESTS_CALIBRATE_TWIN_FIXTURE_H_

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate::testing {

// The twin's true values (slope hardness, slope roughness, runout hardness,
// runout roughness), inside the bounds of TwinSite's calibrate list.
inline const std::vector<double> kTruth = {0.65, 0.25, 0.2, 0.45};

inline sites::Site TwinSite(int rocks) {
  sites::Site site;
  site.path = "twin";
  site.units = sites::Units::kSI;
  core::Scene& scene = site.scene;
  scene.name = "twin";
  const double s = 2.0, theta = 35.0 * M_PI / 180.0;
  scene.grid.spacing = s;
  scene.grid.nx = 46;  // 90 m
  scene.grid.ny = 11;  // 20 m
  for (int j = 0; j < scene.grid.ny; ++j)
    for (int i = 0; i < scene.grid.nx; ++i) {
      const double x = i * s;
      scene.grid.z.push_back(x < 30.0 ? (30.0 - x) * std::tan(theta) : 0.0);
      scene.grid.material.push_back(x < 30.0 ? 0 : 1);
    }
  core::Material slope;
  slope.id = "slope";
  slope.hardness = 0.5;
  slope.roughness_m = 0.3;
  core::Material runout;
  runout.id = "runout";
  runout.hardness = 0.3;
  runout.roughness_m = 0.3;
  // A long contact (20 ms) keeps the test cheap: 4x fewer steps than 5 ms.
  slope.contact_time_s = runout.contact_time_s = 0.02;
  scene.materials = {slope, runout};
  scene.partitions = {{"P", core::Partition::Kind::kX, 20.0}, {"Q", core::Partition::Kind::kX, 40.0}};
  core::RockGroup g;
  g.count = rocks;
  g.shape = core::Shape::kSphere;
  g.size_min = 0.4;
  g.size_max = 0.8;
  g.unit_weight = 26e3;
  g.release.zone = {{1, 8}, {4, 8}, {4, 12}, {1, 12}};
  scene.groups = {g};
  scene.options.max_time = 20.0;
  site.calibrate = {{"slope", "hardness", 0.2, 0.8, "slope"},
                    {"slope", "roughness", 0.1, 0.6, "slope"},
                    {"runout", "hardness", 0.1, 0.6, "runout"},
                    {"runout", "roughness", 0.1, 0.6, "runout"}};
  return site;
}

// Observations of bounce heights at P and of stop points, from a simulation
// of `site` at `truth` with `seed`. With `runs`, each rock group is one
// tracked run (its first rock, released from the group's release point):
// the stop points are the runs' (Runout::run_ids "run1", ..., their
// distances from their own release), and a run whose rock did not stop is
// left out (the stopped share counts it).
inline observations::Observations TwinObservations(const sites::Site& site,
                                                   const std::vector<double>& truth,
                                                   std::uint64_t seed, bool runs = false) {
  core::Scene scene = site.scene;
  ParameterSpace::FromSite(site).Apply(truth, &scene);
  scene.options.seed = seed;
  const core::SimulationResult sim = core::Simulate(scene);
  observations::Observations obs;
  obs.units = sites::Units::kSI;
  observations::ScarSet scars, runout_scars;
  scars.label = "tree_scars[0] P";
  scars.partition = 0;
  runout_scars.label = "tree_scars[1] Q";
  runout_scars.partition = 1;
  observations::Runout runout;
  for (const auto& r : sim.rocks) {
    if (r.crossings[0].crossed) scars.heights.push_back(r.crossings[0].height);
    if (r.crossings[1].crossed) runout_scars.heights.push_back(r.crossings[1].height);
    if (r.outcome != core::Outcome::kStopped) continue;
    runout.stop_points.emplace_back(r.stop.x(), r.stop.y());
    if (!runs) continue;
    runout.run_ids.push_back("run" + std::to_string(r.group + 1));
    runout.run_groups.push_back(r.group);
    runout.run_origins.push_back(scene.groups[static_cast<std::size_t>(r.group)].release.point);
  }
  // The observed share of stopped rocks: the field would see the others go.
  runout.observed_rocks = static_cast<int>(sim.rocks.size());
  runout.stopped_fraction =
      static_cast<double>(runout.stop_points.size()) / static_cast<double>(sim.rocks.size());
  runout.from = Eigen::Vector2d(2.5, 10.0);
  runout.direction = Eigen::Vector2d(1.0, 0.0);
  for (std::size_t i = 0; i < runout.stop_points.size(); ++i) {
    const Eigen::Vector2d& p = runout.stop_points[i];
    if (runs) {
      runout.distances.push_back((p - runout.run_origins[i]).norm());
      continue;
    }
    runout.distances.push_back(runout.Distance(p));
    runout.lateral.push_back(runout.Lateral(p));
  }
  obs.tree_scars = {scars, runout_scars};
  obs.runout = runout;
  obs.error.height = 0.1;
  obs.error.runout = 1.0;
  return obs;
}

}  // namespace rockcal::calibrate::testing

#endif  // ROCKCAL_TESTS_CALIBRATE_TWIN_FIXTURE_H_
