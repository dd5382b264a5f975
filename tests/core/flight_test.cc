// Torque-free rotation in flight (core/src/flight.cc) against the exact
// motion of a symmetric top, and its conservation and order on a box.
#include "flight.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace rockcal::core {
namespace {

RockBody BodyWithInertia(const Eigen::Vector3d& inertia) {
  RockBody body;
  body.shape = Shape::kBox;
  body.mass = 1.0;
  body.inertia = inertia;
  return body;
}

RockState Spinning(const Eigen::Quaterniond& q, const Eigen::Vector3d& w) {
  RockState s;
  s.x.setZero();
  s.v.setZero();
  s.w = w;
  s.q = q;
  s.t = 0.0;
  return s;
}

Eigen::Vector3d AngularMomentum(const RockBody& body, const RockState& s) {
  return s.q * body.inertia.cwiseProduct(s.q.conjugate() * s.w);
}

double Energy(const RockBody& body, const RockState& s) {
  const Eigen::Vector3d wb = s.q.conjugate() * s.w;
  return 0.5 * wb.dot(body.inertia.cwiseProduct(wb));
}

// A symmetric top (I1 = I2) turns about its fixed angular momentum L at
// |L| / I1 and about its own axis at (1 / I3 - 1 / I1) L3, the two turns
// commuting: R(t) = exp(t L / I1) R0 exp(t (1/I3 - 1/I1) L3 e3).
TEST(RotateFree, FollowsTheExactMotionOfASymmetricTop) {
  const RockBody body = BodyWithInertia({1.0, 1.0, 2.5});
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  RockState s = Spinning(q0, q0 * Eigen::Vector3d(2.0, -1.0, 6.0));
  const Eigen::Vector3d l = AngularMomentum(body, s);
  const double l3 = (q0.conjugate() * l).z();
  const double tau = 3.0;
  RotateFree(body, body.inertia.cwiseInverse(), tau, kFlightRotationAngle, &s);
  const Eigen::Quaterniond exact =
      Eigen::Quaterniond(Eigen::AngleAxisd(tau * l.norm() / 1.0, l.normalized())) * q0 *
      Eigen::Quaterniond(
          Eigen::AngleAxisd(tau * (1.0 / 2.5 - 1.0 / 1.0) * l3, Eigen::Vector3d::UnitZ()));
  EXPECT_LT(s.q.angularDistance(exact), 1e-6);
  EXPECT_LT((AngularMomentum(body, s) - l).norm(), 1e-12 * l.norm());
}

// The exact orientation of the symmetric top of the test above after tau.
Eigen::Quaterniond ExactTop(const RockState& s0, double tau) {
  const Eigen::Vector3d l =
      s0.q * Eigen::Vector3d(1.0, 1.0, 2.5).cwiseProduct(s0.q.conjugate() * s0.w);
  const double l3 = (s0.q.conjugate() * l).z();
  return Eigen::Quaterniond(Eigen::AngleAxisd(tau * l.norm(), l.normalized())) * s0.q *
         Eigen::Quaterniond(
             Eigen::AngleAxisd(tau * (1.0 / 2.5 - 1.0) * l3, Eigen::Vector3d::UnitZ()));
}

// A turn shorter than max_angle^(5/3) takes one symmetric step: it must err
// no more than one fourth-order sub-step of max_angle does.
TEST(RotateFree, AShortTurnErrsNoMoreThanAFullSubStep) {
  const RockBody body = BodyWithInertia({1.0, 1.0, 2.5});
  const Eigen::Vector3d inv = body.inertia.cwiseInverse();
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));
  const RockState s0 = Spinning(q0, q0 * Eigen::Vector3d(2.0, -1.0, 6.0));
  // The spin bound RotateFree counts its sub-steps from: sqrt(2 E / I_min).
  const Eigen::Vector3d wb = q0.conjugate() * s0.w;
  const double spin = std::sqrt(wb.dot(body.inertia.cwiseProduct(wb)) / 1.0);
  auto error = [&](double angle) {
    RockState s = s0;
    RotateFree(body, inv, angle / spin, kFlightRotationAngle, &s);
    return s.q.angularDistance(ExactTop(s0, angle / spin));
  };
  const double short_turn = 0.99 * std::pow(kFlightRotationAngle, 5.0 / 3.0);
  const double full_step = error(kFlightRotationAngle);
  EXPECT_GT(full_step, 0.0);
  EXPECT_LE(error(short_turn), full_step);
  // And it is the symmetric step: second order, its error falling eightfold
  // (the cube of the turn) when the turn is halved.
  EXPECT_GT(error(short_turn) / error(0.5 * short_turn), 6.0);
}

// A box (1 x 0.7 x 0.4 m): its angular momentum stays fixed in the world to
// rounding, its energy within 1e-8 over 3 s of tumbling at 9 rad/s, and the
// error falls as the fourth power of the sub-step.
TEST(RotateFree, KeepsMomentumAndEnergyAndIsOfFourthOrder) {
  const RockBody body = BodyWithInertia(
      Eigen::Vector3d(0.7 * 0.7 + 0.4 * 0.4, 1.0 + 0.4 * 0.4, 1.0 + 0.7 * 0.7) / 12.0);
  const Eigen::Vector3d inv = body.inertia.cwiseInverse();
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  const RockState start = Spinning(q0, Eigen::Vector3d(3.0, -7.0, 5.0));
  const double tau = 3.0;
  auto turned = [&](double max_angle) {
    RockState s = start;
    RotateFree(body, inv, tau, max_angle, &s);
    return s;
  };
  const RockState s = turned(kFlightRotationAngle);
  const Eigen::Vector3d l = AngularMomentum(body, start);
  EXPECT_LT((AngularMomentum(body, s) - l).norm(), 1e-12 * l.norm());
  EXPECT_NEAR(Energy(body, s), Energy(body, start), 1e-8 * Energy(body, start));
  const RockState fine = turned(kFlightRotationAngle / 16.0);
  const double coarse_error = turned(0.2).q.angularDistance(fine.q);
  const double half_error = turned(0.1).q.angularDistance(fine.q);
  EXPECT_GT(coarse_error / half_error, 12.0);  // 16 for fourth order, 4 for second
  EXPECT_LT(s.q.angularDistance(fine.q), 1e-5);
}

}  // namespace
}  // namespace rockcal::core
