// The contact law on one rock's contacts at a step (docs/physics.md, Contact and
// Integration): each contact's share of the rock's damping, the dashpots
// implicit together (damping.h), each contact's normal spring-dashpot,
// tangential spring with its Coulomb cap and rolling resistance (contact.h),
// the tangential springs carried from step to step, undergrowth, and the
// step the contacts ask for. The caller (simulate.cc, RockRun) finds the
// contacts (contact_search.h) and integrates the motion. Internal to core
// (simulate.cc; tests/core/contact_forces_test.cc).
#ifndef ROCKCAL_CORE_SRC_CONTACT_FORCES_H_
#define ROCKCAL_CORE_SRC_CONTACT_FORCES_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "damping.h"
#include "rockcal/core/contact.h"
#include "rockcal/core/material.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/scene.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// A rock's contact steps on one material: t_c / N_c within the stability
// bound, and the longer one of gentle contact (GentleTimeStep).
struct MaterialSteps {
  double contact = 0.0, gentle = 0.0;
  double gentle_speed = 0.0;  // g t_c: a contact slower along its normal is gentle
};
struct StepSizes {
  std::vector<MaterialSteps> material;  // Scene::materials order
  double finest = 0.0;                  // the shortest contact step
};
// A rock's contact steps on each of `laws` (the scene's materials'); sets
// *any_shrunk when one was cut below t_c / N_c for stability (time_step.cc).
StepSizes RockSteps(const RockBody& body, const std::vector<ContactLaw>& laws, const Scene& scene,
                    bool* any_shrunk);

// The force along the normal [N] of a contact of a rock of `mass` on `law`
// with `damping_share` of the law's dashpot (DampingShare), at `overlap` and
// normal speed `normal_speed` (contact.h, NormalForce): the law's per-mass
// coefficients times the mass.
inline double DampedNormalForce(const ContactLaw& law, double mass, double damping_share,
                                double overlap, double normal_speed) {
  return NormalForce({mass * law.stiffness_per_mass,
                      mass * (law.damping_per_mass * damping_share)},
                     overlap, normal_speed);
}

// kCluster: the rock's elements are off its centre (the rigid-cluster path).
// Use at each step: Clear, Add each contact found, then Step (or Landing at
// a flight's end).
template <bool kCluster>
class ContactForces {
 public:
  // The force and torque (about the centre) of the contacts together.
  struct Load {
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  };

  // laws: the scene's contact laws (Scene::materials order); steps: the
  // rock's contact steps on each; gravity: the acceleration vector.
  ContactForces(const std::vector<ContactLaw>& laws, const RockBody& body, const StepSizes& steps,
                const Eigen::Vector3d& gravity)
      : laws_(laws),
        body_(body),
        steps_(steps),
        gravity_(gravity),
        inv_inertia_(body.inertia.cwiseInverse()),
        inertia_min_(body.inertia.minCoeff()),
        single_element_(body.elements.size() == 1) {
    hits_.reserve(16);
    contacts_.reserve(16);
    next_.reserve(16);
  }

  // Keep each contact's force of a Step (hit_force), for a caller that
  // needs them apart (the trunks of a forest, simulate.cc); off by default.
  void KeepForces(bool keep) { keep_forces_ = keep; }

  // The contacts of the step to come: element e touches as c says.
  void Clear() { hits_.clear(); }
  void Add(const TerrainContact& c, int e) { hits_.push_back({c, e}); }

  // The contacts' load over a step of dt of a rock at centre x and
  // orientation rot, from its half-step velocity and spin: every contact's
  // law with its share of the damping, the dashpots implicit together (one
  // contact alone solves its own), the rolling torques limited so they at
  // most stop the spin, then undergrowth. Keeps each contact's tangential
  // spring for the next step and the springs' energy; the contacts before
  // the step are kept for Undo.
  Load Step(const Eigen::Vector3d& x, const Eigen::Vector3d& v_half, const Eigen::Vector3d& w_half,
            double dt, const Eigen::Matrix3d& rot) {
    needed_dt_ = kInf;
    sliding_ = false;
    spring_before_ = spring_energy_;
    spring_energy_ = 0.0;
    deepest_ = 0.0;
    next_.clear();
    hit_forces_.clear();
    hit_springs_.clear();
    Load load;
    Eigen::Vector3d rolling = Eigen::Vector3d::Zero();  // before its limit
    const double norm = OverlapNorm();
    const bool joint = hits_.size() > 1;
    const Motion end =
        joint ? JointEndMotion(x, v_half, w_half, dt, norm, rot) : Motion{v_half, w_half};
    for (const Hit& h : hits_)
      AddContactForce(h.contact, h.element, DampingShare(h.contact.overlap, norm), x, v_half,
                      w_half, dt, joint ? &end : nullptr, rot, &load, &rolling);
    load.torque += LimitRollingTorque(rolling, inertia_min_, w_half.norm(), dt);
    AddVegetationForce(v_half, dt, &load);
    contacts_.swap(next_);
    return load;
  }

