#include "rockcal/core/contact.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "rockcal/core/material.h"

namespace rockcal::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- normal: spring-dashpot, compressive only ------------------------------

TEST(NormalForce, SpringPlusDashpotClampedAtZero) {
  const NormalSpringDashpot law{1000.0, 10.0};
  // Approaching at 2 m/s with 1 cm overlap: k d + C |v|.
  EXPECT_DOUBLE_EQ(NormalForce(law, 0.01, -2.0), 30.0);
  // Opening at 0.5 m/s: the dashpot takes off part of the spring's push.
  EXPECT_DOUBLE_EQ(NormalForce(law, 0.01, 0.5), 5.0);
  // Opening at 2 m/s: k d - C v < 0, and the slope does not pull.
  EXPECT_EQ(NormalForce(law, 0.01, 2.0), 0.0);
}

// A rock of unit mass meets the slope at speed v0 along the normal; its
// overlap d follows d'' = -N(d, -d') until it separates. Returns the rebound
// speed ratio and the contact's duration. Classic fourth-order Runge-Kutta in
// steps of `period` / 200000.
struct Impact {
  double rebound_ratio, duration;
};
Impact NormalImpact(const NormalSpringDashpot& per_mass, double v0) {
  const double period = 2.0 * kPi / std::sqrt(per_mass.stiffness);
  const double h = period / 200000.0;
  auto accel = [&](double d, double dd) { return -NormalForce(per_mass, d, -dd); };
  double d = 0.0, dd = v0, t = 0.0;
  while (t < 10.0 * period) {
    const double k1d = dd, k1v = accel(d, dd);
    const double k2d = dd + 0.5 * h * k1v, k2v = accel(d + 0.5 * h * k1d, dd + 0.5 * h * k1v);
    const double k3d = dd + 0.5 * h * k2v, k3v = accel(d + 0.5 * h * k2d, dd + 0.5 * h * k2v);
    const double k4d = dd + h * k3v, k4v = accel(d + h * k3d, dd + h * k3v);
    const double d1 = d + h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
    const double dd1 = dd + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    if (d1 <= 0.0) {  // separated within this step: interpolate the time
      return {-dd1 / v0, t + h * d / (d - d1)};
    }
    d = d1;
    dd = dd1;
    t += h;
  }
  return {0.0, t};
}

// Without damping the contact is half a period of the spring, pi / omega,
// and the rock leaves as fast as it came.
TEST(NormalForce, UndampedImpactLastsHalfAPeriodAndReboundsFully) {
  const double k = 4.0e4;  // per unit mass: omega = 200 rad/s
  const Impact impact = NormalImpact({k, 0.0}, 3.0);
  EXPECT_NEAR(impact.duration, kPi / std::sqrt(k), 1e-6) << "duration " << impact.duration;
  EXPECT_NEAR(impact.rebound_ratio, 1.0, 1e-9) << "ratio " << impact.rebound_ratio;
}

// Damped and clamped: the closed form of x'' + 2 zeta w x' + w^2 x = 0 from
// x(0) = 0, x'(0) = v0, ending when the force w^2 x + 2 zeta w x' reaches 0,
// at w_d t = pi - atan2(2 zeta s, 1 - 2 zeta^2) (s = sqrt(1 - zeta^2),
// w_d = w s), with x'(t) = v0 exp(-zeta w t) (cos w_d t - zeta / s sin w_d t).
TEST(NormalForce, ClampedDampedImpactMatchesTheClosedForm) {
  const double omega = 200.0;
  for (double zeta : {0.1, 0.3, 0.6}) {
    const double s = std::sqrt(1.0 - zeta * zeta);
    const double phase = kPi - std::atan2(2.0 * zeta * s, 1.0 - 2.0 * zeta * zeta);
    const double t_end = phase / (omega * s);
    const double ratio =
        -std::exp(-zeta * omega * t_end) * (std::cos(phase) - zeta / s * std::sin(phase));
    const Impact impact = NormalImpact({omega * omega, 2.0 * zeta * omega}, 2.0);
    EXPECT_NEAR(impact.rebound_ratio, ratio, 1e-6)
        << "zeta " << zeta << ": ratio " << impact.rebound_ratio;
    // The force reaches 0 before the overlap does, so the contact lasts
    // longer than t_end and less than the unclamped half period pi / w_d.
    EXPECT_GT(impact.duration, t_end) << "zeta " << zeta;
    EXPECT_LT(impact.duration, kPi / (omega * s)) << "zeta " << zeta;
  }
}

