// Exact free flight (DESIGN.md, Integration): with no contact force a rock's
// centre follows a parabola and a cluster turns torque-free, so a flight is
// advanced in one go up to the next possible contact. Internal to core.
#ifndef ROCKCAL_CORE_SRC_FLIGHT_H_
#define ROCKCAL_CORE_SRC_FLIGHT_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rock_state.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// The longest time the bounding sphere (radius rb) of a rock in state s can
// fly, gravity g along -z, before it may come down to the highest obstacle
// under its swept footprint: at most the time to cross one grid spacing
// horizontally, and 1 s; 0 when it is not above that obstacle.
double CeilingFlightTime(const Terrain& terrain, const RockState& s, double rb, double g);

// The time to cover a distance d from `speed`, speeding up at g: no point
// of a rock moves further than d in a flight this long.
double GapFlightTime(double d, double speed, double g);

// Advances the centre of s by tau on the parabola under `gravity`, and its time.
void FlyCentre(const Eigen::Vector3d& gravity, double tau, RockState* s);

// Turns the orientation q by the constant angular velocity w for h.
void Rotate(const Eigen::Vector3d& w, double h, Eigen::Quaterniond* q);

// Sub-step of the torque-free rotation of non-isotropic clusters in flight [s].
// The midpoint rule's energy error falls as its square: a tumbling box
// flying 60 m down a cliff was off by 1.3e-6 of its energy at 1e-3 s, by
// 3.5e-7 at 5e-4 s (Simulate.CrossingsInFlightKeepTheEnergyOfATumblingBlock).
inline constexpr double kFlightRotationStep = 5e-4;

// Torque-free rotation of a cluster for tau: its angular momentum stays
// fixed in the world. An isotropic body keeps w; others follow
// w = R I^-1 R^T L in midpoint sub-steps of at most `substep` (no energy is
// pumped in, unlike explicit Euler equations). inv_inertia: the body's
// principal moments inverted.
void RotateFree(const RockBody& body, const Eigen::Vector3d& inv_inertia, double tau,
                double substep, RockState* s);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_FLIGHT_H_
