// The exact answer to one oblique impact of a solid sphere under the
// CRSP-3D contact law (docs/physics.md, Contact): a linear spring-dashpot along
// the normal whose force is clamped at zero (the surface never pulls), a
// tangential spring k_t with a Coulomb cap f times that normal force, no
// tangential damping, constant gravity throughout. The surface is flat and
// fixed; the contact's lever is the sphere's radius.
//
// The normal motion is the damped oscillator's, in closed form. The
// tangential motion goes through phases (the regimes of Maw, Barber and
// Fawcett 1976, Wear 38: 101-114; the oblique-impact tests of Chung and Ooi
// 2011, Granular Matter 13: 643-656, tests 6-8), each in closed form:
//  - stick: the spring's displacement u follows the slip velocity w of the
//    contact point (u' = w) and w' = -K u + g_t with K = kappa k_t / m,
//    kappa = 1 + m a^2 / I (7/2 for a solid sphere): a harmonic
//    oscillation at sqrt(K), whatever the normal force does; with
//    k_t / k_n = 2/7 its frequency is the normal one's;
//  - slip: u is held at the cap, s f N / k_t (s the sign it reached the cap
//    with), and w' = -s kappa f N / m + g_t, whose integral is the normal
//    impulse's: w = w_1 - s kappa f (delta'(t_1) - delta'(t) + g_n (t - t_1)).
// A stick phase ends when |u| reaches the cap; a slip phase when the cap
// would outgrow the spring that sticks (s w < d(cap)/dt); the contact when
// the normal force falls to zero. Each switching time is found by scanning
// the closed forms in 4000 steps of the contact time and bisecting to
// rounding: the answer is exact to about 1e-12 of the impact speed.
#ifndef ROCKCAL_TESTS_CORE_OBLIQUE_IMPACT_H_
#define ROCKCAL_TESTS_CORE_OBLIQUE_IMPACT_H_

#include <cmath>
#include <functional>
#include <stdexcept>

