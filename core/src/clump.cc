#include "rockcal/core/clump.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "rockcal/core/name_table.h"

namespace rockcal::core {

namespace {
constexpr Named<ClumpTarget> kTargets[] = {{ClumpTarget::kMoments, "moments"},
                                           {ClumpTarget::kSides, "sides"}};
}  // namespace

const char* ClumpTargetToString(ClumpTarget target) { return NameOf(kTargets, target); }
bool StringToClumpTarget(const std::string& name, ClumpTarget* target) {
  return IdOf(kTargets, name, target);
}

bool ClumpOptions::IsValid(std::string* error) const {
  if (spheres < 1 || spheres > 64) {
    *error = "spheres = " + std::to_string(spheres) + ": expected 1 to 64";
    return false;
  }
  if (grid < 16 || grid > 200) {
    *error = "grid = " + std::to_string(grid) + ": expected 16 to 200";
    return false;
  }
  if (lloyd_iterations < 1 || fit_iterations < 1) {
    *error = "lloyd_iterations and fit_iterations: expected >= 1";
    return false;
  }
  return true;
}

MassProperties PolyhedronMassProperties(const Polyhedron& p) {
  MassProperties m;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T about the origin
  for (const auto& f : p.faces) {
    const Eigen::Vector3d& a = p.vertices[static_cast<std::size_t>(f[0])];
    const Eigen::Vector3d& b = p.vertices[static_cast<std::size_t>(f[1])];
    const Eigen::Vector3d& c = p.vertices[static_cast<std::size_t>(f[2])];
    m.surface += 0.5 * (b - a).cross(c - a).norm();
    // The signed tetrahedron (0, a, b, c).
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d s = a + b + c;
    m.volume += v;
    first += v * s / 4.0;
    second +=
        v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  if (!(m.volume > 0)) return m;
  m.centroid = first / m.volume;
  const Eigen::Matrix3d central = second - m.volume * m.centroid * m.centroid.transpose();
  m.inertia = central.trace() * Eigen::Matrix3d::Identity() - central;
  return m;
}

Polyhedron ToPrincipalFrame(const Polyhedron& hull, MassProperties* props) {
  const MassProperties m = PolyhedronMassProperties(hull);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.inertia);
  Eigen::Matrix3d axes = eig.eigenvectors();  // columns, ascending moments
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  // Equal moments (a cube, a sphere): any axes are principal; keep the
  // file's rather than rounding's.
  const Eigen::Vector3d mom = eig.eigenvalues();
  if (mom.maxCoeff() - mom.minCoeff() <= 1e-9 * mom.maxCoeff()) axes.setIdentity();
  Polyhedron out = hull;
  for (auto& v : out.vertices) v = axes.transpose() * (v - m.centroid);
  *props = PolyhedronMassProperties(out);
  // Exactly diagonal: the off-diagonal terms are rounding.
  props->inertia = Eigen::Matrix3d(props->inertia.diagonal().asDiagonal());
  props->centroid.setZero();
  return out;
}

namespace {

// The half-spaces n . x <= d of a convex polyhedron's faces.
struct Planes {
  std::vector<Eigen::Vector3d> n;
  std::vector<double> d;
  bool Inside(const Eigen::Vector3d& x) const {
    for (std::size_t k = 0; k < n.size(); ++k)
      if (n[k].dot(x) > d[k]) return false;
    return true;
  }
};

Planes FacePlanes(const Polyhedron& p) {
  Planes planes;
  for (const auto& f : p.faces) {
    const Eigen::Vector3d& a = p.vertices[static_cast<std::size_t>(f[0])];
    Eigen::Vector3d n = (p.vertices[static_cast<std::size_t>(f[1])] - a)
                            .cross(p.vertices[static_cast<std::size_t>(f[2])] - a);
    const double len = n.norm();
    if (!(len > 0)) continue;
    n /= len;
    planes.n.push_back(n);
    planes.d.push_back(n.dot(a));
  }
  return planes;
}

void Bounds(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
  *lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  *hi = -*lo;
  for (const auto& v : points) {
    *lo = lo->cwiseMin(v);
    *hi = hi->cwiseMax(v);
  }
}

// Volume and second moments (integral of x_k^2, about the origin) of the
// union of spheres of `radius` at `centres`: on an n x n grid of vertical
// columns over the union's plan bounding box (the midpoint rule in x and y),
// each column's intervals inside the spheres merged and integrated exactly
// in z.
struct UnionSums {
  double volume = 0.0;
  Eigen::Vector3d second = Eigen::Vector3d::Zero();
};
UnionSums IntegrateUnion(const std::vector<Eigen::Vector3d>& centres, double radius, int n) {
  Eigen::Vector3d lo, hi;
  Bounds(centres, &lo, &hi);
  lo.array() -= radius;
  hi.array() += radius;
  const double hx = (hi.x() - lo.x()) / n, hy = (hi.y() - lo.y()) / n;
  const double area = hx * hy, r2 = radius * radius;
  // One partial sum per row of columns (serial: a fit is ~10^6 operations;
  // threads spent more in their barriers than they saved on a loaded machine).
  std::vector<UnionSums> row(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    UnionSums& part = row[static_cast<std::size_t>(i)];
    std::vector<std::pair<double, double>> spans;
    const double x = lo.x() + (i + 0.5) * hx;
    for (int j = 0; j < n; ++j) {
      const double y = lo.y() + (j + 0.5) * hy;
      spans.clear();
      for (const auto& c : centres) {
        const double d2 = r2 - (x - c.x()) * (x - c.x()) - (y - c.y()) * (y - c.y());
        if (d2 > 0) {
          const double h = std::sqrt(d2);
          spans.emplace_back(c.z() - h, c.z() + h);
        }
      }
      if (spans.empty()) continue;
      std::sort(spans.begin(), spans.end());
      double length = 0.0, z2 = 0.0;  // integrals of 1 and z^2 along the column
      double a = spans[0].first, b = spans[0].second;
      auto close = [&] {
        length += b - a;
        z2 += (b * b * b - a * a * a) / 3.0;
      };
      for (std::size_t k = 1; k < spans.size(); ++k) {
        if (spans[k].first > b) {
          close();
          a = spans[k].first;
          b = spans[k].second;
        } else {
          b = std::max(b, spans[k].second);
        }
      }
      close();
      part.volume += area * length;
      part.second += area * Eigen::Vector3d(x * x * length, y * y * length, z2);
    }
  }
  UnionSums out;
  for (const UnionSums& part : row) {
    out.volume += part.volume;
    out.second += part.second;
  }
  return out;
}

Eigen::Vector3d MomentsFromSecond(const Eigen::Vector3d& s) {
  return Eigen::Vector3d(s.y() + s.z(), s.x() + s.z(), s.x() + s.y());
}

}  // namespace

namespace {

// Interior points of `hull`: the centres of the cells of an n x n x n grid
// over its box (corner lo, sides `sides`) inside every face; the origin if
// none is.
std::vector<Eigen::Vector3d> InteriorPoints(const Polyhedron& hull, const Eigen::Vector3d& lo,
                                            const Eigen::Vector3d& sides, int n) {
  const Planes planes = FacePlanes(hull);
  const Eigen::Vector3d h = sides / n;
  std::vector<Eigen::Vector3d> inside;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      // The column's span inside every face's half-space n . x <= d.
      const double x = lo.x() + (i + 0.5) * h.x(), y = lo.y() + (j + 0.5) * h.y();
      double zlo = -std::numeric_limits<double>::infinity(), zhi = -zlo;
      for (std::size_t f = 0; f < planes.n.size() && zlo <= zhi; ++f) {
        const Eigen::Vector3d& nf = planes.n[f];
        const double rest = planes.d[f] - nf.x() * x - nf.y() * y;
        if (nf.z() > 0)
          zhi = std::min(zhi, rest / nf.z());
        else if (nf.z() < 0)
          zlo = std::max(zlo, rest / nf.z());
        else if (rest < 0)
          zhi = zlo - 1.0;  // outside a vertical face
      }
      for (int k = 0; k < n; ++k) {
        const double z = lo.z() + (k + 0.5) * h.z();
        if (z >= zlo && z <= zhi) inside.emplace_back(x, y, z);
      }
    }
  if (inside.empty()) inside.push_back(Eigen::Vector3d::Zero());
  return inside;
}

// `count` seeds among the interior points: the one farthest from the
// centroid, then each time the one farthest from every seed so far (ties:
// the first in grid order).
std::vector<Eigen::Vector3d> SeedCentres(const std::vector<Eigen::Vector3d>& inside,
                                         std::size_t count) {
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> nearest(inside.size(), std::numeric_limits<double>::infinity());
  std::size_t pick = 0;
  for (std::size_t p = 1; p < inside.size(); ++p)
    if (inside[p].squaredNorm() > inside[pick].squaredNorm()) pick = p;
  while (centres.size() < count) {
    centres.push_back(inside[pick]);
    std::size_t far = 0;
    for (std::size_t p = 0; p < inside.size(); ++p) {
      nearest[p] = std::min(nearest[p], (inside[p] - centres.back()).squaredNorm());
      if (nearest[p] > nearest[far]) far = p;
    }
    pick = far;
  }
  return centres;
}

// Lloyd's iterations: each centre moves to the mean of its Voronoi cell
// among the interior points, until none moves `converged` or after
// `iterations`.
void LloydIterations(const std::vector<Eigen::Vector3d>& inside, int iterations, double converged,
                     std::vector<Eigen::Vector3d>* centres_out) {
  std::vector<Eigen::Vector3d>& centres = *centres_out;
  const std::size_t count = centres.size();
  std::vector<Eigen::Vector3d> sum(count);
  std::vector<int> members(count);
  std::vector<std::size_t> cell_of(inside.size());
  for (int it = 0; it < iterations && count > 1; ++it) {
    std::fill(sum.begin(), sum.end(), Eigen::Vector3d::Zero());
    std::fill(members.begin(), members.end(), 0);
    for (std::size_t p = 0; p < inside.size(); ++p) {
      const Eigen::Vector3d& q = inside[p];
      std::size_t best = 0;
      double best_d = (q - centres[0]).squaredNorm();
      for (std::size_t c = 1; c < count; ++c) {
        const double d = (q - centres[c]).squaredNorm();
        if (d < best_d) {
          best_d = d;
          best = c;
        }
      }
      cell_of[p] = best;
    }
    for (std::size_t p = 0; p < inside.size(); ++p) {
      sum[cell_of[p]] += inside[p];
      ++members[cell_of[p]];
    }
    double moved = 0.0;
    for (std::size_t c = 0; c < count; ++c) {
      if (members[c] == 0) continue;
      const Eigen::Vector3d next = sum[c] / members[c];
      moved = std::max(moved, (next - centres[c]).norm());
      centres[c] = next;
    }
    if (moved < converged) break;
  }
}

}  // namespace