// The law a material derives (per unit mass) gives a normal impact the
// material's restitution: rockcal's e is the rebound-to-impact speed ratio.
TEST(NormalForce, DerivedLawReboundsAtTheMaterialsRestitution) {
  for (double e : {0.2, 0.5, 0.8}) {
    Material m;
    m.restitution = e;
    const ContactLaw law = DeriveContactLaw(m);
    const Impact impact = NormalImpact({law.stiffness_per_mass, law.damping_per_mass}, 5.0);
    EXPECT_NEAR(impact.rebound_ratio, e, 1e-6) << "e " << e << ": ratio " << impact.rebound_ratio;
  }
}

// ---- tangential: spring with a Coulomb cap ---------------------------------

TEST(TangentialForce, BelowTheCapTheSpringHoldsItsDisplacement) {
  Eigen::Vector3d u(0.01, 0.02, 0.0);
  const Eigen::Vector3d f = TangentialForce({1000.0, 0.5}, 100.0, &u);  // cap 50 N
  EXPECT_TRUE(f.isApprox(Eigen::Vector3d(-10.0, -20.0, 0.0), 1e-15)) << f.transpose();
  EXPECT_EQ(u, Eigen::Vector3d(0.01, 0.02, 0.0));
}

TEST(TangentialForce, AtTheCapTheForceIsFrictionTimesNormalAndTheSpringShortens) {
  Eigen::Vector3d u(0.3, 0.4, 0.0);  // spring force 500 N, cap 50 N
  const Eigen::Vector3d f = TangentialForce({1000.0, 0.5}, 100.0, &u);
  EXPECT_TRUE(f.isApprox(Eigen::Vector3d(-30.0, -40.0, 0.0), 1e-14)) << f.transpose();
  EXPECT_TRUE(u.isApprox(Eigen::Vector3d(0.03, 0.04, 0.0), 1e-14)) << u.transpose();
  // Without a normal force nothing holds.
  Eigen::Vector3d v(0.3, 0.4, 0.0);
  EXPECT_EQ(TangentialForce({1000.0, 0.5}, 0.0, &v).norm(), 0.0);
}

// A contact slipping at a steady speed v: the spring builds up as k_s v t
// until it reaches f N, and then stays there (sliding).
TEST(TangentialForce, SteadySlipBuildsUpToTheCoulombLimit) {
  const TangentialSpring law{2000.0, 0.4};
  const double normal_force = 50.0, v = 0.1, dt = 1e-3;                // limit 20 N at t = 0.1 s
  const Eigen::Vector3d normal(0.0, 0.0, 1.0), velocity(v, 0.0, 0.3);  // 0.3: normal, no slip
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int k = 1; k <= 300; ++k) {
    u = CarryTangentialDisplacement(u, normal) + TangentialSlip(velocity, normal, dt);
    const Eigen::Vector3d f = TangentialForce(law, normal_force, &u);
    const double expected = std::min(law.stiffness * v * k * dt, law.friction * normal_force);
    EXPECT_NEAR(-f.x(), expected, 1e-9) << "step " << k;
    EXPECT_EQ(f.y(), 0.0);
    EXPECT_EQ(f.z(), 0.0);
  }
}

