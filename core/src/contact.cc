#include "rockcal/core/contact.h"

#include <Eigen/Geometry>

namespace rockcal::core {

double RollingLever(const Eigen::Vector3d& roll, const Eigen::Vector3d& arm) {
  const double rate = roll.norm();
  return rate > 0.0 ? roll.cross(arm).norm() / rate : 0.0;
}

Eigen::Vector3d RollingResistanceTorque(double mu_r, double lever, double normal_force,
                                        const Eigen::Vector3d& roll) {
  const double rate = roll.norm();
  if (!(rate > 0.0)) return Eigen::Vector3d::Zero();
  return -(mu_r * lever * normal_force / rate) * roll;
}

}  // namespace rockcal::core