Clump FitClump(const Polyhedron& hull, const ClumpOptions& options) {
  Clump clump;
  const MassProperties m = PolyhedronMassProperties(hull);
  clump.hull_volume = m.volume;
  clump.hull_moments = m.inertia.diagonal();
  // Second moments of the hull (integral of x_k^2) from the diagonal inertia.
  const double tr = 0.5 * clump.hull_moments.sum();
  const Eigen::Vector3d target = Eigen::Vector3d::Constant(tr) - clump.hull_moments;
  Eigen::Vector3d lo, hi;
  Bounds(hull.vertices, &lo, &hi);
  clump.hull_sides = hi - lo;

  const int n = options.grid;
  const std::vector<Eigen::Vector3d> inside = InteriorPoints(hull, lo, clump.hull_sides, n);
  const std::size_t count =
      std::min<std::size_t>(static_cast<std::size_t>(options.spheres), inside.size());
  std::vector<Eigen::Vector3d> centres = SeedCentres(inside, count);
  LloydIterations(inside, options.lloyd_iterations, 1e-9 * clump.hull_sides.maxCoeff(), &centres);
  if (count == 1) centres[0].setZero();

  // The common radius and the stretch of the centres along each axis:
  // fixed-point iterations on the union's volume and second moments.
  const std::vector<Eigen::Vector3d> base = centres;
  double radius = std::cbrt(3.0 * m.volume / (4.0 * M_PI * static_cast<double>(count)));
  Eigen::Vector3d stretch = Eigen::Vector3d::Ones();
  auto place = [&](const Eigen::Vector3d& s) {
    std::vector<Eigen::Vector3d> out(base.size());
    for (std::size_t c = 0; c < base.size(); ++c) out[c] = base[c].cwiseProduct(s);
    return out;
  };
  for (int it = 0; it < options.fit_iterations; ++it) {
    const UnionSums u = IntegrateUnion(place(stretch), radius, n);
    if (!(u.volume > 0)) break;
    radius *= std::cbrt(m.volume / u.volume);
    if (options.target == ClumpTarget::kSides) {
      // The outermost centres a radius inside the hull's box on each axis.
      Eigen::Vector3d blo, bhi;
      Bounds(base, &blo, &bhi);
      for (int k = 0; k < 3; ++k) {
        const double span = bhi[k] - blo[k];
        if (span > 1e-12 * clump.hull_sides[k])
          stretch[k] = std::clamp((clump.hull_sides[k] - 2.0 * radius) / span, 0.2, 5.0);
      }
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      if (!(u.second[k] > 0)) continue;
      // Per unit volume, so that the radius's step does not count twice.
      const double ratio = (target[k] / m.volume) / (u.second[k] / u.volume);
      stretch[k] = std::clamp(stretch[k] * std::sqrt(ratio), 0.2, 5.0);
    }
  }
  clump.centres = place(stretch);
  clump.radius = radius;
  const UnionSums u = IntegrateUnion(clump.centres, radius, n);
  clump.union_volume = u.volume;
  clump.union_moments = MomentsFromSecond(u.second);
  Eigen::Vector3d ulo, uhi;
  Bounds(clump.centres, &ulo, &uhi);
  clump.union_sides = (uhi - ulo).array() + 2.0 * radius;
  clump.volume_error = clump.union_volume / clump.hull_volume - 1.0;
  clump.moment_error =
      (clump.union_moments.cwiseQuotient(clump.hull_moments).array() - 1.0).abs().maxCoeff();
  clump.side_error =
      (clump.union_sides.cwiseQuotient(clump.hull_sides).array() - 1.0).abs().maxCoeff();
  return clump;
}

