// The contact law on a rock's contacts at a step (core/src/contact_forces.h),
// each against its closed form: a single contact's spring, its dashpot
// solved implicitly, two equal contacts sharing the dashpot, the Coulomb
// cap, rolling resistance and its limit, the landing's force, the step a
// contact asks for, and a step taken back.
#include "contact_forces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace rockcal::core {
namespace {

// A 2 m sphere of 1000 kg on a law per unit mass, and a step.
constexpr double kMass = 1000.0;
constexpr double kRadius = 1.0;
constexpr double kStiffness = 4.0e5;  // k / m [1/s^2]
constexpr double kDamping = 300.0;    // c / m [1/s]
constexpr double kRatio = 2.0 / 7.0;  // k_s / k_n
constexpr double kFriction = 0.5;
constexpr double kOverlap = 2.0e-3;  // [m]
constexpr double kDt = 1.0e-4;       // [s]

RockBody Sphere() {
  RockBody body;
  body.mass = kMass;
  body.element_radius = kRadius;
  body.bounding_radius = kRadius;
  body.elements = {Eigen::Vector3d::Zero()};
  body.inertia = Eigen::Vector3d::Constant(0.4 * kMass * kRadius * kRadius);
  body.frontal_area = 3.14159265358979323846 * kRadius * kRadius;
  return body;
}

// Two spheres of radius 0.5 m at x = -+1 m, 1000 kg together.
RockBody Dumbbell() {
  RockBody body;
  body.mass = kMass;
  body.element_radius = 0.5;
  body.bounding_radius = 1.5;
  body.elements = {Eigen::Vector3d(-1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0)};
  body.inertia = Eigen::Vector3d(100.0, 1100.0, 1100.0);
  body.frontal_area = 2.0;
  return body;
}

ContactLaw Law(double damping = kDamping, double rolling = 0.0) {
  ContactLaw law;
  law.stiffness_per_mass = kStiffness;
  law.damping_per_mass = damping;
  law.tangential_ratio = kRatio;
  law.friction = kFriction;
  law.rolling_resistance = rolling;
  law.vegetation_stress = 0.0;
  return law;
}

StepSizes Steps() {
  StepSizes steps;
  steps.material = {{1.0e-4, 4.0e-4, 0.05}};  // contact, gentle, g t_c
  steps.finest = 1.0e-4;
  return steps;
}

// The contact of an element centred at `centre` with a floor of normal +z,
// `overlap` deep: its point in the middle of the overlap.
TerrainContact FloorContact(const Eigen::Vector3d& centre, double radius, double overlap,
                            std::int64_t key = 7) {
  TerrainContact c;
  c.normal = Eigen::Vector3d::UnitZ();
  c.point = centre - (radius - 0.5 * overlap) * c.normal;
  c.overlap = overlap;
  c.material = 0;
  c.key = key;
  return c;
}

const Eigen::Vector3d kNoGravity = Eigen::Vector3d::Zero();
const Eigen::Vector3d kCentre(3.0, -2.0, 10.0);
const Eigen::Matrix3d kUpright = Eigen::Matrix3d::Identity();

TEST(ContactForces, ASpringAloneIsKD) {
  const RockBody body = Sphere();
  const std::vector<ContactLaw> laws = {Law(0.0)};
  const StepSizes steps = Steps();
  ContactForces<false> forces(laws, body, steps, kNoGravity);
  forces.Clear();
  forces.Add(FloorContact(kCentre, kRadius, kOverlap), 0);
  const auto load = forces.Step(kCentre, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDt,
                                kUpright);
  const double exact = kMass * kStiffness * kOverlap;  // 800 N
  EXPECT_NEAR(load.force.z(), exact, 1e-12 * exact) << "force " << load.force.transpose();
  EXPECT_EQ(load.force.x(), 0.0);
  EXPECT_EQ(load.force.y(), 0.0);
  EXPECT_EQ(load.torque, Eigen::Vector3d::Zero()) << "torque " << load.torque.transpose();
  const double energy = 0.5 * kMass * kStiffness * kOverlap * kOverlap;
  EXPECT_NEAR(forces.spring_energy(), energy, 1e-12 * energy);
  EXPECT_TRUE(forces.touching());
  EXPECT_EQ(forces.deepest(), kOverlap);
}

// One contact's dashpot, implicit: v_n = (v_half + dt/2 k d) / (1 + dt/2 c),
// f = m (k d - c v_n).
TEST(ContactForces, OneDashpotIsSolvedImplicitly) {
  const RockBody body = Sphere();
  const std::vector<ContactLaw> laws = {Law()};
  const StepSizes steps = Steps();
  ContactForces<false> forces(laws, body, steps, kNoGravity);
  forces.Clear();
  forces.Add(FloorContact(kCentre, kRadius, kOverlap), 0);
  const double approach = -4.0;
  const auto load = forces.Step(kCentre, Eigen::Vector3d(0.0, 0.0, approach),
                                Eigen::Vector3d::Zero(), kDt, kUpright);
  const double vn = (approach + 0.5 * kDt * kStiffness * kOverlap) / (1.0 + 0.5 * kDt * kDamping);
  const double exact = kMass * (kStiffness * kOverlap - kDamping * vn);
  EXPECT_NEAR(load.force.z(), exact, 1e-12 * exact) << "force " << load.force.transpose();
  // Approaching at 4 m/s: not gentle (g t_c 0.05 m/s), the contact step.
  EXPECT_EQ(forces.needed_dt(), 1.0e-4);
}

// Two equal contacts of a cluster share the dashpot, c / sqrt(2) each, and
// meet it together: symmetric about the centre, the spin stays zero and
// (1 + dt c / sqrt 2) v_n = v_half + dt k d.
TEST(ContactForces, TwoEqualContactsShareTheDashpot) {
  const RockBody body = Dumbbell();
  const std::vector<ContactLaw> laws = {Law()};
  const StepSizes steps = Steps();
  ContactForces<true> forces(laws, body, steps, kNoGravity);
  forces.Clear();
  for (int e = 0; e < 2; ++e)
    forces.Add(FloorContact(kCentre + body.elements[static_cast<std::size_t>(e)], 0.5, kOverlap, e),
               e);
  const double approach = -4.0;
  const auto load = forces.Step(kCentre, Eigen::Vector3d(0.0, 0.0, approach),
                                Eigen::Vector3d::Zero(), kDt, kUpright);
  const double share = 1.0 / std::sqrt(2.0);
  const double vn = (approach + kDt * kStiffness * kOverlap) / (1.0 + kDt * kDamping * share);
  const double exact = 2.0 * kMass * (kStiffness * kOverlap - kDamping * share * vn);
  EXPECT_NEAR(load.force.z(), exact, 1e-12 * exact) << "force " << load.force.transpose();
  EXPECT_NEAR(load.torque.norm(), 0.0, 1e-9 * exact) << "torque " << load.torque.transpose();
  // Two at once: t_c / sqrt(2) takes N_c steps.
  EXPECT_DOUBLE_EQ(forces.needed_dt(), 1.0e-4 / std::sqrt(2.0));
}

// The tangential spring k_s dt u under the Coulomb cap, f k d at it; the
// torque is the arm times the force.
TEST(ContactForces, TheTangentialSpringIsCappedByCoulomb) {
  const RockBody body = Sphere();
  const std::vector<ContactLaw> laws = {Law(0.0)};
  const StepSizes steps = Steps();
  const double fn = kMass * kStiffness * kOverlap;
  const double arm = -(kRadius - 0.5 * kOverlap);  // z of the contact point from the centre
  for (double slide : {0.01, 1.0}) {  // m/s: under the cap, at it
    ContactForces<false> forces(laws, body, steps, kNoGravity);
    forces.Clear();
    forces.Add(FloorContact(kCentre, kRadius, kOverlap), 0);
    const auto load = forces.Step(kCentre, Eigen::Vector3d(slide, 0.0, 0.0),
                                  Eigen::Vector3d::Zero(), kDt, kUpright);
    const double spring = kMass * kStiffness * kRatio * kDt * slide;
    const bool capped = spring > kFriction * fn;
    const double ft = capped ? -kFriction * fn : -spring;
    EXPECT_NEAR(load.force.x(), ft, 1e-12 * std::abs(ft)) << "sliding at " << slide << " m/s";
    EXPECT_NEAR(load.force.z(), fn, 1e-12 * fn);
    EXPECT_NEAR(load.torque.y(), arm * ft, 1e-12 * std::abs(arm * ft));
    EXPECT_EQ(forces.sliding(), capped) << "sliding at " << slide << " m/s";
    // The spring shortened to the cap's length when sliding.
    const double u = capped ? kFriction * fn / (kMass * kStiffness * kRatio) : kDt * slide;
    const double energy = 0.5 * fn * kOverlap + 0.5 * kMass * kStiffness * kRatio * u * u;
    EXPECT_NEAR(forces.spring_energy(), energy, 1e-12 * energy);
  }
}

// Rolling resistance mu_r a k d against the roll (a sphere's lever is its
// radius), limited so that it at most stops the spin in a step: I w / dt.
TEST(ContactForces, RollingResistanceOpposesTheRollUpToItsLimit) {
  const RockBody body = Sphere();
  const double mu = 0.1;
  const std::vector<ContactLaw> laws = {Law(0.0, mu)};
  const StepSizes steps = Steps();
  const double fn = kMass * kStiffness * kOverlap;
  const double arm = -(kRadius - 0.5 * kOverlap);
  const double inertia = 0.4 * kMass * kRadius * kRadius;
  for (double spin : {0.5, 1.0e-6}) {  // rad/s about +y: under the limit, at it
    ContactForces<false> forces(laws, body, steps, kNoGravity);
    forces.Clear();
    forces.Add(FloorContact(kCentre, kRadius, kOverlap), 0);
    const auto load = forces.Step(kCentre, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, spin, 0.0),
                                  kDt, kUpright);
    // The contact point moves at w x r = (spin * arm, 0, 0): the spring's force.
    const double ft = -kMass * kStiffness * kRatio * kDt * spin * arm;
    const double rolling = std::min(mu * kRadius * fn, inertia * spin / kDt);
    const double exact = arm * ft - rolling;
    EXPECT_NEAR(load.torque.y(), exact, 1e-12 * std::abs(exact))
        << "spin " << spin << " rad/s: rolling " << rolling << ", spring's " << arm * ft;
    EXPECT_EQ(load.torque.x(), 0.0);
    EXPECT_EQ(load.torque.z(), 0.0);
  }
}

