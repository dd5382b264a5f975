#include "flight.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rockcal::core {

double CeilingFlightTime(const Terrain& terrain, const RockState& s, double rb, double g) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
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

void Rotate(const Eigen::Vector3d& w, double h, Eigen::Quaterniond* q) {
  const double angle = w.norm() * h;
  if (angle > 0.0) {
    *q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, w.normalized())) * *q;
    q->normalize();
  }
}

void RotateFree(const RockBody& body, const Eigen::Vector3d& inv_inertia, double tau,
                double substep, RockState* s) {
  const bool isotropic =
      (body.inertia - Eigen::Vector3d::Constant(body.inertia.x())).cwiseAbs().maxCoeff() <
      1e-12 * body.inertia.x();
  if (isotropic) {
    Rotate(s->w, tau, &s->q);
    return;
  }
  const Eigen::Vector3d lb = body.inertia.cwiseProduct(s->q.conjugate() * s->w);
  const Eigen::Vector3d l = s->q * lb;
  auto omega = [&](const Eigen::Quaterniond& q) {
    return Eigen::Vector3d(q * inv_inertia.cwiseProduct(q.conjugate() * l));
  };
  const int n = std::max(1, static_cast<int>(std::ceil(tau / substep)));
  const double h = tau / n;
  for (int k = 0; k < n; ++k) {
    const Eigen::Quaterniond q0 = s->q;
    Rotate(omega(s->q), 0.5 * h, &s->q);
    const Eigen::Vector3d w_mid = omega(s->q);
    s->q = q0;
    Rotate(w_mid, h, &s->q);
  }
  s->w = omega(s->q);
}

}  // namespace rockcal::core
