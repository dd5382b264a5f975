// The Delaunay triangulation of scattered plan points (Qhull) and the point
// location that grids them (gridding.cc): a triangle's vertices, its
// neighbours and the barycentric coordinates of a point in it.
#ifndef ROCKCAL_SITES_SRC_DELAUNAY_H_
#define ROCKCAL_SITES_SRC_DELAUNAY_H_

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace rockcal::sites {

class Delaunay {
 public:
  // Twice a triangle's area below this (in the points' units) is a sliver
  // without barycentric coordinates: GridPoints triangulates in units of the
  // data spacing, where it means the same whatever the data's units.
  static constexpr double kDegenerateArea2 = 1e-5;

  // Triangulates the points (u[k], v[k]) (distinct, at least 3 not on one
  // line): the lower hull of the points lifted onto a paraboloid, Qhull's
  // "d Qbb Qc Qz Qt" (cocircular points, as on a regular grid, give
  // triangles, not polygons). False with *error (Qhull's message) when Qhull
  // fails.
  bool Build(const std::vector<double>& u, const std::vector<double>& v, std::string* error);

  int size() const { return static_cast<int>(vertices_.size()); }
  // Triangle f's vertices (indices of the points), counter-clockwise.
  const std::array<int, 3>& vertices(int f) const { return vertices_[f]; }
  // The triangle across triangle f's edge opposite vertex k; -1 on the hull.
  int neighbour(int f, int k) const { return neighbours_[f][k]; }
  bool degenerate(int f) const { return !(std::abs(area2_[f]) >= kDegenerateArea2); }

  // The barycentric coordinates l (l[k] of vertex k, summing to 1) of the
  // point (x, y) in triangle f, which is not degenerate.
  void Barycentric(int f, double x, double y, double l[3]) const;

  // The triangle holding (x, y): walks from triangle `start` towards the
  // point. True, *f that triangle (never a degenerate one) when the point is
  // inside one (every barycentric coordinate >= -1e-10); false when it lies
  // beyond the hull, *f the hull triangle the walk stopped at (-1 when none).
  bool Locate(int start, double x, double y, int* f) const;

 private:
  std::vector<double> u_, v_;
  std::vector<std::array<int, 3>> vertices_, neighbours_;
  std::vector<double> area2_;  // twice each triangle's area (>= 0)
};

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SRC_DELAUNAY_H_
