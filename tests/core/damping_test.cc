// The contact law's damping role (core/src/damping.h): the small Cholesky,
// the damping share, and the implicit dashpot solve of one contact and of
// several, each against its exact answer.
#include "damping.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace rockcal::core {
namespace damping_test {

// ---- SolveSmallSpd -----------------------------------------------------------

TEST(SolveSmallSpd, SolvesAKnownSystemFromItsLowerTriangle) {
  // a = L L^T with L = [2 0 0; 1 2 0; -1 0.5 3], x = (1, -2, 3).
  const Eigen::Matrix3d l = (Eigen::Matrix3d() << 2, 0, 0, 1, 2, 0, -1, 0.5, 3).finished();
  const Eigen::Matrix3d full = l * l.transpose();
  const Eigen::Vector3d x(1.0, -2.0, 3.0);
  const Eigen::Vector3d rhs = full * x;
  double a[4][4], b[4];
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int r = 0; r < 4; ++r) {
    b[r] = nan;
    for (int c = 0; c < 4; ++c) a[r][c] = nan;  // the upper triangle and the rest: unread
  }
  for (int r = 0; r < 3; ++r) {
    b[r] = rhs[r];
    for (int c = 0; c <= r; ++c) a[r][c] = full(r, c);
  }
  SolveSmallSpd<4>(3, a, b);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(b[r], x[r], 1e-13) << "x[" << r << "]";
  // a holds the Cholesky factor.
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) EXPECT_NEAR(a[r][c], l(r, c), 1e-14) << "L(" << r << ", " << c << ")";
}

// ---- DampingShare ------------------------------------------------------------

TEST(DampingShare, EqualContactsShareSqrtNOfTheDashpot) {
  // n equal overlaps: each c / sqrt(n), so the shares' squares sum to 1.
  for (std::size_t n : {2u, 3u, 4u}) {
    const double d = 0.003;
    const double norm = d * std::sqrt(static_cast<double>(n));
    EXPECT_NEAR(DampingShare(d, norm, n, false), 1.0 / std::sqrt(static_cast<double>(n)), 1e-15)
        << n << " contacts";
    // Touching without overlap (a landing's first instant): equal shares too.
    EXPECT_DOUBLE_EQ(DampingShare(0.0, 0.0, n, false), 1.0 / std::sqrt(static_cast<double>(n)));
  }
  // Unequal: in proportion to the overlap.
  EXPECT_DOUBLE_EQ(DampingShare(0.003, 0.005, 2, false), 0.6);
  EXPECT_DOUBLE_EQ(DampingShare(0.004, 0.005, 2, false), 0.8);
  // One contact, or a sphere: the whole law.
  EXPECT_EQ(DampingShare(0.003, 0.003, 1, false), 1.0);
  EXPECT_EQ(DampingShare(0.003, 0.005, 2, true), 1.0);
}

// ---- the implicit dashpot of one contact --------------------------------------

// A contact's law per unit mass and a step, as simulate.cc takes them.
constexpr double kStiffness = 4.0e5;  // k / m [1/s^2]
constexpr double kDamping = 300.0;    // c / m [1/s]
constexpr double kOverlap = 2.0e-3;   // [m]
constexpr double kDt = 1.0e-4;        // [s]

TEST(ImplicitNormalSpeed, SolvesTheTrapezoidalStep) {
  // v_n = v_half + dt/2 (s k d - s c v_n + g_n) for the returned v_n.
  for (double s : {1.0, 2.5}) {
    const double v_half = -3.0, g_n = -8.0;
    const double vn = ImplicitNormalSpeed(v_half, kDt, s, kStiffness, kOverlap, g_n, kDamping);
    const double rhs = v_half + 0.5 * kDt * (s * kStiffness * kOverlap - s * kDamping * vn + g_n);
    EXPECT_NEAR(vn, rhs, 1e-14) << "s " << s;
  }
}

// The joint solve with one contact is the closed form: through the centre
// of a sphere (s = 1) and the tangential motion left alone.
TEST(JointDashpots, OneContactOnASphereIsTheClosedForm) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.6, 0.0, 0.8);
  const Eigen::Vector3d g(0.0, 0.0, -9.81), v_half(4.0, 1.0, -3.0);
  JointDashpots<3> dashpots;
  dashpots.Resize(1);
  dashpots.row(0) << n, Eigen::Vector3d::Zero();
  dashpots.terms(0) = {0.5 * kDt * kDamping, 0.5 * kDt * kStiffness * kOverlap};
  const Eigen::Vector3d free = v_half + 0.5 * kDt * g;
  const Eigen::Vector3d u = dashpots.Solve(free, [] { return Eigen::Matrix3d::Identity().eval(); });
  const double exact = ImplicitNormalSpeed(v_half.dot(n), kDt, 1.0, kStiffness, kOverlap, g.dot(n), kDamping);
  EXPECT_NEAR(u.dot(n), exact, 1e-14) << "solved " << u.dot(n) << ", exact " << exact;
  const Eigen::Vector3d tangential = (u - free) - n * n.dot(u - free);
  EXPECT_LT(tangential.norm(), 1e-15) << "tangential change " << tangential.transpose();
  EXPECT_FALSE(dashpots.pulling(0));
}

