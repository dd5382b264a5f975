// The contact law as stateless kernels by role (docs/physics.md, Contact): the
// normal spring-dashpot, the tangential spring with its Coulomb cap, and
// rolling resistance. Plain numbers in, a force or torque out; whatever a
// contact keeps from step to step (the tangential spring's displacement)
// belongs to the caller. A step's contact forces (core/src/contact_forces.h)
// call these and nothing else for the contact law.
#ifndef ROCKCAL_CORE_CONTACT_H_
#define ROCKCAL_CORE_CONTACT_H_

#include <Eigen/Core>

namespace rockcal::core {

// ---- normal: linear spring-dashpot (manual eq. 10), compressive only -------

// The normal spring-dashpot of one contact. The force's unit follows the
// coefficients': k_n [N/m] and C [N s/m] give newtons; ContactLaw's per-mass
// coefficients [1/s^2, 1/s] give the force per kg of rock.
struct NormalSpringDashpot {
  double stiffness = 0.0;  // k_n >= 0
  double damping = 0.0;    // C >= 0
};

// The normal force k_n d - C v_n of an overlap d >= 0 whose overlap opens at
// normal speed v_n (the relative velocity along the normal pointing out of
// the slope: negative while the rock approaches), and 0 where that is
// negative: the slope pushes, it never pulls.
double NormalForce(const NormalSpringDashpot& law, double overlap, double normal_speed);

// ---- tangential: spring with a Coulomb cap (manual eq. 11) -----------------

struct TangentialSpring {
  double stiffness = 0.0;  // k_s > 0 (ContactLaw: k_n * tangential_ratio)
  double friction = 0.0;   // Coulomb coefficient f >= 0
};

// A contact's spring displacement `u` carried into the tangent plane of
// `normal` (unit) at the next step: its normal part removed, its length kept
// (a spring turning with the contact neither stretches nor relaxes).
Eigen::Vector3d CarryTangentialDisplacement(const Eigen::Vector3d& u,
                                            const Eigen::Vector3d& normal);

// The tangential part of `velocity` times dt: the slip the spring takes in
// one step.
Eigen::Vector3d TangentialSlip(const Eigen::Vector3d& velocity, const Eigen::Vector3d& normal,
                               double dt);

// The spring force -k_s u of the displacement *u, capped at f times
// `normal_force`. When the cap holds (sliding), *u is shortened to the
// length whose spring force is the cap, so the spring does not keep
// stretching while the contact slides.
Eigen::Vector3d TangentialForce(const TangentialSpring& law, double normal_force,
                                Eigen::Vector3d* u);

// ---- rolling resistance -----------------------------------------------------

// Rolling resistance (a rockcal addition to the CRSP-3D law) is a torque
// mu_r rho N against the rolling rate: it resists like a force mu_r N at the
// contact, whatever the rock's shape and size, so mu_r means the same for a
// sphere, a cylinder rolling on its side and a block tumbling over its edges.

// The rolling rate of angular velocity `w` on a contact of unit `normal`: w
// less its spin about the normal.
Eigen::Vector3d RollingRate(const Eigen::Vector3d& w, const Eigen::Vector3d& normal);

// The lever rho of a contact at `arm` (contact point minus centre of mass)
// for a rolling rate `roll` (angular velocity less its spin about the
// contact normal): the contact's distance from the rolling axis through the
// centre of mass, |roll / |roll| x arm|. A sphere's is its radius; 0 when
// roll is 0.
double RollingLever(const Eigen::Vector3d& roll, const Eigen::Vector3d& arm);

// The torque mu_r * lever * normal_force against `roll` (0 when roll is 0).
Eigen::Vector3d RollingResistanceTorque(double mu_r, double lever, double normal_force,
                                        const Eigen::Vector3d& roll);

// The rolling torques of all a rock's contacts together, `torque`, limited
// so that in one step dt they at most stop a rotation at `rate` [rad/s] of a
// body whose smallest moment of inertia is `inertia`: |torque| <= I w / dt.
// Each torque opposes the rotation, so their sum only takes energy out.
Eigen::Vector3d LimitRollingTorque(const Eigen::Vector3d& torque, double inertia, double rate,
                                   double dt);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_CONTACT_H_