  // Takes the last Step back: the contacts and spring energy before it.
  void Undo() {
    contacts_.swap(next_);
    spring_energy_ = spring_before_;
  }

  // The normal spring-dashpots' load at a flight's end, the rock at centre
  // x with velocity v and spin w: each contact's damped normal force at its
  // normal speed there, nothing kept.
  Load Landing(const Eigen::Vector3d& x, const Eigen::Vector3d& v, const Eigen::Vector3d& w) const {
    Load load;
    const double norm = OverlapNorm();
    const double m = body_.mass;
    for (const Hit& h : hits_) {
      const TerrainContact& c = h.contact;
      const ContactLaw& law = laws_[static_cast<std::size_t>(c.material)];
      const Eigen::Vector3d arm = c.point - x;
      const double vn = (v + w.cross(arm)).dot(c.normal);
      // Per unit mass, as the law keeps it, then times the mass.
      const double fn =
          m * NormalForce({law.stiffness_per_mass,
                           law.damping_per_mass * DampingShare(c.overlap, norm)},
                          c.overlap, vn);
      load.force += fn * c.normal;
      load.torque += arm.cross(fn * c.normal);
    }
    return load;
  }

  // Whether the last Step had contacts (they are held into the next).
  bool touching() const { return !contacts_.empty(); }
  // The step the last Step's contacts ask for: each its material's gentle
  // step while it moves along its normal slower than g t_c, its contact step
  // otherwise; infinite without contacts.
  double needed_dt() const { return needed_dt_; }
  // A contact of the last Step slid or carried no load.
  bool sliding() const { return sliding_; }
  // The energy in the contacts' springs after the last Step [J].
  double spring_energy() const { return spring_energy_; }
  // The deepest overlap of the last Step's contacts [m] (0 without).
  double deepest() const { return deepest_; }
  // The last Step's contacts in the order added, and (KeepForces) each
  // one's force on the rock [N].
  std::size_t hits() const { return hits_.size(); }
  const TerrainContact& hit(std::size_t i) const { return hits_[i].contact; }
  const Eigen::Vector3d& hit_force(std::size_t i) const { return hit_forces_[i]; }
  // (KeepForces) The energy in contact i's springs after the last Step [J].
  double hit_spring(std::size_t i) const { return hit_springs_[i]; }
  // Contacts whose springs held `energy` are gone since the last Step (a
  // stem broke): spring_energy() no longer counts it.
  void ForgetSpringEnergy(double energy) { spring_energy_ -= energy; }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();

  struct Hit {
    TerrainContact contact;
    int element;
  };
  struct ContactState {
    std::int64_t key;
    int element;
    Eigen::Vector3d u;  // tangential spring displacement
  };
  // The rock's velocity and spin at a step's end.
  struct Motion {
    Eigen::Vector3d v, w;
  };
  using Dashpots = JointDashpots<kCluster ? 6 : 3>;

  // The Euclidean norm of the step's contacts' overlaps, for their damping
  // shares (damping.h, DampingShare).
  double OverlapNorm() const {
    double sum = 0.0;
    for (const Hit& h : hits_) sum += h.contact.overlap * h.contact.overlap;
    return std::sqrt(sum);
  }
  double DampingShare(double overlap, double norm) const {
    return core::DampingShare(overlap, norm, hits_.size(), single_element_);
  }

