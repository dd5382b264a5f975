#include "flight.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rockcal/core/numbers.h"

namespace rockcal::core {

double CeilingFlightTime(const Terrain& terrain, const RockState& s, double rb, double g) {
  const double spacing = terrain.grid().spacing;
  const double vh = std::hypot(s.v.x(), s.v.y());
  const double t_cap = std::min(vh > 0 ? spacing / vh : kInf, 1.0);
  const double x1 = s.x.x() + s.v.x() * t_cap, y1 = s.x.y() + s.v.y() * t_cap;
  const double ceiling = terrain.Ceiling(std::min(s.x.x(), x1) - rb, std::max(s.x.x(), x1) + rb,
                                         std::min(s.x.y(), y1) - rb, std::max(s.x.y(), y1) + rb);
  // Vertical clearance above every obstacle under the swept footprint.
  const double h = s.x.z() - rb - ceiling;
  const double vz = s.v.z();  // gravity is along -z
  double tau = 0.0;
  if (h > 0.0) tau = std::min(t_cap, (vz + std::sqrt(vz * vz + 2.0 * g * h)) / g);
  return tau;
}

double GapFlightTime(double d, double speed, double g) {
  return 2.0 * d / (speed + std::sqrt(speed * speed + 2.0 * g * d));
}

void FlyCentre(const Eigen::Vector3d& gravity, double tau, RockState* s) {
  s->x += s->v * tau + 0.5 * gravity * tau * tau;
  s->v += gravity * tau;
  s->t += tau;
}

namespace {

// sin(x) / x and cos(x) from x^2 by their series, for x^2 <= 0.01 (the
// terms left out are below 1e-18 there): the half turns of contact steps and
// flight sub-steps. Multiplied by the reciprocals: a chain of divisions took
// longer than the rest of a contact step's turn.
constexpr double kSeriesBound = 0.01;
double SinOverX(double x2) {
  constexpr double k6 = 1.0 / 6.0, k20 = 1.0 / 20.0, k42 = 1.0 / 42.0, k72 = 1.0 / 72.0;
  return 1.0 - x2 * k6 * (1.0 - x2 * k20 * (1.0 - x2 * k42 * (1.0 - x2 * k72)));
}
double CosSeries(double x2) {
  constexpr double k12 = 1.0 / 12.0, k30 = 1.0 / 30.0, k56 = 1.0 / 56.0;
  return 1.0 - 0.5 * x2 * (1.0 - x2 * k12 * (1.0 - x2 * k30 * (1.0 - x2 * k56)));
}

// sin x and cos x, by the series where they hold.
void SinCos(double x, double* sin_x, double* cos_x) {
  const double x2 = x * x;
  if (x2 > kSeriesBound) {
    *sin_x = std::sin(x);
    *cos_x = std::cos(x);
    return;
  }
  *sin_x = x * SinOverX(x2);
  *cos_x = CosSeries(x2);
}

// The flow of one principal term M_i^2 / (2 I_i) of the kinetic energy for
// h: the body turns about its principal axis i at M_i / I_i, and its angular
// momentum in body axes m turns the other way about that axis.
template <int i>
void TurnAboutAxis(double h, const Eigen::Vector3d& inv_inertia, Eigen::Vector3d* m,
                   Eigen::Quaterniond* q) {
  constexpr int j = (i + 1) % 3, k = (i + 2) % 3;
  double sh, ch;
  SinCos(0.5 * h * (*m)[i] * inv_inertia[i], &sh, &ch);
  const double s = 2.0 * sh * ch, c = 1.0 - 2.0 * sh * sh;  // of the whole angle
  const double mj = (*m)[j], mk = (*m)[k];
  (*m)[j] = c * mj + s * mk;
  (*m)[k] = c * mk - s * mj;
  // q times the turn (ch, sh e_i), written out.
  const double w = q->w(), vi = q->vec()[i], vj = q->vec()[j], vk = q->vec()[k];
  q->w() = ch * w - sh * vi;
  q->vec()[i] = ch * vi + sh * w;
  q->vec()[j] = ch * vj + sh * vk;
  q->vec()[k] = ch * vk - sh * vj;
}

// The symmetric (Strang) splitting over h, x(h/2) y(h/2) z(h) y(h/2)
// x(h/2), second order and time-reversible, without its turns about x:
// consecutive ones merge.
void SplitStepInside(double h, const Eigen::Vector3d& inv_inertia, Eigen::Vector3d* m,
                     Eigen::Quaterniond* q) {
  TurnAboutAxis<1>(0.5 * h, inv_inertia, m, q);
  TurnAboutAxis<2>(h, inv_inertia, m, q);
  TurnAboutAxis<1>(0.5 * h, inv_inertia, m, q);
}

}  // namespace

void Rotate(const Eigen::Vector3d& w, double h, Eigen::Quaterniond* q) {
  const double x2 = 0.25 * h * h * w.squaredNorm();  // the half angle, squared
  if (!(x2 > 0.0)) return;
  double sin_half_over_rate, cos_half;
  if (x2 <= kSeriesBound) {  // without a square root or a division
    sin_half_over_rate = 0.5 * h * SinOverX(x2);
    cos_half = CosSeries(x2);
  } else {
    const double rate = w.norm();
    sin_half_over_rate = std::sin(0.5 * rate * h) / rate;
    cos_half = std::cos(0.5 * rate * h);
  }
  const Eigen::Vector3d axis = sin_half_over_rate * w;
  *q = Eigen::Quaterniond(cos_half, axis.x(), axis.y(), axis.z()) * *q;
  // Both factors are unit to rounding: one Newton step towards 1 / |q|
  // keeps q unit (to 1e-16 per step) without a square root.
  q->coeffs() *= 0.5 * (3.0 - q->squaredNorm());
}

void RotateFree(const RockBody& body, const Eigen::Vector3d& inv_inertia, double tau,
                double max_angle, RockState* s) {
  const bool isotropic =
      (body.inertia - Eigen::Vector3d::Constant(body.inertia.x())).cwiseAbs().maxCoeff() <
      1e-12 * body.inertia.x();
  if (isotropic) {
    Rotate(s->w, tau, &s->q);
    return;
  }
  Eigen::Vector3d m = body.inertia.cwiseProduct(s->q.conjugate() * s->w);  // body axes
  // The spin never exceeds sqrt(2 E / I_min) (E = sum I_i w_i^2 / 2).
  const double spin = std::sqrt(m.cwiseProduct(inv_inertia).dot(m) * inv_inertia.maxCoeff());
  // A turn so short that one symmetric step errs less than a fourth-order
  // sub-step of max_angle (the errors grow as the cube and the fifth power
  // of the angle) takes that one step, at 5 turns about the axes instead of 13.
  if (spin * tau <= std::pow(max_angle, 5.0 / 3.0)) {
    TurnAboutAxis<0>(0.5 * tau, inv_inertia, &m, &s->q);
    SplitStepInside(tau, inv_inertia, &m, &s->q);
    TurnAboutAxis<0>(0.5 * tau, inv_inertia, &m, &s->q);
    s->q.normalize();
    s->w = s->q * inv_inertia.cwiseProduct(m);
    return;
  }
  const int n = std::max(1, static_cast<int>(std::ceil(spin * tau / max_angle)));
  const double h = tau / n;
  // Three symmetric steps with the weights that cancel the third-order error
  // (the triple-jump composition): fourth order.
  const double cbrt2 = std::cbrt(2.0);
  const double outer = 1.0 / (2.0 - cbrt2), inner = -cbrt2 / (2.0 - cbrt2);
  const double a = outer * h, b = inner * h;
  TurnAboutAxis<0>(0.5 * a, inv_inertia, &m, &s->q);
  for (int k = 0; k < n; ++k) {
    SplitStepInside(a, inv_inertia, &m, &s->q);
    TurnAboutAxis<0>(0.5 * (a + b), inv_inertia, &m, &s->q);
    SplitStepInside(b, inv_inertia, &m, &s->q);
    TurnAboutAxis<0>(0.5 * (a + b), inv_inertia, &m, &s->q);
    SplitStepInside(a, inv_inertia, &m, &s->q);
    TurnAboutAxis<0>(k + 1 < n ? a : 0.5 * a, inv_inertia, &m, &s->q);
  }
  s->q.normalize();
  s->w = s->q * inv_inertia.cwiseProduct(m);
}

}  // namespace rockcal::core
