#include "rockcal/core/contact.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace rockcal::core {
namespace {

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

}  // namespace
}  // namespace rockcal::core
