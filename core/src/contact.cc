#include "rockcal/core/contact.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace rockcal::core {

double NormalForce(const NormalSpringDashpot& law, double overlap, double normal_speed) {
  return std::max(0.0, law.stiffness * overlap - law.damping * normal_speed);
}

Eigen::Vector3d CarryTangentialDisplacement(const Eigen::Vector3d& u,
                                            const Eigen::Vector3d& normal) {
  const double len = u.norm();
  Eigen::Vector3d carried = u - normal * normal.dot(u);
  const double nlen = carried.norm();
  if (nlen > 0) carried *= len / nlen;
  return carried;
}

Eigen::Vector3d TangentialSlip(const Eigen::Vector3d& velocity, const Eigen::Vector3d& normal,
                               double dt) {
  return dt * (velocity - normal * normal.dot(velocity));
}

Eigen::Vector3d TangentialForce(const TangentialSpring& law, double normal_force,
                                Eigen::Vector3d* u) {
  Eigen::Vector3d force = -law.stiffness * *u;
  const double cap = law.friction * normal_force;
  const double magnitude = force.norm();
  if (magnitude > cap) {
    force *= cap / magnitude;
    *u = -force / law.stiffness;
  }
  return force;
}

Eigen::Vector3d RollingRate(const Eigen::Vector3d& w, const Eigen::Vector3d& normal) {
  return w - normal * normal.dot(w);
}

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

Eigen::Vector3d LimitRollingTorque(const Eigen::Vector3d& torque, double inertia, double rate,
                                   double dt) {
  const double norm = torque.norm();
  const double limit = inertia * rate / dt;
  return norm > limit ? Eigen::Vector3d(torque * (limit / norm)) : torque;
}

}  // namespace rockcal::core
