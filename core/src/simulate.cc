#include "rockcal/core/simulate.h"

#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include "contact_forces.h"
#include "contact_search.h"
#include "flight.h"
#include "look_ahead.h"
#include "rebound.h"
#include "recording.h"
#include "rest.h"
#include "rock_state.h"
#include "rockcal/core/contact.h"
#include "rockcal/core/impact_replay.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/polygon.h"
#include "rockcal/core/random.h"
#include "stems.h"

namespace rockcal::core {
namespace {

// Free flight near the terrain advances up to kFlightReach (look_ahead.h) of
// the gap at a time, and is worth it while it covers more than kMinFlight of
// a step, so a landing starts within 1 % of a step of the touch (at 5 %, a
// box landing flat on 16 elements rebounded 2.1 % short of its restitution).
constexpr double kMinFlight = 0.01;
// A flight starts from a new neighbourhood once the centre has moved this
// fraction of the skin from where the last one was made (NearFlightTime).
constexpr double kFlightKeep = 0.5;
// A step is redone at most this many times with the shorter step its
// contacts ask for.
constexpr int kMaxRetries = 3;

// Everything a rock needs that is shared by all rocks of the scene.
struct SceneContext {
  const Scene& scene;
  const Terrain& terrain;
  std::vector<ContactLaw> laws;
  Eigen::Vector3d gravity;
  double max_contact_time = 0.0;  // longest contact time of the scene's materials
  // The forest's stems (empty without one) and the index of the trunks'
  // contact law in `laws` (after the materials'; -1 without a forest).
  StemGrid stems;
  int trunk_material = -1;
};

// One rock, from release to its outcome. kCluster selects the rigid-cluster
// path (orientation, full inertia); spheres carry no orientation work.
// kForest: the scene has stems (stems.h); a bare scene does no forest work.
template <bool kCluster, bool kForest>
class RockRun {
 public:
  // steps: the rock's contact steps per material.
  RockRun(const SceneContext& ctx, const RockBody& body, const StepSizes& steps, RockRecord* rec)
      : ctx_(ctx),
        opt_(ctx.scene.options),
        body_(body),
        steps_(steps),
        dt_(steps.finest),
        exact_flight_(opt_.exact_flight && !opt_.reference_path),
        rec_(rec),
        recorder_(ctx.scene, ctx.terrain, body, kCluster, rec),
        ends_(opt_, ctx.terrain, body, opt_.reference_path ? 0.0 : opt_.rest_window,
              ctx.max_contact_time),
        search_(ctx.terrain, body, !opt_.reference_path),
        look_ahead_(ctx.terrain, body, ctx.gravity),
        forces_(ctx.laws, body, steps, ctx.gravity),
        stems_(ctx.stems, body.bounding_radius) {
    inv_inertia_ = body.inertia.cwiseInverse();
    g_ = ctx.gravity.norm();
    if constexpr (kForest) forces_.KeepForces(true);
  }

  // The loop of docs/design.md: advance (an exact flight while nothing is near,
  // a contact step otherwise), record what the advance crossed, and end the
  // rock when it stopped, left the slope or ran out of time.
  void Run(RockState s) {
    Start(s);
    Outcome outcome = Outcome::kTimeout;
    while (s_.t < opt_.max_time) {
      const RockState before = s_;
      const bool flew = Advance();
      if (!s_.x.allFinite() || !s_.v.allFinite() || !s_.w.allFinite()) {
        rec_->max_relative_energy_gain = kInf;  // flagged; the caller counts it
        outcome = Outcome::kLeft;
        break;
      }
      if (recorder_.Advance(before, s_, flew, &caught_)) {  // a barrier stopped it
        s_ = caught_;
        outcome = Outcome::kStopped;
        break;
      }
      const int cell = ctx_.terrain.CellOf(s_.x.x(), s_.x.y());
      if (opt_.record.energy_check && !flew) CheckEnergy();
      if (ends_.Ended(s_, cell, before.t, search_.FloorClear(s_.x), &outcome, rec_)) break;
      if (ends_.AtRest(s_, flew, forces_.touching(), forces_.sliding(), before.t)) {
        s_.t = ends_.slow_since() + opt_.stop_duration;
        outcome = Outcome::kStopped;
        break;
      }
    }
    Finish(outcome);
  }

