#include "rockcal/core/material.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "rockcal/core/numbers.h"

namespace rockcal::core {
namespace {

// Rebound speed ratio of x'' + 2 zeta x' + x = 0 (unit natural frequency),
// x(0) = 0, x'(0) = 1, ending when the contact force x + 2 zeta x' reaches 0.
double UnderdampedRestitution(double zeta) {
  const double wd = std::sqrt(1.0 - zeta * zeta);
  // Force zero: tan(wd t) = -2 zeta wd / (1 - 2 zeta^2), with wd t in (pi/2, pi].
  const double phase = kPi - std::atan2(2.0 * zeta * wd, 1.0 - 2.0 * zeta * zeta);
  const double t = phase / wd;
  const double v = std::exp(-zeta * t) * (std::cos(phase) - zeta / wd * std::sin(phase));
  return -v;
}

double OverdampedRestitution(double zeta) {
  const double root = std::sqrt(zeta * zeta - 1.0);
  const double l1 = -zeta + root, l2 = -zeta - root;  // l2 < l1 < 0
  // x = (e^{l1 t} - e^{l2 t}) / (l1 - l2); force x + 2 zeta x' = 0.
  const double a1 = 1.0 + 2.0 * zeta * l1, a2 = 1.0 + 2.0 * zeta * l2;  // both < 0
  const double t = std::log(a2 / a1) / (l1 - l2);
  const double v = (l1 * std::exp(l1 * t) - l2 * std::exp(l2 * t)) / (l1 - l2);
  return -v;
}

}  // namespace

double ClampedRestitution(double zeta) {
  if (zeta <= 0.0) return 1.0;
  if (zeta < 1.0 - 1e-9) return UnderdampedRestitution(zeta);
  if (zeta > 1.0 + 1e-9) return OverdampedRestitution(zeta);
  // Critical damping: the two formulas meet; average just around it.
  return 0.5 * (UnderdampedRestitution(1.0 - 1e-6) + OverdampedRestitution(1.0 + 1e-6));
}

double DampingRatioForRestitution(double e) {
  assert(e > 0.0 && e < 1.0);
  // ClampedRestitution falls monotonically from 1 (zeta = 0) towards 0.
  double lo = 0.0, hi = 1.0;
  while (ClampedRestitution(hi) > e) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ClampedRestitution(mid) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double VirtualSphereRadius(double roughness, double spacing) {
  if (roughness <= 0.0) return std::numeric_limits<double>::infinity();
  const double half = 0.5 * spacing;
  return (roughness * roughness + half * half) / (2.0 * roughness);
}

double MinRoughness(double spacing) { return spacing / 80.0; }

ContactLaw DeriveContactLaw(const Material& material, const HardnessModel& model) {
  ContactLaw law;
  const double h = std::clamp(material.hardness, 0.0, 1.0);
  law.restitution = std::clamp(material.restitution.value_or(h), model.restitution_min,
                               model.restitution_max);
  law.friction = material.friction.value_or(model.friction_soft -
                                            (model.friction_soft - model.friction_hard) * h);
  law.rolling_resistance = material.rolling_resistance.value_or(
      model.rolling_soft - (model.rolling_soft - model.rolling_hard) * h);
  law.contact_time = material.contact_time_s;
  law.vegetation_stress = material.vegetation_pa;
  const double ln_e = std::log(law.restitution);
  const double tc = law.contact_time;
  law.stiffness_per_mass = (kPi * kPi + ln_e * ln_e) / (tc * tc);
  const double omega = std::sqrt(law.stiffness_per_mass);
  law.damping_ratio = DampingRatioForRestitution(law.restitution);
  law.damping_per_mass = 2.0 * law.damping_ratio * omega;
  law.eq13_damping_ratio = -ln_e / std::sqrt(kPi * kPi + ln_e * ln_e);
  return law;
}

}  // namespace rockcal::core
