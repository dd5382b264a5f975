#include "rockcal/sites/gridding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "delaunay.h"
#include "rockcal/core/format.h"
#include "rockcal/core/numbers.h"

namespace rockcal::sites {
namespace {

using core::kNaN;

// The points with every run of equal plan positions replaced by one point at
// their mean elevation, sorted by x then y.
std::vector<Eigen::Vector3d> MergeSamePlanPositions(std::vector<Eigen::Vector3d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Eigen::Vector3d> out;
  out.reserve(p.size());
  for (std::size_t k = 0; k < p.size();) {
    std::size_t e = k + 1;
    double sum = p[k].z();
    while (e < p.size() && p[e].x() == p[k].x() && p[e].y() == p[k].y()) sum += p[e++].z();
    out.emplace_back(p[k].x(), p[k].y(), sum / static_cast<double>(e - k));
    k = e;
  }
  return out;
}

// True when the points (at least 2) lie on one line in plan, to 1e-9 of
// their extent.
bool Collinear(const std::vector<Eigen::Vector3d>& p) {
  const Eigen::Vector2d a = p[0].head<2>();
  Eigen::Vector2d b = a;
  for (const Eigen::Vector3d& q : p)
    if ((q.head<2>() - a).squaredNorm() > (b - a).squaredNorm()) b = q.head<2>();
  const Eigen::Vector2d d = b - a;
  const double length = d.norm();
  double off = 0.0;
  for (const Eigen::Vector3d& q : p) {
    const Eigen::Vector2d r = q.head<2>() - a;
    off = std::max(off, std::abs(d.x() * r.y() - d.y() * r.x()) / length);
  }
  return !(off > 1e-9 * length);
}

}  // namespace

long NodeCount(double extent, double spacing) {
  return static_cast<long>(std::floor(extent / spacing + 1e-6)) + 1;
}

bool GriddingOptions::IsValid(std::string* error) const {
  if (!(spacing > 0.0 && std::isfinite(spacing))) {
    *error = "GriddingOptions::spacing = " + core::FormatNumber(spacing) +
             "; expected a finite spacing > 0";
    return false;
  }
  if (!(max_edge > 0.0)) {
    *error = "GriddingOptions::max_edge = " + core::FormatNumber(max_edge) +
             "; expected > 0 (or infinity)";
    return false;
  }
  return true;
}

namespace {

// Whether each triangle of dt is usable: not degenerate, no edge longer than
// max_edge (p: the points, dt's vertices).
std::vector<char> UsableTriangles(const Delaunay& dt, const std::vector<Eigen::Vector3d>& p,
                                  double max_edge) {
  std::vector<char> usable(static_cast<std::size_t>(dt.size()));
  for (int f = 0; f < dt.size(); ++f) {
    const std::array<int, 3>& vi = dt.vertices(f);
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (p[vi[k]].head<2>() - p[vi[(k + 1) % 3]].head<2>()).norm());
    usable[f] = !dt.degenerate(f) && longest <= max_edge;
  }
  return usable;
}

// How far outside triangle f of dt the plan point with barycentric
// coordinates l lies [m] (0 inside).
double DistanceOutside(const Delaunay& dt, const std::vector<Eigen::Vector3d>& p, int f,
                       const double* l) {
  const std::array<int, 3>& vi = dt.vertices(f);
  const Eigen::Vector2d a = p[vi[0]].head<2>(), b = p[vi[1]].head<2>(), c = p[vi[2]].head<2>();
  const double area2 = std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  const double opposite[3] = {(c - b).norm(), (a - c).norm(), (b - a).norm()};
  double out = 0.0;
  for (int k = 0; k < 3; ++k)
    if (l[k] < 0.0) out = std::max(out, -l[k] * area2 / opposite[k]);
  return out;
}

// Each node of g interpolated linearly in its usable triangle of dt (built
// in units of d from g's corner); counted in *rep.
void InterpolateNodes(const Delaunay& dt, const std::vector<Eigen::Vector3d>& p,
                      const std::vector<char>& usable, double d, core::HeightGrid* grid,
                      GriddingReport* report) {
  core::HeightGrid& g = *grid;
  GriddingReport& rep = *report;
  const double s = g.spacing;
  int start = 0;
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double x = i * s / d, y = j * s / d;
      int f = -1;
      double l[3];
      const bool inside = dt.Locate(start, x, y, &f);
      if (f < 0) {
        ++rep.outside_hull;
        continue;
      }
      start = f;
      dt.Barycentric(f, x, y, l);
      if (!inside && DistanceOutside(dt, p, f, l) > 1e-6 * s) {
        ++rep.outside_hull;
        continue;
      }
      if (!usable[f]) {
        // On an edge (or a corner) shared with a usable triangle: take that one.
        int other = -1;
        for (int k = 0; k < 3 && other < 0; ++k) {
          const int n = dt.neighbour(f, k);
          if (std::abs(l[k]) <= 1e-9 && n >= 0 && usable[n]) other = n;
        }
        if (other < 0) {
          ++rep.long_edge;
          continue;
        }
        f = other;
        dt.Barycentric(f, x, y, l);
      }
      const std::array<int, 3>& vi = dt.vertices(f);
      g.z[g.index(i, j)] = l[0] * p[vi[0]].z() + l[1] * p[vi[1]].z() + l[2] * p[vi[2]].z();
      ++rep.nodes;
    }
  }
}

}  // namespace

