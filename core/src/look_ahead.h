// The free flight's look-ahead near the ground (docs/physics.md, Integration): how
// long a rock close to the terrain can fly before any of its elements may
// touch anything of its neighbourhood (contact_search.h). Internal to core
// (simulate.cc).
#ifndef ROCKCAL_CORE_SRC_LOOK_AHEAD_H_
#define ROCKCAL_CORE_SRC_LOOK_AHEAD_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "contact_search.h"
#include "flight.h"
#include "rock_state.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// A flight near the terrain advances up to this fraction of the gap at a
// time (simulate.cc, kMinFlight).
inline constexpr double kFlightReach = 0.98;

template <bool kCluster>
class FlightLookAhead {
 public:
  FlightLookAhead(const Terrain& terrain, const RockBody& body, const Eigen::Vector3d& gravity)
      : terrain_(terrain), body_(body), gravity_(gravity) {
    // Torque-free, |w| stays within |w0| sqrt(I_max / I_min) (energy and
    // angular momentum are kept), |dw/dt| within (I_max / I_min) |w|^2, so
    // an arm's acceleration |w' x r + w x (w x r)| is at most
    // bend_ |w0|^2 |r|; an isotropic body keeps w (bend_ = 1).
    const double ratio = body.inertia.maxCoeff() / body.inertia.minCoeff();
    spin_growth_ = std::sqrt(ratio);
    bend_ = ratio > 1.0 + 1e-12 ? ratio * (1.0 + ratio) : 1.0;
    g_ = gravity.norm();
    for (const Eigen::Vector3d& e : body.elements) arm_length_.push_back(kCluster ? e.norm() : 0.0);
  }

  // The longest flight from s in which no element can reach
  // anything of the neighbourhood, while the neighbourhood holds (the centre
  // moves less than the skin). Each element's gap to each virtual sphere
  // closes no faster than its own velocity along the line between them
  // allows: the distance to a sphere is convex in the element's position,
  // so it stays above its tangent, gap + n.(displacement), and the
  // displacement is v t + g t^2 / 2 plus the turn of the element's arm, at
  // first w x arm, bending by at most bend_ |w|^2 |arm| (torque-free
  // rotation). An element leaving a sphere is not held back by it, as a
  // bound from the rock's speed alone would (a tumbling block then crept
  // away from each bump in dozens of ever longer flights). The floor (facets
  // and catch surface), where it is within reach, is bounded by each
  // element's speed. 0 when something already touches. moved: the
  // centre's distance from the neighbourhood's centre (UpdateNeighbours).
  double NearFlightTime(const RockState& s, double moved, ContactSearch<kCluster>* search) {
    const double rb = body_.bounding_radius;
    const double v = s.v.norm();
    const double spin = kCluster ? s.w.norm() : 0.0;
    const double speed = v + spin * spin_growth_ * rb;  // of any point of the rock
    const double skin = search->skin();
    double best = GapFlightTime(kFlightReach * (skin - moved), v, g_);
    if constexpr (kCluster) search->ElementCentres(s.x, s.q.toRotationMatrix());
    const double a = body_.element_radius;
    const std::size_t ne = body_.elements.size();
    auto centre = [&](std::size_t e) -> const Eigen::Vector3d& {
      return kCluster ? search->centre(e) : s.x;
    };
    if (search->floor_clear() < skin) {
      for (std::size_t e = 0; e < ne; ++e) {
        const double gap = terrain_.FloorGap(centre(e), a, skin, skin);
        if (!(gap > 0.0)) return 0.0;
        best = std::min(
            best, GapFlightTime(kFlightReach * gap, v + spin * spin_growth_ * arm_length_[e], g_));
      }
    }
    // Per element: its velocity and a bound on how fast its gap to anything
    // can close (speed) and speed up (pull).
    const double bend = bend_ * spin * spin;
    arms_.resize(ne);
    for (std::size_t e = 0; e < ne; ++e) {
      ElementMotion& m = arms_[e];
      m.velocity = s.v + s.w.cross(centre(e) - s.x);
      m.speed = v + spin * arm_length_[e];  // at least |velocity|
      m.pull = bend * arm_length_[e] + g_;
    }
    // A pair whose gap stays open for `best` at the element's bounds cannot
    // shorten the flight and is skipped before any square root: within t the
    // gap closes by at most speed t + pull t^2 / 2. The same test on the
    // bounding sphere skips a sphere whole.
    for (int n : search->near()) {
      const Eigen::Vector3d& c = terrain_.sphere_centre(n);
      const double r = terrain_.sphere_radius(n);
      const double closing = best * (speed + 0.5 * g_ * best);
      const double clear = r + rb + closing;
      if ((s.x - c).squaredNorm() >= clear * clear) continue;
      for (std::size_t e = 0; e < ne; ++e) {
        const ElementMotion& m = arms_[e];
        const Eigen::Vector3d d = centre(e) - c;
        const double reach = r + a + best * (m.speed + 0.5 * m.pull * best) / kFlightReach;
        const double dist2 = d.squaredNorm();
        if (dist2 >= reach * reach) continue;
        const double dist = std::sqrt(dist2);
        const double gap = dist - r - a;
        if (!(gap > 0.0)) return 0.0;
        const Eigen::Vector3d normal = d / dist;
        const double rate = normal.dot(m.velocity);
        const double pull = bend * arm_length_[e] - normal.dot(gravity_);
        best = std::min(best, FirstReach(kFlightReach * gap, rate, pull));
      }
    }
    return best;
  }

  // The first time t > 0 at which d + rate t - pull t^2 / 2 falls to 0
  // (d > 0); infinite when it never does.
  static double FirstReach(double d, double rate, double pull) {
    const double disc = rate * rate + 2.0 * pull * d;
    if (pull > 0.0) return (rate + std::sqrt(disc)) / pull;
    if (rate >= 0.0) return std::numeric_limits<double>::infinity();
    if (pull == 0.0) return d / -rate;
    return disc >= 0.0 ? (rate + std::sqrt(disc)) / pull : std::numeric_limits<double>::infinity();
  }

 private:
  const Terrain& terrain_;
  const RockBody& body_;
  const Eigen::Vector3d gravity_;
  double spin_growth_ = 1.0, bend_ = 1.0;  // bounds of the spin in flight
  double g_ = 0.0;
  struct ElementMotion {
    double speed, pull;
    Eigen::Vector3d velocity;
  };
  std::vector<ElementMotion> arms_;  // per element, for NearFlightTime
  std::vector<double> arm_length_;   // per element, its centre's distance from the rock's
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_LOOK_AHEAD_H_