  // An observed impact replayed (core/impact_replay.h): from s on the
  // production path until the rock has touched the ground and is in flight
  // again, moving away from it along `normal`, or until max_time (or
  // contact_seconds after its first contact, if sooner). Returns
  // true when it left the ground; *velocity is its velocity then.
  bool Rebound(const RockState& s, const Eigen::Vector3d& normal, double max_time,
               double contact_seconds, Eigen::Vector3d* velocity) {
    Start(s);
    bool touched = false, left = false;
    Outcome outcome = Outcome::kTimeout;
    while (s_.t < max_time) {
      Advance();
      if (!s_.x.allFinite() || !s_.v.allFinite() || !s_.w.allFinite()) {
        outcome = Outcome::kLeft;
        break;
      }
      if (forces_.touching()) {
        if (!touched) max_time = std::min(max_time, s_.t + contact_seconds);
        touched = true;
      } else if (touched && s_.v.dot(normal) > 0.0) {
        left = true;
        break;
      }
      if (!ctx_.terrain.OnSlope(s_.x.x(), s_.x.y())) {
        outcome = Outcome::kLeft;
        break;
      }
    }
    Finish(outcome);
    *velocity = s_.v;
    return left;
  }

 private:
  // The state at release, the first accelerations and what is recorded.
  void Start(const RockState& s) {
    s_ = s;
    a_ = ctx_.gravity;
    alpha_.setZero();
    search_.InvalidatePairs();
    UpdateNeighbours();  // and the local contact step, before the first advance
    recorder_.Start(s_);
    const double scale_floor = body_.mass * g_ * body_.bounding_radius;
    ends_.Start(Energy(), scale_floor);
  }

  // One advance: an exact flight up to the next possible contact when
  // nothing touches and the flight is worth it, a contact step otherwise.
  // True for a flight.
  bool Advance() {
    if (!forces_.touching() && exact_flight_) {
      const double tau = std::min(FlightTime(), opt_.max_time - s_.t);
      if (tau > kMinFlight * dt_) {
        Fly(tau);
        landing_ = true;
        ++rec_->flights;
        return true;
      }
    }
    // After a flight the rock is within a small fraction of a step of the
    // terrain: the contact force at the step start is the dashpot's.
    if (landing_ && !forces_.touching()) PrimeLanding();
    landing_ = false;
    ContactStep();
    ++rec_->steps;
    return false;
  }

  // A contact step of the step the last one's contacts asked for (their
  // materials, gentle or not, and how many touch at once), or of the local
  // contact step without contacts. A step whose contacts ask for a shorter
  // one is taken back and redone with that.
  void ContactStep() {
    double dt = NextStep();
    const RockState s0 = s_;
    const Eigen::Vector3d a0 = a_, alpha0 = alpha_;
    Step(dt);
    for (int retry = 0; retry < kMaxRetries; ++retry) {
      const double asked = NextStep();
      if (!(asked < dt)) break;
      s_ = s0;
      a_ = a0;
      alpha_ = alpha0;
      forces_.Undo();             // the contacts before the step
      search_.InvalidatePairs();  // made at the step's end
      ++rec_->retried_steps;
      dt = asked;
      Step(dt);
    }
    rec_->max_penetration =
        std::max(rec_->max_penetration, forces_.deepest() / body_.element_radius);
    if (dt > dt_) ++rec_->gentle_steps;
    if constexpr (kForest) StemWork(dt);
  }
  // The step the last step's contacts ask for, or the local one without.
  double NextStep() const { return forces_.touching() ? forces_.needed_dt() : dt_; }

  void Finish(Outcome outcome) {
    if constexpr (kForest)
      for (StemLoad& l : loads_) CloseStrike(&l, false);
    rec_->outcome = outcome;
    rec_->stop = s_.x;
    rec_->time = s_.t;
    recorder_.Finish(s_);
  }

  Eigen::Matrix3d Rotation() const {
    if constexpr (kCluster) return s_.q.toRotationMatrix();
    return Eigen::Matrix3d::Identity();
  }

  // World angular acceleration from torque (with the gyroscopic term for clusters).
  Eigen::Vector3d AngularAcceleration(const Eigen::Vector3d& torque, const Eigen::Vector3d& w,
                                      const Eigen::Matrix3d& rot) const {
    if constexpr (kCluster) {
      const Eigen::Vector3d wb = rot.transpose() * w;
      const Eigen::Vector3d tb = rot.transpose() * torque;
      const Eigen::Vector3d lb = body_.inertia.cwiseProduct(wb);
      return rot * inv_inertia_.cwiseProduct(tb - wb.cross(lb));
    }
    return torque * inv_inertia_.x();
  }

