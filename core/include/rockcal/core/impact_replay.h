// Observed impacts replayed on the production contact path
// (docs/physics.md, "Replayed impacts"): each impact's rock set just clear of
// the ground on its incoming path, at its incoming velocity, with a drawn
// orientation (and spin unless measured), run until it is in flight again.
#ifndef ROCKCAL_CORE_IMPACT_REPLAY_H_
#define ROCKCAL_CORE_IMPACT_REPLAY_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// The longest a replayed rock may stay on the ground: a rock still touching
// this long after its first contact rolls or slides on, and its velocity
// then is its rebound (ImpactRebound::left 0).
constexpr double kReplayContactSeconds = 0.25;

// The unit normal, out of the ground, of the triangulated surface at (x, y)
// by central differences over one grid spacing (one-sided at the edges and
// next to holes), as the virtual spheres are placed (docs/physics.md,
// "Terrain and virtual spheres"); false off the slope.
bool GroundNormal(const Terrain& terrain, double x, double y, Eigen::Vector3d* normal);

// A rebound's ratios to the incoming velocity about the ground's unit normal
// n: normal = -v_out.n / v_in.n, tangential = v_out.t / |v_in,t| with t the
// unit direction of the incoming tangential velocity (NaN when that is below
// kMinTangentialShare of the incoming speed: a near-normal impact).
struct ReboundRatios {
  double normal = 0.0, tangential = 0.0;
};
constexpr double kMinTangentialShare = 0.05;
ReboundRatios RatiosOf(const Eigen::Vector3d& v_in, const Eigen::Vector3d& v_out,
                       const Eigen::Vector3d& n);

// Each impact's draws (one ImpactRebound per impact, in order). Draw d of
// impact i takes the random stream (scene seed, 2^63 + 2^20 i + d): its size
// in the group's range, its orientation (uniform), and its spin unless
// measured (about n x t, the rolling axis, of a uniform share of the rolling
// spin |v_in,t| / bounding radius). Deterministic at any thread count.
std::vector<ImpactRebound> ReplayImpacts(const Scene& scene, const Terrain& terrain,
                                         const std::vector<ImpactReplay>& impacts);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_IMPACT_REPLAY_H_
