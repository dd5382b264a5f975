// The production path's part of a replayed impact (impact_replay.cc): each
// job's rock run from its start until it is in flight again (simulate.cc,
// RockRun::Rebound). Internal to core.
#ifndef ROCKCAL_CORE_SRC_REBOUND_H_
#define ROCKCAL_CORE_SRC_REBOUND_H_

#include <Eigen/Core>
#include <vector>

#include "rock_state.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/scene.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

struct ReboundJob {
  RockBody body;
  RockState start;                                    // clear of the ground, approaching it
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // the ground's at the impact
  double max_time = 0.0;                              // s, the run's end at the latest
  double contact_seconds = 0.0;                       // s after the first contact at the latest
  // Filled by RunRebounds: the velocity when in flight again (or at
  // max_time), and whether it left the ground.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  bool left = false;
};

// Runs every job (in parallel; each job alone, so the same at any thread count).
void RunRebounds(const Scene& scene, const Terrain& terrain, std::vector<ReboundJob>* jobs);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_REBOUND_H_
