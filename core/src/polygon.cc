#include "rockcal/core/polygon.h"

#include <algorithm>
#include <cmath>

#include "rockcal/core/numbers.h"

namespace rockcal::core {

bool PointInPolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  if (polygon.size() < 3) return false;
  Eigen::Vector2d lo = polygon[0], hi = polygon[0];
  for (const Eigen::Vector2d& v : polygon) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double tol = 1e-9 * std::max(1.0, (hi - lo).norm());
  bool inside = false;
  for (std::size_t k = 0, l = polygon.size() - 1; k < polygon.size(); l = k++) {
    const Eigen::Vector2d& a = polygon[l];
    const Eigen::Vector2d& b = polygon[k];
    // On the edge a-b?
    const Eigen::Vector2d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    if ((a + t * ab - p).norm() <= tol) return true;
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

std::vector<Eigen::Vector2d> DiscPolygon(const Eigen::Vector2d& centre, double radius) {
  std::vector<Eigen::Vector2d> disc;
  disc.reserve(kDiscVertices);
  for (int k = 0; k < kDiscVertices; ++k) {
    const double a = 2.0 * kPi * k / kDiscVertices;
    disc.push_back(centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return disc;
}

}  // namespace rockcal::core