  double KineticEnergy(const RockState& s) const { return core::KineticEnergy<kCluster>(body_, s); }

  // Mechanical energy including the energy stored in contact springs.
  double Energy() const {
    return KineticEnergy(s_) - body_.mass * ctx_.gravity.dot(s_.x) + forces_.spring_energy();
  }

  void CheckEnergy() {
    const double e = Energy();
    ends_.CheckEnergy(e, KineticEnergy(s_), rec_);
  }

  // Longest time the rock can fly freely from s_ without touching anything
  // (flight.h): the terrain's, cut where it may reach a trunk (stems.h).
  double FlightTime() {
    const double tau = TerrainFlightTime();
    if constexpr (kForest) {
      if (tau > 0.0) return stems_.FlightTime(s_, tau, g_);
    }
    return tau;
  }
  double TerrainFlightTime() {
    const double tau = CeilingFlightTime(ctx_.terrain, s_, body_.bounding_radius, g_);
    if (tau > 4.0 * dt_) return tau;
    return std::max(tau, NearFlightTime());
  }

  // Close to the ground (look_ahead.h): the longest flight in which no
  // element can reach anything of the neighbourhood, while it holds. A
  // flight may not leave the neighbourhood: one that would start near its
  // edge starts from a new one (else the flights near the ground came in
  // ever shorter pieces towards the edge, each with its landing).
  double NearFlightTime() {
    const double moved = UpdateNeighbours(kFlightKeep);
    return look_ahead_.NearFlightTime(s_, moved, &search_);
  }

  // Exact ballistic advance by tau (free rotation for clusters).
  void Fly(double tau) {
    search_.InvalidatePairs();
    FlyCentre(ctx_.gravity, tau, &s_);
    if constexpr (kCluster) RotateFree(body_, inv_inertia_, tau, kFlightRotationAngle, &s_);
    a_ = ctx_.gravity;
    alpha_.setZero();
  }

  // Contact forces at the current state for obstacles within the landing
  // tolerance: the dashpot resists the approach from the first instant of
  // contact, so the trapezoidal step does not miss the onset impulse.
  void PrimeLanding() {
    const double tol =
        (kMinFlight / kFlightReach) * dt_ * (s_.v.norm() + s_.w.norm() * body_.bounding_radius) +
        1e-12 * body_.element_radius;
    const Eigen::Matrix3d rot = Rotation();
    // The neighbourhood where the flight ended (a new one if it left the
    // old one), and the floor where it is within the tolerance's reach. The
    // floor's clearance is read after the update, which remakes it.
    const double moved = UpdateNeighbours();
    const bool floor = moved + tol >= search_.floor_clear();
    forces_.Clear();
    for (std::size_t e = 0; e < body_.elements.size(); ++e) {
      Eigen::Vector3d centre = s_.x;
      if constexpr (kCluster) centre += rot * body_.elements[e];
      for (TerrainContact c :
           search_.FindElementContacts(centre, floor, body_.element_radius + tol)) {
        c.overlap = std::max(c.overlap - tol, 0.0);
        forces_.Add(c, static_cast<int>(e));
      }
    }
    const auto load = forces_.Landing(s_.x, s_.v, s_.w);
    a_ = ctx_.gravity + load.force / body_.mass;
    alpha_ = AngularAcceleration(load.torque, s_.w, rot);
  }

