// The ends of a rock's run and the energy check (docs/design.md, the loop's
// "test the ends"): it left the slope, went through it, stopped, or came to
// rest; and the relative energy gain a stable step never shows. Internal to
// core (simulate.cc).
#ifndef ROCKCAL_CORE_SRC_REST_H_
#define ROCKCAL_CORE_SRC_REST_H_

#include <Eigen/Core>
#include <algorithm>

#include "rock_state.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// A rock is still while every point of it is slower than this fraction of
// the stop speed (SimulationOptions::rest_window).
inline constexpr double kStillSpeed = 0.1;

// Watches one rock's run, advance after advance.
class RockEnds {
 public:
  // rest_window: SimulationOptions::rest_window, 0 on the reference path;
  // max_contact_time: the longest contact time of the scene's materials.
  RockEnds(const SimulationOptions& opt, const Terrain& terrain, const RockBody& body,
           double rest_window, double max_contact_time)
      : opt_(opt),
        terrain_(terrain),
        body_(body),
        rest_window_(rest_window),
        max_contact_time_(max_contact_time) {}

  // At release: the rock's energy, and the floor of the kinetic energy
  // the energy gain is measured against.
  void Start(double energy, double scale_floor) {
    energy_min_ = energy;
    ke_max_ = scale_floor;
    slow_since_ = -1.0;
    below_since_ = -1.0;
  }

  // After an advance that began at t0 and ended in state s over grid cell
  // `cell`: sets *outcome and returns true when the rock has left the
  // slope, gone through it (rec->tunneled), or stopped. floor_clear: its
  // bounding sphere is known to clear the floor (ContactSearch::FloorClear).
  bool Ended(const RockState& s, int cell, double t0, bool floor_clear, Outcome* outcome,
             RockRecord* rec) {
    if (!terrain_.CellOnSlope(cell)) {
      *outcome = Outcome::kLeft;
      return true;
    }
    // Below the floor by more than its radius: a hard impact of a small
    // rock overlaps for less than a contact time (about v t_c / pi deep,
    // whatever its size); a rock still there after two has gone through.
    // A rock whose bounding sphere is known to clear the floor is not below it.
    if (!floor_clear && terrain_.FloorHeight(s.x.x(), s.x.y()) - s.x.z() > body_.bounding_radius) {
      if (below_since_ < 0) below_since_ = t0;
      if (s.t - below_since_ > 2.0 * max_contact_time_) {
        rec->tunneled = true;
        *outcome = Outcome::kLeft;
        return true;
      }
    } else {
      below_since_ = -1.0;
    }
    if (s.v.norm() < opt_.stop_speed) {
      if (slow_since_ < 0) slow_since_ = t0;
      if (s.t - slow_since_ >= opt_.stop_duration) {
        *outcome = Outcome::kStopped;
        return true;
      }
    } else {
      slow_since_ = -1.0;
    }
    return false;
  }

  // After an advance that began at t0 and ended in state s: true when the
  // rock is at rest (SimulationOptions::rest_window), so it would stay slow
  // until its slow spell reaches stop_duration, within max_time. flew: the
  // advance was a flight; touching: the rock has contacts; sliding: one of
  // them slid or carried no load.
  bool AtRest(const RockState& s, bool flew, bool touching, bool sliding, double t0) {
    if (!(rest_window_ > 0.0)) return false;
    const double speed = s.v.norm() + s.w.norm() * body_.bounding_radius;  // of any point
    const double still = kStillSpeed * opt_.stop_speed;
    if (flew || !touching || sliding || !(speed < still)) {
      still_since_ = -1.0;
      return false;
    }
    if (still_since_ < 0) {
      still_since_ = t0;
      still_speed_ = speed;
    }
    // Slower than when it became still: not speeding up out of a balance
    // (a block tipping over an edge it came to rest on).
    return s.t - still_since_ >= rest_window_ && speed < still_speed_ && slow_since_ >= 0 &&
           slow_since_ + opt_.stop_duration <= opt_.max_time;
  }
  // Since when the rock has been slow (-1: it is not).
  double slow_since() const { return slow_since_; }

  // The energy check after a contact step: e the mechanical energy with
  // the springs', ke the kinetic energy; a rise above the lowest energy so
  // far, relative to the largest kinetic energy, goes to
  // rec->max_relative_energy_gain.
  void CheckEnergy(double e, double ke, RockRecord* rec) {
    ke_max_ = std::max(ke_max_, ke);
    if (e < energy_min_) {
      energy_min_ = e;
    } else {
      rec->max_relative_energy_gain =
          std::max(rec->max_relative_energy_gain, (e - energy_min_) / ke_max_);
    }
  }

 private:
  const SimulationOptions& opt_;
  const Terrain& terrain_;
  const RockBody& body_;
  const double rest_window_;
  const double max_contact_time_;
  double energy_min_ = 0.0, ke_max_ = 0.0;
  // Since when the rock has been slow, and below the floor (-1: it is not).
  double slow_since_ = -1.0, below_since_ = -1.0;
  // Since when the rock has been still (AtRest; -1: it is not), and its speed then.
  double still_since_ = -1.0, still_speed_ = 0.0;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_REST_H_