namespace rockcal::core::testing {

struct ImpactLaw {
  double omega = 0.0;                   // sqrt(k_n / m) [1/s]
  double zeta = 0.0;                    // damping ratio, c / m = 2 zeta omega; below 1
  double tangential_ratio = 2.0 / 7.0;  // k_t / k_n
  double friction = 0.0;                // Coulomb coefficient f
  double kappa = 3.5;                   // 1 + m a^2 / I
};

// The impact: gravity's components into the surface (g_n, along the
// inward normal) and along the tangent (g_t), the approach speed along the
// normal vn > 0, and the contact point's initial slip velocity w0 along
// the tangent (centre's tangential velocity less a times the spin).
struct ImpactStart {
  double gn = 0.0, gt = 0.0;
  double vn = 0.0;
  double slip = 0.0;
};

struct ImpactEnd {
  double duration = 0.0;    // s, from touch to the normal force's end
  double vn = 0.0;          // m/s, normal velocity then (positive: leaving)
  double impulse = 0.0;     // m/s, the tangential force's impulse per unit mass
  int phases = 0;           // stick and slip phases in all
  bool slipped = false;     // some phase slid
  bool stuck_last = false;  // the last phase before the end stuck
};

inline ImpactEnd SolveImpact(const ImpactLaw& law, const ImpactStart& in) {
  if (!(law.zeta >= 0.0 && law.zeta < 1.0) || !(in.vn > 0.0))
    throw std::invalid_argument("SolveImpact: an underdamped law and an approach speed > 0");
  const double w = law.omega, z = law.zeta;
  const double wd = w * std::sqrt(1.0 - z * z);
  // delta = gn / w^2 + e^{-z w t} (A cos wd t + B sin wd t), delta(0) = 0, delta'(0) = vn.
  const double A = -in.gn / (w * w);
  const double B = (in.vn + z * w * A) / wd;
  auto delta = [&](double t) {
    return in.gn / (w * w) + std::exp(-z * w * t) * (A * std::cos(wd * t) + B * std::sin(wd * t));
  };
  auto rate = [&](double t) {
    return std::exp(-z * w * t) *
           ((-z * w * A + wd * B) * std::cos(wd * t) + (-z * w * B - wd * A) * std::sin(wd * t));
  };
  auto force = [&](double t) { return w * w * delta(t) + 2.0 * z * w * rate(t); };  // N / m
  auto accel = [&](double t) { return in.gn - force(t); };
  // The cap in displacement units, f N / k_t, and its rate.
  const double kt = law.tangential_ratio * w * w;  // k_t / m
  auto cap = [&](double t) { return law.friction * force(t) / kt; };
  auto cap_rate = [&](double t) {
    return law.friction * (w * w * rate(t) + 2.0 * z * w * accel(t)) / kt;
  };
  const double period = M_PI / wd;
  const double h = period / 4000.0;
  // The first t in (t0, t_max] where g changes sign from its sign just after
  // t0 (g(t0 + ) taken as >= 0 by the callers), bisected; t_max if none.
  auto first_root = [&](double t0, double t_max, const std::function<double(double)>& g) {
    double lo = t0;
    for (double t = std::min(t0 + h, t_max);; t = std::min(t + h, t_max)) {
      if (g(t) < 0.0) {
        double hi = t;
        for (int i = 0; i < 200 && hi - lo > 1e-15 * period; ++i) {
          const double mid = 0.5 * (lo + hi);
          (g(mid) < 0.0 ? hi : lo) = mid;
        }
        return 0.5 * (lo + hi);
      }
      if (t >= t_max) return t_max;
      lo = t;
    }
  };
  ImpactEnd out;
  const double t_end = first_root(0.0, 3.0 * period, force);
  out.duration = t_end;
  out.vn = -rate(t_end);
  const double K = law.kappa * kt;
  const double W = std::sqrt(K);
  double t = 0.0, u = 0.0, slip = in.slip;
  bool stick = true;
  while (t < t_end) {
    ++out.phases;
    const double t1 = t;
    if (stick) {
      out.stuck_last = true;
      const double up = in.gt / K, u1 = u, w1 = slip;
      auto u_at = [&](double tt) {
        const double s = tt - t1;
        return up + (u1 - up) * std::cos(W * s) + w1 / W * std::sin(W * s);
      };
      auto w_at = [&](double tt) {
        const double s = tt - t1;
        return -(u1 - up) * W * std::sin(W * s) + w1 * std::cos(W * s);
      };
      // Sticks while |u| stays within the cap (a hair of rounding allowed at
      // the phase's start, where they are equal).
      const double slack = 1e-12 * (std::abs(u1) + in.vn / W);
      const double t2 =
          first_root(t1, t_end, [&](double tt) { return cap(tt) - std::abs(u_at(tt)) + slack; });
      u = u_at(t2);
      slip = w_at(t2);
      t = t2;
    } else {
      out.slipped = true;
      out.stuck_last = false;
      const double s = u >= 0.0 ? 1.0 : -1.0, w1 = slip, r1 = rate(t1);
      auto w_at = [&](double tt) {
        return w1 - s * law.kappa * law.friction * (r1 - rate(tt) + in.gn * (tt - t1)) +
               in.gt * (tt - t1);
      };
      const double slack = 1e-12 * (std::abs(w1) + in.vn);
      const double t2 =
          first_root(t1, t_end, [&](double tt) { return s * w_at(tt) - cap_rate(tt) + slack; });
      slip = w_at(t2);
      u = s * cap(t2);
      t = t2;
    }
    stick = !stick;
    if (out.phases > 1000) throw std::runtime_error("SolveImpact: no end of phases");
  }
  // w(t_end) - w0 = kappa J + g_t t_end.
  out.impulse = (slip - in.slip - in.gt * t_end) / law.kappa;
  return out;
}

}  // namespace rockcal::core::testing

#endif  // ROCKCAL_TESTS_CORE_OBLIQUE_IMPACT_H_