// At a flight's end the dashpot acts at the rock's normal speed there, no
// spring kept: f = m (k d - c v_n).
TEST(ContactForces, TheLandingForceIsTheDashpotsAtTheSpeedThere) {
  const RockBody body = Sphere();
  const std::vector<ContactLaw> laws = {Law()};
  const StepSizes steps = Steps();
  ContactForces<false> forces(laws, body, steps, kNoGravity);
  forces.Clear();
  forces.Add(FloorContact(kCentre, kRadius, 0.0), 0);  // touching, no overlap yet
  const double approach = -4.0;
  const auto load = forces.Landing(kCentre, Eigen::Vector3d(1.0, 0.0, approach),
                                   Eigen::Vector3d::Zero());
  const double exact = -kMass * kDamping * approach;
  EXPECT_NEAR(load.force.z(), exact, 1e-12 * exact) << "force " << load.force.transpose();
  EXPECT_EQ(load.force.x(), 0.0) << "no tangential force at the landing";
  EXPECT_FALSE(forces.touching()) << "a landing keeps no contact";
}

// A gentle contact asks for its gentle step; a step taken back restores the
// contacts and spring energy before it.
TEST(ContactForces, AGentleContactAsksForTheGentleStepAndUndoRestores) {
  const RockBody body = Sphere();
  const std::vector<ContactLaw> laws = {Law(0.0)};
  const StepSizes steps = Steps();
  ContactForces<false> forces(laws, body, steps, kNoGravity);
  forces.Clear();
  forces.Add(FloorContact(kCentre, kRadius, kOverlap), 0);
  forces.Step(kCentre, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDt, kUpright);
  // v_n = dt/2 k d = 0.04 m/s, under g t_c = 0.05 m/s.
  EXPECT_EQ(forces.needed_dt(), 4.0e-4);
  const double held = forces.spring_energy();
  forces.Clear();
  forces.Step(kCentre, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kDt, kUpright);
  EXPECT_FALSE(forces.touching());
  EXPECT_EQ(forces.spring_energy(), 0.0);
  forces.Undo();
  EXPECT_TRUE(forces.touching());
  EXPECT_EQ(forces.spring_energy(), held);
}

}  // namespace
}  // namespace rockcal::core