// Carried into a tilted tangent plane, the displacement keeps its length and
// lies in the plane.
TEST(TangentialForce, CarriedDisplacementTurnsWithTheContact) {
  const double theta = 0.3;
  const Eigen::Vector3d normal(std::sin(theta), 0.0, std::cos(theta));
  const Eigen::Vector3d u = CarryTangentialDisplacement({0.02, 0.0, 0.0}, normal);
  EXPECT_TRUE(u.isApprox(0.02 * Eigen::Vector3d(std::cos(theta), 0.0, -std::sin(theta)), 1e-14))
      << u.transpose();
  EXPECT_EQ(CarryTangentialDisplacement(Eigen::Vector3d::Zero(), normal), Eigen::Vector3d::Zero());
}

// ---- rolling resistance ----------------------------------------------------

// The lever of rolling resistance is the contact's distance from the rolling
// axis through the centre of mass.
TEST(RollingResistance, LeverIsTheDistanceFromTheRollingAxis) {
  const double a = 0.3;
  // A sphere rolling along +x on the ground: axis y, contact straight below.
  EXPECT_NEAR(RollingLever({0, 2, 0}, {0, 0, -a}), a, 1e-15);
  // A cylinder's element offset along its axis rolls on the same radius.
  EXPECT_NEAR(RollingLever({0, 2, 0}, {0, 0.7, -a}), a, 1e-15);
  // A cube of side L tipping about its bottom edge (along y): the edge lies
  // at (L/2, ., -L/2) from the centre, L / sqrt(2) from the axis.
  const double L = 1.2;
  EXPECT_NEAR(RollingLever({0, -1, 0}, {L / 2, 0.2, -L / 2}), L / std::sqrt(2.0), 1e-15);
  EXPECT_EQ(RollingLever(Eigen::Vector3d::Zero(), {0, 0, -a}), 0.0);
}

// The torque opposes the rolling rate with magnitude mu_r * lever * N, so
// that on a sphere it acts like a force mu_r N at the contact.
TEST(RollingResistance, TorqueOpposesRollingWithMuLeverN) {
  const Eigen::Vector3d roll(0.0, 3.0, 4.0);
  const Eigen::Vector3d t = RollingResistanceTorque(0.2, 0.5, 1000.0, roll);
  EXPECT_NEAR(t.norm(), 0.2 * 0.5 * 1000.0, 1e-9);
  EXPECT_NEAR(t.normalized().dot(roll.normalized()), -1.0, 1e-15);
  EXPECT_EQ(RollingResistanceTorque(0.2, 0.5, 1000.0, Eigen::Vector3d::Zero()),
            Eigen::Vector3d::Zero());
}

// A sphere of radius 0.25 m rolling along +x (axis y) while spinning about
// the vertical: only the rolling part is resisted, by mu_r a N about -y.
TEST(RollingResistance, SphereTorqueByHand) {
  const Eigen::Vector3d normal(0.0, 0.0, 1.0), w(0.0, 4.0, 3.0), arm(0.0, 0.0, -0.25);
  const Eigen::Vector3d roll = RollingRate(w, normal);
  EXPECT_EQ(roll, Eigen::Vector3d(0.0, 4.0, 0.0));
  const double lever = RollingLever(roll, arm);
  const Eigen::Vector3d t = RollingResistanceTorque(0.1, lever, 800.0, roll);
  EXPECT_TRUE(t.isApprox(Eigen::Vector3d(0.0, -0.1 * 0.25 * 800.0, 0.0), 1e-15)) << t.transpose();
}

// The torques together at most stop the rotation in one step: I w / dt.
TEST(RollingResistance, LimitedToStoppingTheRotationInOneStep) {
  const double inertia = 2.0, rate = 3.0, dt = 0.01;  // limit 600 N m
  EXPECT_TRUE(LimitRollingTorque({0.0, -1000.0, 0.0}, inertia, rate, dt)
                  .isApprox(Eigen::Vector3d(0.0, -600.0, 0.0), 1e-15));
  EXPECT_EQ(LimitRollingTorque({0.0, -100.0, 0.0}, inertia, rate, dt),
            Eigen::Vector3d(0.0, -100.0, 0.0));
  EXPECT_EQ(LimitRollingTorque(Eigen::Vector3d::Zero(), inertia, 0.0, dt), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace rockcal::core