bool GridPoints(const std::vector<Eigen::Vector3d>& points, const GriddingOptions& options,
                core::HeightGrid* grid, GriddingReport* report, std::string* error) {
  if (!options.IsValid(error)) return false;
  GriddingReport rep;
  rep.points = static_cast<int>(points.size());
  const std::vector<Eigen::Vector3d> p = MergeSamePlanPositions(points);
  rep.merged = rep.points - static_cast<int>(p.size());
  if (p.size() < 3) {
    *error = std::to_string(p.size()) +
             " distinct plan position(s) among the surface points; expected at least 3 points "
             "not on one line";
    return false;
  }
  if (Collinear(p)) {
    *error = "the " + std::to_string(p.size()) +
             " distinct surface points lie on one line in plan, so they span no area; expected "
             "points spanning an area (at least 3 not on one line)";
    return false;
  }
  double xmin = p[0].x(), xmax = xmin, ymin = p[0].y(), ymax = ymin;
  for (const Eigen::Vector3d& q : p) {
    xmin = std::min(xmin, q.x());
    xmax = std::max(xmax, q.x());
    ymin = std::min(ymin, q.y());
    ymax = std::max(ymax, q.y());
  }
  // Triangulated in coordinates relative to (xmin, ymin) in units of the
  // data spacing d, so that the fixed threshold for a degenerate triangle
  // (Delaunay::kDegenerateArea2) means a sliver whatever the units and the
  // distance from the origin.
  const double d = std::sqrt((xmax - xmin) * (ymax - ymin) / static_cast<double>(p.size()));
  std::vector<double> u(p.size()), v(p.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    u[k] = (p[k].x() - xmin) / d;
    v[k] = (p[k].y() - ymin) / d;
  }
  Delaunay dt;
  std::string why;
  if (!dt.Build(u, v, &why)) {
    *error = "the Delaunay triangulation of the " + std::to_string(p.size()) +
             " surface points failed (" + why + "); expected points spanning an area";
    return false;
  }
  rep.triangles = dt.size();

  const std::vector<char> usable = UsableTriangles(dt, p, options.max_edge);
  core::HeightGrid& g = *grid;
  const double s = options.spacing;
  g = core::HeightGrid();
  g.spacing = s;
  g.x0 = xmin;
  g.y0 = ymin;
  g.nx = static_cast<int>(NodeCount(xmax - xmin, s));
  g.ny = static_cast<int>(NodeCount(ymax - ymin, s));
  g.z.assign(static_cast<std::size_t>(g.nx) * g.ny, kNaN);
  g.material.assign(g.z.size(), 0);
  InterpolateNodes(dt, p, usable, d, &g, &rep);
  if (report) *report = rep;
  return true;
}

core::HeightGrid ResampleNodes(int ncols, int nrows, double cell, double x0, double y0,
                               const std::function<double(int, int)>& z_at, double spacing) {
  core::HeightGrid out;
  out.x0 = x0;
  out.y0 = y0;
  if (std::abs(spacing - cell) <= 1e-9 * cell) {
    out.spacing = cell;
    out.nx = ncols;
    out.ny = nrows;
    out.z.resize(static_cast<std::size_t>(out.nx) * out.ny);
    for (int j = 0; j < out.ny; ++j)
      for (int i = 0; i < out.nx; ++i) out.z[out.index(i, j)] = z_at(i, j);
  } else {
    out.spacing = spacing;
    out.nx = static_cast<int>(NodeCount((ncols - 1) * cell, spacing));
    out.ny = static_cast<int>(NodeCount((nrows - 1) * cell, spacing));
    out.z.resize(static_cast<std::size_t>(out.nx) * out.ny);
    for (int j = 0; j < out.ny; ++j) {
      const double fy = j * spacing / cell;
      const int jy = std::max(0, std::min(static_cast<int>(fy), nrows - 2));
      const double ty = fy - jy;
      for (int i = 0; i < out.nx; ++i) {
        const double fx = i * spacing / cell;
        const int ix = std::max(0, std::min(static_cast<int>(fx), ncols - 2));
        const double tx = fx - ix;
        // A corner with zero weight is not used; a hole corner with a
        // positive weight makes the node a hole (NaN propagates).
        const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
        double z = 0.0;
        for (int k = 0; k < 4; ++k)
          if (w[k] > 0) z += w[k] * z_at(ix + (k & 1), jy + (k >> 1));
        out.z[out.index(i, j)] = z;
      }
    }
  }
  out.material.assign(out.z.size(), 0);
  return out;
}

core::HeightGrid ResampleGrid(const core::HeightGrid& grid, double spacing) {
  core::HeightGrid out = ResampleNodes(
      grid.nx, grid.ny, grid.spacing, grid.x0, grid.y0,
      [&](int i, int j) { return grid.z[grid.index(i, j)]; }, spacing);
  if (grid.material.size() != grid.z.size()) return out;
  for (int j = 0; j < out.ny; ++j) {
    const int jn =
        std::min(grid.ny - 1, static_cast<int>(std::lround(j * out.spacing / grid.spacing)));
    for (int i = 0; i < out.nx; ++i) {
      const int in =
          std::min(grid.nx - 1, static_cast<int>(std::lround(i * out.spacing / grid.spacing)));
      out.material[out.index(i, j)] = grid.material[grid.index(in, jn)];
    }
  }
  return out;
}

}  // namespace rockcal::sites
