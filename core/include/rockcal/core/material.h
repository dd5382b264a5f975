// Slope materials and the hardness model: calibrated physical quantities in
// (hardness, roughness, contact time), derived stiffness and damping out.
#ifndef ROCKCAL_CORE_MATERIAL_H_
#define ROCKCAL_CORE_MATERIAL_H_

#include <optional>
#include <string>

namespace rockcal::core {

// One slope material, SI units.
struct Material {
  std::string id;
  double hardness = 0.5;          // H in [0, 1]
  double roughness_m = 0.0;       // R >= 0; 0 means a smooth surface (facets)
  double contact_time_s = 0.005;  // t_c > 0, duration of a normal impact
  std::optional<double> restitution;  // overrides e = H when set, in (0, 1)
  std::optional<double> friction;     // overrides f(H) when set, >= 0
  std::optional<double> rolling_resistance;  // overrides mu_r(H) when set, >= 0
  // Undergrowth (shrubs, saplings) on the material: the stress it puts on
  // the frontal area of a rock moving through it while the rock touches the
  // ground, against the rock's motion [Pa] (0: bare ground). Its deceleration
  // tau A / m falls with the rock's size: undergrowth stops small rocks
  // sooner than large ones, which nothing else of the contact law does.
  double vegetation_pa = 0.0;
};

// Constants of the default hardness model.
struct HardnessModel {
  double friction_soft = 0.9;  // f at H = 0
  double friction_hard = 0.4;  // f at H = 1
  // Rolling resistance mu_r (a rockcal addition to the CRSP-3D law): a torque
  // mu_r a N against rolling, a the element radius, N the normal force. Without
  // it a rock can rock for ever in a trough between virtual spheres.
  double rolling_soft = 0.15;  // mu_r at H = 0
  double rolling_hard = 0.02;  // mu_r at H = 1
  double restitution_min = 0.01;
  double restitution_max = 0.99;
};

// Contact parameters of a material, per unit rock mass (the slope's mass is
// infinite, k_n = m (pi^2 + ln^2 e) / t_c^2, so every force scales with m).
struct ContactLaw {
  double restitution = 0.5;   // e, rebound/impact speed ratio of a normal impact
  double friction = 0.65;     // Coulomb coefficient f
  double rolling_resistance = 0.085;  // mu_r: rolling torque / (element radius * normal force)
  double contact_time = 0.005;     // t_c [s]
  double stiffness_per_mass = 0.0;  // k_n / m [1/s^2]
  double damping_per_mass = 0.0;    // C / m [1/s], chosen so the clamped contact gives e
  double damping_ratio = 0.0;       // zeta = C / (2 sqrt(k m))
  double eq13_damping_ratio = 0.0;  // the manual's eq. 13 zeta (reported, not used)
  double tangential_ratio = 2.0 / 7.0;  // k_s / k_n
  double vegetation_stress = 0.0;       // tau [Pa], Material::vegetation_pa
};

// Derives the contact law of `material` with the hardness model. Pure function.
ContactLaw DeriveContactLaw(const Material& material, const HardnessModel& model = {});

// Restitution (rebound/impact speed) of a linear spring-dashpot with damping
// ratio zeta whose force is clamped at zero (the slope never pulls).
double ClampedRestitution(double zeta);

// Inverse of ClampedRestitution: the damping ratio giving restitution e in (0, 1).
double DampingRatioForRestitution(double e);

// Roughness R -> radius of virtual spheres a distance s apart that sag R
// between them: (R^2 + (s/2)^2) / (2R). Terrain takes s as the surface
// distance between neighbouring nodes along the fall line (the grid spacing
// on level ground). Returns +infinity for R == 0 (smooth).
double VirtualSphereRadius(double roughness, double spacing);

// Smallest roughness above 0 a site may give on a grid of spacing s: s / 80,
// whose virtual spheres have radius 10.006 s on level ground (twice the
// manual's largest, 60 ft on a 12 ft grid; up to 4 times that on faces of 60
// degrees and more, see Terrain). Below it r grows as s^2 / (8R) without
// bound, while the surface differs from the smooth facets (R = 0) by less
// than s / 80.
double MinRoughness(double spacing);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_MATERIAL_H_
