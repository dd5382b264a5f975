// Exact free flight (docs/physics.md, Integration): with no contact force a rock's
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

// Largest turn [rad] of a sub-step of the torque-free rotation of
// non-isotropic clusters in flight. The fourth-order splitting's error falls
// as its fourth power: a box (1 x 0.7 x 0.4 m) turning at 9 rad/s for 1 s
// ends 8e-7 rad from the exact orientation with its energy within 5e-8 at
// 0.05 rad (the midpoint rule at 5e-4 s before it: 4.5e-6 rad, 1.6e-7, with
// ten times the sub-steps).
inline constexpr double kFlightRotationAngle = 0.05;

// Torque-free rotation of a cluster for tau: its angular momentum stays
// fixed in the world (exactly, but for rounding). An isotropic body keeps w;
// others take sub-steps of at most `max_angle` of turn, each the symmetric
// splitting of the kinetic energy into its three principal terms (each term's
// flow is an exact turn about its principal axis) composed to fourth order,
// so that the energy error stays bounded rather than drifting. inv_inertia:
// the body's principal moments inverted.
void RotateFree(const RockBody& body, const Eigen::Vector3d& inv_inertia, double tau,
                double max_angle, RockState* s);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_FLIGHT_H_