  // The rock's velocity and spin at the end of a step of dt with all its
  // contacts' dashpots implicit together (damping.h, JointDashpots).
  Motion JointEndMotion(const Eigen::Vector3d& x, const Eigen::Vector3d& v_half,
                        const Eigen::Vector3d& w_half, double dt, double norm,
                        const Eigen::Matrix3d& rot) {
    using Vector = typename Dashpots::Vector;
    using Matrix = typename Dashpots::Matrix;
    // The free motion M^-1 (M u_half + dt/2 g), and M^-1 per unit mass.
    Vector free;
    free.template head<3>() = v_half + 0.5 * dt * gravity_;
    Eigen::Matrix3d inverse_inertia;
    if constexpr (kCluster) {
      free.template tail<3>() = w_half;
      inverse_inertia = rot * (body_.mass * inv_inertia_).asDiagonal() * rot.transpose();
    }
    // Each contact's row g_i, M^-1 g_i, dashpot (dt/2 c_i) and spring (dt/2 k d_i) terms.
    const std::size_t n = hits_.size();
    dashpots_.Resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const TerrainContact& c = hits_[i].contact;
      const ContactLaw& law = laws_[static_cast<std::size_t>(c.material)];
      auto& row = dashpots_.row(i);
      row.template head<3>() = c.normal;
      if constexpr (kCluster) {
        row.template tail<3>() = (c.point - x).cross(c.normal);
        auto& reach = dashpots_.reach(i);
        reach.template head<3>() = c.normal;
        reach.template tail<3>() = inverse_inertia * row.template tail<3>();
      } else {
        row.template tail<3>().setZero();
      }
      dashpots_.terms(i) = {0.5 * dt * law.damping_per_mass * DampingShare(c.overlap, norm),
                            0.5 * dt * law.stiffness_per_mass * c.overlap};
    }
    // M per unit mass, only where the 6 x 6 (or a sphere's 3 x 3) is solved.
    const Vector u = dashpots_.Solve(free, [&] {
      Matrix mass = Matrix::Identity();
      if constexpr (kCluster)
        mass.template bottomRightCorner<3, 3>() =
            rot * (body_.inertia / body_.mass).asDiagonal() * rot.transpose();
      return mass;
    });
    if constexpr (kCluster) {
      return {u.template head<3>(), u.template tail<3>()};
    } else {
      return {u, w_half};
    }
  }

  // The contact law (core/contact.h) on contact c of element e, with its
  // share of the rock's damping, over a step of dt from the half-step
  // velocities: adds its force and torque to *load and its rolling torque
  // (before the limit) to *rolling, keeps its spring in next_ and its energy
  // in spring_energy_, and lowers needed_dt_ to the step it asks for. end:
  // the rock's motion at the step's end from JointEndMotion, or null to
  // solve this contact's dashpot alone (the rock's only contact).
  void AddContactForce(const TerrainContact& c, int e, double damping_share,
                       const Eigen::Vector3d& x, const Eigen::Vector3d& v_half,
                       const Eigen::Vector3d& w_half, double dt, const Motion* end,
                       const Eigen::Matrix3d& rot, Load* load, Eigen::Vector3d* rolling) {
    const ContactLaw& law = laws_[static_cast<std::size_t>(c.material)];
    const double m = body_.mass;
    const Eigen::Vector3d arm = c.point - x;
    const Eigen::Vector3d vc_half = v_half + w_half.cross(arm);
    const double kn = m * law.stiffness_per_mass;
    const double damping_per_mass = law.damping_per_mass * damping_share;
    // Normal velocity at the end of the step, with the dashpot taken
    // implicitly (trapezoidal): v_n = v_n,half + dt/2 (k d / m - c v_n + g_n).
    // Alone, the contact's own row of JointEndMotion's system: the rock
    // meets it with its effective mass there, m / s.
    double vn;
    if (end) {
      vn = (end->v + end->w.cross(arm)).dot(c.normal);
    } else {
      double s = 1.0;
      if constexpr (kCluster) {
        const Eigen::Vector3d lever = rot.transpose() * arm.cross(c.normal);  // body axes
        s += m * lever.cwiseAbs2().dot(inv_inertia_);
      }
      vn = ImplicitNormalSpeed(vc_half.dot(c.normal), dt, s, law.stiffness_per_mass, c.overlap,
                               gravity_.dot(c.normal), damping_per_mass);
    }
    const double fn = NormalForce({kn, m * damping_per_mass}, c.overlap, vn);
    const MaterialSteps& ms = steps_.material[static_cast<std::size_t>(c.material)];
    // n contacts at once meet the rock with up to n times the stiffness, so
    // their impact lasts down to t_c / sqrt(n): it takes N_c steps of that.
    needed_dt_ =
        std::min(needed_dt_, std::abs(vn) < ms.gentle_speed
                                 ? ms.gentle
                                 : ms.contact / std::sqrt(static_cast<double>(hits_.size())));
    // Tangential spring: carry the displacement over, rotated into the
    // current tangent plane, and add this step's sliding.
    Eigen::Vector3d u = CarriedDisplacement(c.key, e, c.normal);
    u += TangentialSlip(vc_half, c.normal, dt);
    const double ks = kn * law.tangential_ratio;
    const Eigen::Vector3d ft = TangentialForce({ks, law.friction}, fn, &u);
    // At the Coulomb cap, or carrying no load: the contact does not hold the rock.
    if (!(ft.norm() < law.friction * fn)) sliding_ = true;
    const Eigen::Vector3d f = fn * c.normal + ft;
    if (keep_forces_) hit_forces_.push_back(f);
    load->force += f;
    load->torque += arm.cross(f);
    // Rolling resistance against rolling, not spin about this contact's
    // normal, on the spring's normal force k_n d: the load on the contact
    // (the dashpot's share nets about zero over an impact). The lever is the
    // contact's distance from the rolling axis (a sphere's radius a; with the
    // element radius instead, a block tumbling over its edges felt a fraction
    // of the resistance a sphere of its size feels).
    if (law.rolling_resistance > 0.0) {
      const Eigen::Vector3d roll = RollingRate(w_half, c.normal);
      const double lever = single_element_ ? body_.element_radius : RollingLever(roll, arm);
      *rolling += RollingResistanceTorque(law.rolling_resistance, lever, kn * c.overlap, roll);
    }
    const double spring = 0.5 * kn * c.overlap * c.overlap + 0.5 * ks * u.squaredNorm();
    if (keep_forces_) hit_springs_.push_back(spring);
    spring_energy_ += spring;
    next_.push_back({c.key, e, u});
    deepest_ = std::max(deepest_, c.overlap);
  }

  // The tangential spring displacement contact `key` of element e had at
  // the last step, carried into the tangent plane of `normal`; zero for a
  // new contact.
  Eigen::Vector3d CarriedDisplacement(std::int64_t key, int e,
                                      const Eigen::Vector3d& normal) const {
    for (const ContactState& old : contacts_)
      if (old.key == key && old.element == e) return CarryTangentialDisplacement(old.u, normal);
    return Eigen::Vector3d::Zero();
  }

  // Undergrowth on the ground the rock touches (the highest stress of this
  // step's contacts' materials): tau times the rock's frontal area, at its
  // centre, against its velocity, at most what stops it within the step,
  // so it only ever takes energy and never reverses the motion. A rock
  // flying over the ground is not slowed.
  void AddVegetationForce(const Eigen::Vector3d& v_half, double dt, Load* load) const {
    double stress = 0.0;
    for (const Hit& h : hits_)
      stress = std::max(stress, laws_[static_cast<std::size_t>(h.contact.material)].vegetation_stress);
    const double speed = v_half.norm();
    if (!(stress > 0.0) || !(speed > 0.0)) return;
    const double deceleration = std::min(stress * body_.frontal_area / body_.mass, speed / dt);
    load->force -= (body_.mass * deceleration / speed) * v_half;
  }

  const std::vector<ContactLaw>& laws_;
  const RockBody& body_;
  const StepSizes& steps_;
  const Eigen::Vector3d gravity_;
  const Eigen::Vector3d inv_inertia_;
  const double inertia_min_;
  const bool single_element_;  // a sphere (on either path)
  std::vector<Hit> hits_;      // the step's contacts, every element's
  std::vector<ContactState> contacts_, next_;  // the springs held, and the step's
  Dashpots dashpots_;  // JointEndMotion's system (damping.h)
  double needed_dt_ = kInf;
  double spring_energy_ = 0.0, spring_before_ = 0.0;
  double deepest_ = 0.0;
  bool sliding_ = false;
  bool keep_forces_ = false;
  std::vector<Eigen::Vector3d> hit_forces_;  // per hit of the last Step (KeepForces)
  std::vector<double> hit_springs_;          // per hit of the last Step (KeepForces)
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_CONTACT_FORCES_H_
