// The state of one rock as the simulation loop advances it (simulate.cc,
// flight.cc, recording.cc). Internal to core.
#ifndef ROCKCAL_CORE_SRC_ROCK_STATE_H_
#define ROCKCAL_CORE_SRC_ROCK_STATE_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rockcal/core/rock_shape.h"

namespace rockcal::core {

struct RockState {
  Eigen::Vector3d x, v, w;  // centre, velocity, angular velocity (world)
  Eigen::Quaterniond q;     // body -> world (clusters only)
  double t;
};

// Rotational kinetic energy of `body` in state s. kCluster: with its
// orientation and principal inertia; otherwise a sphere's (isotropic).
template <bool kCluster>
double RotationalEnergy(const RockBody& body, const RockState& s) {
  if constexpr (kCluster) {
    const Eigen::Vector3d wb = s.q.conjugate() * s.w;
    return 0.5 * wb.dot(body.inertia.cwiseProduct(wb));
  }
  return 0.5 * body.inertia.x() * s.w.squaredNorm();
}

// Kinetic energy, translational plus rotational.
template <bool kCluster>
double KineticEnergy(const RockBody& body, const RockState& s) {
  return 0.5 * body.mass * s.v.squaredNorm() + RotationalEnergy<kCluster>(body, s);
}

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_ROCK_STATE_H_