  // The rock's neighbourhood where it is (ContactSearch::UpdateNeighbours),
  // and its local contact step when it is made anew. Returns the centre's
  // distance from where it was made (infinite on the reference path).
  double UpdateNeighbours(double keep = 1.0) {
    bool rebuilt = false;
    const double moved = search_.UpdateNeighbours(s_.x, keep, &rebuilt);
    if (rebuilt) dt_ = LocalStep();
    return moved;
  }
  // The shortest contact step of the materials the rock may touch before its
  // neighbourhood is rebuilt: those of its candidate spheres and of the grid
  // nodes within its bounding radius and skin (their facets and catch
  // surface). A material elsewhere on the slope leaves the rock's steps
  // alone, so changing it changes no rock that does not reach it. A step
  // that meets a contact asking for a shorter one is redone with that (Run).
  double LocalStep() const {
    const HeightGrid& g = ctx_.terrain.grid();
    double dt = kInf;
    auto take = [&](int node) {
      const int material = g.material[static_cast<std::size_t>(node)];
      dt = std::min(dt, steps_.material[static_cast<std::size_t>(material)].contact);
    };
    for (int n : search_.near()) take(n);
    const double w = body_.bounding_radius + search_.skin();
    const int i0 = std::max(0, static_cast<int>(std::floor((s_.x.x() - w - g.x0) / g.spacing)));
    const int i1 =
        std::min(g.nx - 1, static_cast<int>(std::ceil((s_.x.x() + w - g.x0) / g.spacing)));
    const int j0 = std::max(0, static_cast<int>(std::floor((s_.x.y() - w - g.y0) / g.spacing)));
    const int j1 =
        std::min(g.ny - 1, static_cast<int>(std::ceil((s_.x.y() + w - g.y0) / g.spacing)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) take(g.index(i, j));
    return std::isfinite(dt) ? dt : steps_.finest;
  }

  // One central-difference (kick-drift-kick) contact step of dt, its
  // contacts' load from the contact law (contact_forces.h).
  void Step(double dt) {
    const Eigen::Vector3d v_half = s_.v + 0.5 * dt * a_;
    const Eigen::Vector3d w_half = s_.w + 0.5 * dt * alpha_;
    s_.x += dt * v_half;
    if constexpr (kCluster) Rotate(w_half, dt, &s_.q);
    s_.t += dt;
    // Angular velocity estimate at the new time for the gyroscopic term.
    const Eigen::Vector3d w_pred = w_half + 0.5 * dt * alpha_;
    const Eigen::Matrix3d rot = Rotation();
    const double moved = UpdateNeighbours();
    const bool floor = moved >= search_.floor_clear();
    const bool paired = search_.UpdatePairs(
        s_.x, dt * (v_half.norm() + w_half.norm() * body_.bounding_radius), moved, rot);
    if (kCluster && !paired) search_.ElementCentres(s_.x, rot);
    forces_.Clear();
    for (std::size_t e = 0; e < body_.elements.size(); ++e) {
      const std::vector<TerrainContact>* found = search_.StepContacts(e, s_.x, rot, paired, floor);
      if (!found) continue;
      for (const TerrainContact& c : *found) forces_.Add(c, static_cast<int>(e));
    }
    if constexpr (kForest) {
      AddStemContacts(rot);
      v_half_ = v_half;
      w_half_ = w_half;
    }
    const auto load = forces_.Step(s_.x, v_half, w_half, dt, rot);
    a_ = ctx_.gravity + load.force / body_.mass;
    alpha_ = AngularAcceleration(load.torque, w_pred, rot);
    s_.v = v_half + 0.5 * dt * a_;
    s_.w = w_half + 0.5 * dt * alpha_;
  }

  // ---- the forest (kForest only; docs/physics.md, "Trees") ----------------

  // What the rock did to one stem it touched: the work the trunk's force
  // took from it over its whole run (the stem breaks for this rock when that
  // reaches its capacity), the trunk's force and torque (about the centre)
  // at the last step and at this one (zero where it did not touch), and its
  // strike under way.
  struct StemLoad {
    int stem = 0;
    double absorbed = 0.0;  // J
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
    Eigen::Vector3d force_now = Eigen::Vector3d::Zero(), torque_now = Eigen::Vector3d::Zero();
    double spring_now = 0.0;    // J, in its contacts' springs at this step
    bool touched = false;       // at this step
    bool open = false;          // a strike is under way
    double strike_start = 0.0;  // absorbed when it began
    int record = -1;            // its row in rec_->strikes (-1: not recorded)
  };

  StemLoad& LoadOf(int stem) {
    for (StemLoad& l : loads_)
      if (l.stem == stem) return l;
    loads_.push_back(StemLoad{});
    loads_.back().stem = stem;
    return loads_.back();
  }

  // The contacts of the rock's elements with the trunks within reach.
  void AddStemContacts(const Eigen::Matrix3d& rot) {
    stems_.Update(s_.x);
    if (stems_.near().empty()) return;
    TerrainContact c;
    for (std::size_t e = 0; e < body_.elements.size(); ++e) {
      Eigen::Vector3d centre = s_.x;
      if constexpr (kCluster) centre += rot * body_.elements[e];
      for (int k : stems_.near())
        if (stems_.Contact(centre, body_.element_radius, k, ctx_.trunk_material, &c))
          forces_.Add(c, static_cast<int>(e));
    }
  }

  // After a contact step of dt: the work each touched trunk's force did on
  // the rock over the step (trapezoidal in its force and torque, with the
  // half-step velocity and spin: exact for a linear spring), the strikes
  // begun and ended, and a stem whose capacity is reached broken (Break).
  void StemWork(double dt) {
    if (loads_.empty()) {  // nothing touched yet: only a trunk contact now matters
      bool trunk = false;
      for (std::size_t i = 0; i < forces_.hits() && !trunk; ++i)
        trunk = forces_.hit(i).material == ctx_.trunk_material;
      if (!trunk) return;
    }
    for (StemLoad& l : loads_) {
      l.touched = false;
      l.force_now.setZero();
      l.torque_now.setZero();
      l.spring_now = 0.0;
    }
    for (std::size_t i = 0; i < forces_.hits(); ++i) {
      const TerrainContact& c = forces_.hit(i);
      if (c.material != ctx_.trunk_material) continue;
      StemLoad& l = LoadOf(static_cast<int>(c.key - kStemKey));
      l.touched = true;
      l.force_now += forces_.hit_force(i);
      l.torque_now += (c.point - s_.x).cross(forces_.hit_force(i));
      l.spring_now += forces_.hit_spring(i);
      if (!l.open) OpenStrike(&l, c);
    }
    for (StemLoad& l : loads_) {
      if (l.touched) {
        const Eigen::Vector3d f = 0.5 * (l.force + l.force_now);
        const Eigen::Vector3d t = 0.5 * (l.torque + l.torque_now);
        const double work = -dt * (f.dot(v_half_) + t.dot(w_half_));
        l.absorbed += work;
        if (work > 0.0 && l.absorbed >= ctx_.stems.stem(l.stem).capacity) Break(&l, dt, f, t, work);
      } else if (l.open) {
        CloseStrike(&l, false);
      }
      l.force = l.force_now;
      l.torque = l.torque_now;
    }
  }

  // The stem of l breaks for this rock within the last step (of dt, mean
  // trunk force f and torque t, work `work`): the share of the step's
  // impulse that took the work beyond the capacity is given back, and the
  // trunk's force at the step's end is taken out of the accelerations, so
  // the rock passes with its energy less the capacity.
  void Break(StemLoad* l, double dt, const Eigen::Vector3d& f, const Eigen::Vector3d& t,
             double work) {
    const double capacity = ctx_.stems.stem(l->stem).capacity;
    const double back = std::clamp((l->absorbed - capacity) / work, 0.0, 1.0);
    l->absorbed = capacity;
    s_.v -= (back * dt / body_.mass) * f;
    s_.w -= back * dt * WorldInverseInertia(t);
    a_ -= l->force_now / body_.mass;
    alpha_ -= WorldInverseInertia(l->torque_now);
    l->force_now.setZero();
    l->torque_now.setZero();
    forces_.ForgetSpringEnergy(l->spring_now);  // counted in the capacity
    stems_.Break(l->stem);
    CloseStrike(l, true);
  }

  // The angular acceleration of torque t alone (without the gyroscopic term).
  Eigen::Vector3d WorldInverseInertia(const Eigen::Vector3d& t) const {
    if constexpr (kCluster) {
      const Eigen::Matrix3d rot = Rotation();
      return rot * inv_inertia_.cwiseProduct(rot.transpose() * t);
    }
    return t * inv_inertia_.x();
  }

  // A strike of l's stem begins at this step (c: the first of its contacts).
  void OpenStrike(StemLoad* l, const TerrainContact& c) {
    l->open = true;
    l->strike_start = l->absorbed;
    if (!opt_.record.tree_strikes) return;
    TreeStrike t;
    t.tree = l->stem;
    t.point = s_.x;
    t.height = c.point.z() - ctx_.stems.foot(l->stem);
    t.speed = s_.v.norm();
    t.energy = KineticEnergy(s_);
    l->record = static_cast<int>(rec_->strikes.size());
    rec_->strikes.push_back(t);
  }
  // The strike of l ends (broken: its stem broke).
  void CloseStrike(StemLoad* l, bool broken) {
    if (!l->open) return;
    l->open = false;
    if (l->record < 0) return;
    TreeStrike& t = rec_->strikes[static_cast<std::size_t>(l->record)];
    t.absorbed = l->absorbed - l->strike_start;
    t.broken = broken;
    l->record = -1;
  }

  const SceneContext& ctx_;
  const SimulationOptions& opt_;
  const RockBody& body_;
  const StepSizes& steps_;
  // The rock's contact step where it is (LocalStep): the step of contact-free
  // advances, the flight look-ahead and the landing. The scene's finest until
  // the first neighbourhood, and always on the reference path.
  double dt_;
  const bool exact_flight_;  // off on the reference path
  RockRecord* rec_;
  Recorder recorder_;  // what the record keeps of the path (recording.h)
  RockState caught_;   // where a barrier stopped the rock (Recorder::Advance)
  RockEnds ends_;      // rest, the run's ends and the energy check (rest.h)
  RockState s_;
  Eigen::Vector3d a_, alpha_;  // accelerations at the current state
  Eigen::Vector3d inv_inertia_;
  double g_ = 0.0;
  bool landing_ = false;            // the last advance was a flight
  ContactSearch<kCluster> search_;  // neighbour lists and contact detection (contact_search.h)
  FlightLookAhead<kCluster> look_ahead_;  // the flight near the ground (look_ahead.h)
  ContactForces<kCluster> forces_;  // the contact law on the step's contacts (contact_forces.h)
  StemSearch stems_;                // the stems within reach (kForest; stems.h)
  std::vector<StemLoad> loads_;     // the stems the rock has touched (kForest)
  Eigen::Vector3d v_half_ = Eigen::Vector3d::Zero(),
                  w_half_ = Eigen::Vector3d::Zero();  // of the last Step
};

// Release: a random point of the zone, a random size and orientation, then
// placed so the lowest point is `height` above every obstacle.
RockState ReleaseRock(const SceneContext& ctx, const RockGroup& group, const RockBody& body,
                      RandomStream* rng, double u_pos[2], Eigen::Quaterniond q) {
  RockState s;
  const core::Release& rel = group.release;
  double x = rel.point.x(), y = rel.point.y();
  if (!rel.zone.empty()) {
    double xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
    for (const auto& p : rel.zone) {
      xmin = std::min(xmin, p.x());
      xmax = std::max(xmax, p.x());
      ymin = std::min(ymin, p.y());
      ymax = std::max(ymax, p.y());
    }
    x = xmin + u_pos[0] * (xmax - xmin);
    y = ymin + u_pos[1] * (ymax - ymin);
    for (int tries = 0; tries < 10000 && !PointInPolygon(rel.zone, Eigen::Vector2d(x, y));
         ++tries) {
      x = rng->Uniform(xmin, xmax);
      y = rng->Uniform(ymin, ymax);
    }
  }
  s.q = q;
  const Eigen::Matrix3d rot = s.q.toRotationMatrix();
  double lowest = kInf;
  for (const auto& e : body.elements)
    lowest = std::min(lowest, (rot * e).z() - body.element_radius);
  double ground = 0.0;
  ctx.terrain.Elevation(x, y, &ground);
  // A surveyed drop elevation, but never below the ground.
  const double base = rel.elevation ? std::max(*rel.elevation, ground) : ground + rel.height;
  s.x = Eigen::Vector3d(x, y, base - lowest);
  // Lift out of any virtual sphere that pokes above the interpolated surface.
  // A vertical lift by the overlap clears a tilted obstacle only in part, so
  // repeat (each pass lifts at least by the remaining overlap).
  for (int pass = 0; pass < 100; ++pass) {
    double worst = 0.0;
    for (const auto& e : body.elements)
      worst = std::min(worst, ctx.terrain.Gap(s.x + rot * e, body.element_radius, 0.0));
    if (worst >= 0.0) break;
    s.x.z() += -worst + 1e-6 * body.bounding_radius;
  }
  s.v = rel.velocity;
  // The spread's draws come last, so a site without one draws as before.
  if (rel.velocity_spread.any()) {
    for (int k = 0; k < 3; ++k) s.v[k] += rel.velocity_spread[k] * rng->Normal();
  }
  s.w = rel.angular_velocity;
  s.t = 0.0;
  return s;
}

}  // namespace

Terrain BuildTerrain(const Scene& scene) {
  std::vector<double> roughness;
  for (const auto& m : scene.materials) roughness.push_back(m.roughness_m);
  double max_radius = 0.0;
  for (const auto& g : scene.groups)
    max_radius = std::max(max_radius, GroupBodies(g, scene.gravity).max_element_radius);
  return Terrain(scene.grid, roughness, max_radius, scene.options.threads);
}

SimulationResult Simulate(const Scene& scene) { return Simulate(scene, BuildTerrain(scene)); }

SimulationResult Simulate(const Scene& scene, const Terrain& terrain, const ProgressFn& progress) {
  return SimulateRocks(scene, terrain, 0, scene.total_rocks(), progress);
}

namespace {

// What every rock of a run shares: the contact laws, the forest's stems.
SceneContext MakeContext(const Scene& scene, const Terrain& terrain) {
  SceneContext ctx{scene, terrain, {}, Eigen::Vector3d(0, 0, -scene.gravity), 0.0, {}, -1};
  for (const auto& m : scene.materials) {
    ctx.laws.push_back(DeriveContactLaw(m, scene.hardness_model));
    ctx.max_contact_time = std::max(ctx.max_contact_time, m.contact_time_s);
  }
  if (!scene.forest.empty()) {  // decided once per run: a bare scene does no forest work
    ctx.stems = StemGrid(scene.forest, terrain);
    if (!ctx.stems.empty()) {
      ctx.trunk_material = static_cast<int>(ctx.laws.size());
      ctx.laws.push_back(scene.forest.Law());
    }
  }
  return ctx;
}

// Rocks first, first + stride, ... below last (SimulateRocks: stride 1).
SimulationResult SimulateStridedRocks(const Scene& scene, const Terrain& terrain, int first,
                                      int last, int stride, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  const SceneContext ctx = MakeContext(scene, terrain);
  struct Job {
    int group;
    int rock;
    int in_group;  // index within the group
  };
  std::vector<Job> jobs;
  for (std::size_t g = 0; g < scene.groups.size(); ++g)
    for (int k = 0; k < scene.groups[g].count; ++k)
      jobs.push_back({static_cast<int>(g), static_cast<int>(jobs.size()), k});

  if (first < 0 || first > last || last > static_cast<int>(jobs.size()))
    throw std::invalid_argument("SimulateRocks: rocks [" + std::to_string(first) + ", " +
                                std::to_string(last) + ") are not within the scene's " +
                                std::to_string(jobs.size()));
  jobs.erase(jobs.begin() + last, jobs.end());
  jobs.erase(jobs.begin(), jobs.begin() + first);
  if (stride > 1) {
    std::vector<Job> kept;
    for (std::size_t k = 0; k < jobs.size(); k += static_cast<std::size_t>(stride))
      kept.push_back(jobs[k]);
    jobs = std::move(kept);
  }

  SimulationResult result;
  result.rocks.resize(jobs.size());
  std::vector<char> shrunk(jobs.size(), 0);
  const int threads = scene.options.threads > 0 ? scene.options.threads : omp_get_max_threads();
  const long n = static_cast<long>(jobs.size());
  int done = 0;
  std::vector<double> busy(jobs.size(), 0.0);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < n; ++k) {
    const auto rock_start = std::chrono::steady_clock::now();
    const Job& job = jobs[static_cast<std::size_t>(k)];
    const RockGroup& group = scene.groups[static_cast<std::size_t>(job.group)];
    // Keyed by the group and the index within it, so adding rocks to one
    // group leaves every other group's rocks alone (a one-group scene keys
    // by the rock index, as before).
    RandomStream rng(scene.options.seed, (static_cast<std::uint64_t>(job.group) << 32) |
                                             static_cast<std::uint64_t>(job.in_group));
    // Draws in a fixed order, whatever the shape or parameters: size, position, orientation.
    const double u_size = rng.Uniform();
    double u_pos[2] = {rng.Uniform(), rng.Uniform()};
    const double u1 = rng.Uniform(), u2 = rng.Uniform(), u3 = rng.Uniform();
    const Eigen::Quaterniond drawn(
        std::sqrt(1 - u1) * std::sin(2 * kPi * u2), std::sqrt(1 - u1) * std::cos(2 * kPi * u2),
        std::sqrt(u1) * std::sin(2 * kPi * u3), std::sqrt(u1) * std::cos(2 * kPi * u3));
    const Eigen::Quaterniond q = group.release.orientation.value_or(drawn);
    const RockBody body = GroupRockBody(group, job.in_group, u_size, scene.gravity);
    bool any_shrunk = false;
    const StepSizes steps = RockSteps(body, ctx.laws, scene, &any_shrunk);
    const double dt = steps.finest;
    shrunk[static_cast<std::size_t>(k)] = any_shrunk;
    RockRecord& rec = result.rocks[static_cast<std::size_t>(k)];
    rec.rock = job.rock;
    rec.group = job.group;
    rec.shape = body.shape;
    rec.size = body.size;
    rec.mass = body.mass;
    rec.bounding_radius = body.bounding_radius;
    rec.dt = dt;
    const bool cluster = body.elements.size() > 1 || scene.options.reference_path;
    const RockState s0 = ReleaseRock(ctx, group, body, &rng, u_pos,
                                     cluster ? q.normalized() : Eigen::Quaterniond::Identity());
    rec.start = s0.x;
    const bool forest = !ctx.stems.empty();
    if (cluster) {
      if (forest)
        RockRun<true, true>(ctx, body, steps, &rec).Run(s0);
      else
        RockRun<true, false>(ctx, body, steps, &rec).Run(s0);
    } else {
      if (forest)
        RockRun<false, true>(ctx, body, steps, &rec).Run(s0);
      else
        RockRun<false, false>(ctx, body, steps, &rec).Run(s0);
    }
    busy[static_cast<std::size_t>(k)] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - rock_start).count();
    if (progress) {
#pragma omp critical(rockcal_progress)
      progress(++done, static_cast<int>(n));
    }
  }
  for (std::size_t k = 0; k < result.rocks.size(); ++k)
    result.figures += RunFigures::OfRock(result.rocks[k], shrunk[k] != 0);
  for (double b : busy) result.busy_seconds += b;
  result.cells_recorded = scene.options.record.passages;
  result.strikes_recorded = scene.options.record.tree_strikes && !scene.forest.empty();
  if (first == 0 && !scene.options.record.impacts.empty())
    result.impacts = ReplayImpacts(scene, terrain, scene.options.record.impacts);
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

void RunRebounds(const Scene& scene, const Terrain& terrain, std::vector<ReboundJob>* jobs) {
  const SceneContext ctx = MakeContext(scene, terrain);
  const int threads = scene.options.threads > 0 ? scene.options.threads : omp_get_max_threads();
  const long n = static_cast<long>(jobs->size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < n; ++k) {
    ReboundJob& job = (*jobs)[static_cast<std::size_t>(k)];
    bool any_shrunk = false;
    const StepSizes steps = RockSteps(job.body, ctx.laws, scene, &any_shrunk);
    RockRecord rec;
    rec.rock = std::numeric_limits<int>::max();  // no trajectory
    const bool cluster = job.body.elements.size() > 1 || scene.options.reference_path;
    RockState s = job.start;
    if (!cluster) s.q = Eigen::Quaterniond::Identity();
    const bool forest = !ctx.stems.empty();
    if (cluster) {
      if (forest)
        job.left = RockRun<true, true>(ctx, job.body, steps, &rec)
                       .Rebound(s, job.normal, job.max_time, job.contact_seconds, &job.velocity);
      else
        job.left = RockRun<true, false>(ctx, job.body, steps, &rec)
                       .Rebound(s, job.normal, job.max_time, job.contact_seconds, &job.velocity);
    } else {
      if (forest)
        job.left = RockRun<false, true>(ctx, job.body, steps, &rec)
                       .Rebound(s, job.normal, job.max_time, job.contact_seconds, &job.velocity);
      else
        job.left = RockRun<false, false>(ctx, job.body, steps, &rec)
                       .Rebound(s, job.normal, job.max_time, job.contact_seconds, &job.velocity);
    }
  }
}

SimulationResult SimulateRocks(const Scene& scene, const Terrain& terrain, int first, int last,
                               const ProgressFn& progress) {
  return SimulateStridedRocks(scene, terrain, first, last, 1, progress);
}

SimulationResult SimulateEveryNthRock(const Scene& scene, const Terrain& terrain, int offset,
                                      int stride, const ProgressFn& progress) {
  if (stride < 1 || offset < 0 || offset >= stride)
    throw std::invalid_argument("SimulateEveryNthRock: offset " + std::to_string(offset) +
                                " and stride " + std::to_string(stride) +
                                ": expected 0 <= offset < stride");
  return SimulateStridedRocks(scene, terrain, std::min(offset, scene.total_rocks()),
                              scene.total_rocks(), stride, progress);
}
}  // namespace rockcal::core