// Off the centre of a cluster the contact meets the rock's effective mass
// there: s = g^T M^-1 g = 1 + m |r x n|^2_{J^-1}. Solved in the contacts'
// space (one contact of six degrees of freedom).
TEST(JointDashpots, OneContactOffCentreMeetsTheEffectiveMass) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.0, 0.6, 0.8);
  const Eigen::Vector3d arm(0.5, -0.2, -0.4);
  const Eigen::Vector3d inertia_per_mass(0.10, 0.15, 0.20);  // J / m, world axes
  Eigen::Matrix<double, 6, 1> row, reach, free;
  row << n, arm.cross(n);
  reach << n, arm.cross(n).cwiseQuotient(inertia_per_mass);  // M^-1 g
  const Eigen::Vector3d g(0.0, 0.0, -9.81), v_half(2.0, 0.5, -4.0), w_half(1.0, -3.0, 0.5);
  free << v_half + 0.5 * kDt * g, w_half;
  JointDashpots<6> dashpots;
  dashpots.Resize(1);
  dashpots.row(0) = row;
  dashpots.reach(0) = reach;
  dashpots.terms(0) = {0.5 * kDt * kDamping, 0.5 * kDt * kStiffness * kOverlap};
  bool full = false;
  const Eigen::Matrix<double, 6, 1> u = dashpots.Solve(free, [&] {
    full = true;
    Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Identity();
    m.bottomRightCorner<3, 3>() = inertia_per_mass.asDiagonal();
    return m;
  });
  EXPECT_FALSE(full) << "one contact of a cluster is solved in the contacts' space";
  const double s = row.dot(reach);
  const double exact = ImplicitNormalSpeed(v_half.dot(n) + w_half.dot(arm.cross(n)), kDt, s,
                                           kStiffness, kOverlap, g.dot(n), kDamping);
  EXPECT_NEAR(row.dot(u), exact, 1e-13) << "solved " << row.dot(u) << ", exact " << exact << ", s " << s;
}

// A contact separating faster than k d / c would pull: it takes no part.
TEST(JointDashpots, APullingContactTakesNoPart) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  JointDashpots<3> dashpots;
  dashpots.Resize(1);
  dashpots.row(0) << n, Eigen::Vector3d::Zero();
  dashpots.terms(0) = {0.5 * kDt * kDamping, 0.5 * kDt * kStiffness * kOverlap};
  // k d / c = 2.67 m/s: leaving at 5 m/s.
  const Eigen::Vector3d free(1.0, 0.0, 5.0);
  const Eigen::Vector3d u = dashpots.Solve(free, [] { return Eigen::Matrix3d::Identity().eval(); });
  EXPECT_TRUE(dashpots.pulling(0));
  EXPECT_EQ(u, free) << "u " << u.transpose();
}

// Several contacts of a cluster together, in the contacts' space (3) and in
// the full 6 x 6 system (7), against a dense solve of
// (M + sum c_i g_i g_i^T) u = M free + sum k d_i g_i.
TEST(JointDashpots, SeveralContactsSolveTheJointSystem) {
  const Eigen::Vector3d inertia_per_mass(0.12, 0.09, 0.21);
  Eigen::Matrix<double, 6, 6> mass = Eigen::Matrix<double, 6, 6>::Identity();
  mass.bottomRightCorner<3, 3>() = inertia_per_mass.asDiagonal();
  Eigen::Matrix<double, 6, 1> free;
  free << 0.3, -0.2, -2.0, 0.4, 0.1, -0.3;
  for (int contacts : {3, 7}) {
    JointDashpots<6> dashpots;
    dashpots.Resize(static_cast<std::size_t>(contacts));
    Eigen::Matrix<double, 6, 6> a = mass;
    Eigen::Matrix<double, 6, 1> b = mass * free;
    for (int i = 0; i < contacts; ++i) {
      const double phi = 0.9 * i;
      const Eigen::Vector3d n = Eigen::Vector3d(0.2 * std::cos(phi), 0.2 * std::sin(phi), 1.0).normalized();
      const Eigen::Vector3d arm(0.4 * std::cos(phi + 0.3), 0.4 * std::sin(phi + 0.3), -0.5);
      Eigen::Matrix<double, 6, 1> row, reach;
      row << n, arm.cross(n);
      reach << n, arm.cross(n).cwiseQuotient(inertia_per_mass);
      dashpots.row(static_cast<std::size_t>(i)) = row;
      dashpots.reach(static_cast<std::size_t>(i)) = reach;
      const double damping = 0.5 * kDt * kDamping * (0.5 + 0.1 * i);
      const double spring = 0.5 * kDt * kStiffness * kOverlap * (1.0 + 0.2 * i);
      dashpots.terms(static_cast<std::size_t>(i)) = {damping, spring};
      a += damping * row * row.transpose();
      b += spring * row;
    }
    const Eigen::Matrix<double, 6, 1> exact = a.ldlt().solve(b);
    const Eigen::Matrix<double, 6, 1> u = dashpots.Solve(free, [&] { return mass; });
    for (int i = 0; i < contacts; ++i)
      ASSERT_FALSE(dashpots.pulling(static_cast<std::size_t>(i))) << "contact " << i << " pulls";
    EXPECT_LT((u - exact).norm(), 1e-13 * exact.norm())
        << contacts << " contacts: solved " << u.transpose() << ", exact " << exact.transpose();
  }
}

}  // namespace damping_test
}  // namespace rockcal::core
