#include "rockcal/sites/geometry.h"

#include <algorithm>
#include <cmath>

namespace rockcal::sites {
namespace {

bool Valid(const core::HeightGrid& g, int i, int j) {
  return i >= 0 && j >= 0 && i < g.nx && j < g.ny && !std::isnan(g.z[g.index(i, j)]);
}

// Cell (i, j) holding (x, y) and the fractions inside it; false outside the grid.
bool Locate(const core::HeightGrid& g, double x, double y, int* i, int* j, double* fx, double* fy) {
  if (g.nx < 2 || g.ny < 2) return false;
  const double u = (x - g.x0) / g.spacing, v = (y - g.y0) / g.spacing;
  if (!(u >= 0.0 && v >= 0.0 && u <= g.nx - 1 && v <= g.ny - 1)) return false;
  *i = std::min(static_cast<int>(u), g.nx - 2);
  *j = std::min(static_cast<int>(v), g.ny - 2);
  *fx = u - *i;
  *fy = v - *j;
  return true;
}

}  // namespace

double SignedArea(const Polygon& polygon) {
  double a = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& p = polygon[k];
    const Eigen::Vector2d& q = polygon[(k + 1) % polygon.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Whether segments [a, b] and [c, d] share a point (tolerance `eps` on the
// orientation tests).
bool SegmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d, double eps) {
  const double d1 = Cross(b - a, c - a), d2 = Cross(b - a, d - a);
  const double d3 = Cross(d - c, a - c), d4 = Cross(d - c, b - c);
  if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) &&
      ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps)))
    return true;
  // Touching or collinear: a point of one segment on the other.
  auto on = [eps](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                  double turn) {
    return std::abs(turn) <= eps && std::min(p.x(), q.x()) - 1e-12 <= r.x() &&
           r.x() <= std::max(p.x(), q.x()) + 1e-12 && std::min(p.y(), q.y()) - 1e-12 <= r.y() &&
           r.y() <= std::max(p.y(), q.y()) + 1e-12;
  };
  return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

}  // namespace

std::optional<std::pair<int, int>> FindSelfIntersection(const Polygon& ring) {
  // Repeated vertices (e.g. the first one again at the end) make no edge.
  Polygon polygon;
  for (const Eigen::Vector2d& v : ring)
    if (polygon.empty() || v != polygon.back()) polygon.push_back(v);
  while (polygon.size() > 1 && polygon.back() == polygon.front()) polygon.pop_back();
  if (polygon.size() < 3) return std::nullopt;
  const int n = static_cast<int>(polygon.size());
  double scale = 0.0;
  for (const Eigen::Vector2d& v : polygon) scale = std::max(scale, (v - polygon[0]).norm());
  const double eps = 1e-12 * scale * scale;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = polygon[static_cast<std::size_t>(i)];
    const Eigen::Vector2d& b = polygon[static_cast<std::size_t>((i + 1) % n)];
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector2d& c = polygon[static_cast<std::size_t>(j)];
      const Eigen::Vector2d& d = polygon[static_cast<std::size_t>((j + 1) % n)];
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      if (!neighbours) {
        if (SegmentsMeet(a, b, c, d, eps)) return std::make_pair(i, j);
      } else {
        // Neighbours share a vertex; they must not fold back over each other.
        const Eigen::Vector2d shared = j == i + 1 ? b : a;
        const Eigen::Vector2d p = j == i + 1 ? a : b, q = j == i + 1 ? d : c;
        const Eigen::Vector2d u = p - shared, w = q - shared;
        if (std::abs(Cross(u, w)) <= eps && u.dot(w) > 0) return std::make_pair(i, j);
      }
    }
  }
  return std::nullopt;
}

bool OnTerrain(const core::HeightGrid& grid, double x, double y) {
  int i = 0, j = 0;
  double fx = 0, fy = 0;
  if (!Locate(grid, x, y, &i, &j, &fx, &fy)) return false;
  return Valid(grid, i, j) && Valid(grid, i + 1, j) && Valid(grid, i, j + 1) &&
         Valid(grid, i + 1, j + 1);
}

std::optional<double> ElevationAt(const core::HeightGrid& grid, double x, double y) {
  if (!OnTerrain(grid, x, y)) return std::nullopt;
  int i = 0, j = 0;
  double fx = 0, fy = 0;
  Locate(grid, x, y, &i, &j, &fx, &fy);
  const double z00 = grid.z[grid.index(i, j)], z11 = grid.z[grid.index(i + 1, j + 1)];
  if (fx >= fy) {  // lower-right triangle (i,j) (i+1,j) (i+1,j+1)
    const double z10 = grid.z[grid.index(i + 1, j)];
    return z00 + fx * (z10 - z00) + fy * (z11 - z10);
  }
  const double z01 = grid.z[grid.index(i, j + 1)];
  return z00 + fy * (z01 - z00) + fx * (z11 - z01);
}

std::optional<Eigen::Vector2d> FindOffTerrain(const core::HeightGrid& grid, const Polygon& polygon,
                                              double step) {
  for (const Eigen::Vector2d& v : polygon)
    if (!OnTerrain(grid, v.x(), v.y())) return v;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& a = polygon[k];
    const Eigen::Vector2d& b = polygon[(k + 1) % polygon.size()];
    const int n = static_cast<int>(std::ceil((b - a).norm() / step));
    for (int m = 1; m < n; ++m) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(m) / n);
      if (!OnTerrain(grid, p.x(), p.y())) return p;
    }
  }
  Eigen::Vector2d lo = polygon[0], hi = polygon[0];
  for (const Eigen::Vector2d& v : polygon) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / step));
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / step));
  for (int b = 1; b < ny; ++b) {
    for (int a = 1; a < nx; ++a) {
      const Eigen::Vector2d p(lo.x() + (hi.x() - lo.x()) * a / nx,
                              lo.y() + (hi.y() - lo.y()) * b / ny);
      if (PointInPolygon(polygon, p) && !OnTerrain(grid, p.x(), p.y())) return p;
    }
  }
  return std::nullopt;
}

int NodesInside(const core::HeightGrid& grid, const Polygon& polygon) {
  int n = 0;
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i)
      n += PointInPolygon(polygon, Eigen::Vector2d(grid.x(i), grid.y(j)));
  return n;
}

}  // namespace rockcal::sites