double UnionIntegrals(const std::vector<Eigen::Vector3d>& centres, double radius, int grid,
                      Eigen::Vector3d* moments) {
  const auto u = IntegrateUnion(centres, radius, grid);
  *moments = MomentsFromSecond(u.second);
  return u.volume;
}

ScannedShape MakeScannedShape(const Polyhedron& hull, const ClumpOptions& options,
                              const std::string& name, const std::string& file) {
  ScannedShape s;
  s.name = name;
  s.file = file;
  s.hull = ToPrincipalFrame(hull, &s.mass);
  s.clump = FitClump(s.hull, options);
  return s;
}

Polyhedron StretchToSides(const Polyhedron& principal_hull, const Eigen::Vector3d& sides) {
  Eigen::Vector3d lo, hi;
  Bounds(principal_hull.vertices, &lo, &hi);
  const Eigen::Vector3d scale = sides.cwiseQuotient(hi - lo);
  Polyhedron out = principal_hull;
  for (auto& v : out.vertices) v = v.cwiseProduct(scale);
  MassProperties m;
  return ToPrincipalFrame(out, &m);
}

ScannedShape ScaleShape(const ScannedShape& shape, double scale) {
  ScannedShape s = shape;
  const double s3 = scale * scale * scale, s5 = s3 * scale * scale;
  for (auto& v : s.hull.vertices) v *= scale;
  s.mass.volume *= s3;
  s.mass.surface *= scale * scale;
  s.mass.inertia *= s5;
  Clump& c = s.clump;
  for (auto& e : c.centres) e *= scale;
  c.radius *= scale;
  c.hull_volume *= s3;
  c.union_volume *= s3;
  c.hull_moments *= s5;
  c.union_moments *= s5;
  c.hull_sides *= scale;
  c.union_sides *= scale;
  return s;
}

RockBody ScannedBody(const ScannedShape& shape, double scale, double mass) {
  RockBody body;
  body.shape = Shape::kScanned;
  body.size = shape.clump.hull_sides.x() * scale;
  body.mass = mass;
  body.element_radius = shape.clump.radius * scale;
  body.elements.reserve(shape.clump.centres.size());
  for (const auto& c : shape.clump.centres) body.elements.push_back(c * scale);
  const double volume = shape.mass.volume * scale * scale * scale;
  body.inertia = shape.mass.inertia.diagonal() * std::pow(scale, 5) * (mass / volume);
  body.frontal_area = shape.mass.surface * scale * scale / 4.0;
  double reach = 0.0;
  for (const auto& e : body.elements) reach = std::max(reach, e.norm());
  body.bounding_radius = reach + body.element_radius;
  return body;
}

}  // namespace rockcal::core
