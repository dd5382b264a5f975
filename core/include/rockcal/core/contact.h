// Contact kernels by role, stateless: plain numbers in, a force or torque out.
#ifndef ROCKCAL_CORE_CONTACT_H_
#define ROCKCAL_CORE_CONTACT_H_

#include <Eigen/Core>

namespace rockcal::core {

// Rolling resistance (a rockcal addition to the CRSP-3D law) is a torque
// mu_r rho N against the rolling rate: it resists like a force mu_r N at the
// contact, whatever the rock's shape and size, so mu_r means the same for a
// sphere, a cylinder rolling on its side and a block tumbling over its edges.
//
// The lever rho of a contact at `arm` (contact point minus centre of mass)
// for a rolling rate `roll` (angular velocity less its spin about the
// contact normal): the contact's distance from the rolling axis through the
// centre of mass, |roll / |roll| x arm|. A sphere's is its radius; 0 when
// roll is 0.
double RollingLever(const Eigen::Vector3d& roll, const Eigen::Vector3d& arm);

// The torque mu_r * lever * normal_force against `roll` (0 when roll is 0).
Eigen::Vector3d RollingResistanceTorque(double mu_r, double lever, double normal_force,
                                        const Eigen::Vector3d& roll);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_CONTACT_H_
