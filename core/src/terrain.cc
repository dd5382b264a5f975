#include "rockcal/core/terrain.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rockcal/core/material.h"
#include "rockcal/core/numbers.h"

namespace rockcal::core {
namespace {

// Contact keys of catch planes (below every node and facet key).
constexpr std::int64_t kCatchKey = -(std::int64_t{1} << 40);
// Cosine of the steepest slope whose fall-line spacing sizes a virtual
// sphere (60 degrees; see Terrain::BuildSpheres).
constexpr double kMinFallLineCos = 0.5;

// Height at (u, v) in [0, 1]^2 of a cell with corner heights z00 .. z11,
// split along the (0, 0)-(1, 1) diagonal into two planar facets.
double OnFacets(double u, double v, double z00, double z10, double z01, double z11) {
  return u >= v ? z00 + u * (z10 - z00) + v * (z11 - z10) : z00 + v * (z01 - z00) + u * (z11 - z01);
}

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision
// Detection, section 5.1.5: regions of the triangle by barycentric tests).
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Signed distance from point c to the triangle (p0, b, d) of the terrain with
// unit upward normal `up`, one-sided: positive above the surface; negative
// (minus the depth below the facet plane) when c lies under the facet; +inf
// when c is under the plane but not over this facet (a neighbour handles it).
// When c is at least `limit` above the plane, returns that height (a lower
// bound of the distance) without *normal. *normal points out of the terrain.
double FacetDistance(const Eigen::Vector3d& c, const Eigen::Vector3d& p0, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& d, const Eigen::Vector3d& up, double limit,
                     Eigen::Vector3d* normal) {
  const double height = up.dot(c - p0);
  if (height >= limit) return height;
  const Eigen::Vector3d q = ClosestPointOnTriangle(c, p0, b, d);
  if (height > 0.0) {
    const Eigen::Vector3d gap = c - q;
    const double dist = gap.norm();
    *normal = dist > 1e-12 ? Eigen::Vector3d(gap / dist) : up;
    return dist;
  }
  const double off = (c - height * up - q).squaredNorm();
  if (off > 1e-18 + 1e-12 * height * height) return kInf;
  *normal = up;
  return height;
}

// The largest radius, up to r_max, of a sphere touching node (i, j) from
// below (centre at the node less radius times `normal`) that holds no other
// node: node q lies inside once the radius passes |q|^2 / (2 depth), depth
// its distance below the tangent plane (a sphere of r_max reaches 2 r_max).
double EmptyRadius(const HeightGrid& grid, int i, int j, const Eigen::Vector3d& normal,
                   double r_max) {
  const double s = grid.spacing;
  const Eigen::Vector3d p(grid.x(i), grid.y(j), grid.z[grid.index(i, j)]);
  const int w = static_cast<int>(std::ceil(2.0 * r_max / s));
  double r = r_max;
  for (int jj = std::max(j - w, 0); jj <= std::min(j + w, grid.ny - 1); ++jj)
    for (int ii = std::max(i - w, 0); ii <= std::min(i + w, grid.nx - 1); ++ii) {
      if ((ii == i && jj == j) || !grid.valid(ii, jj)) continue;
      const Eigen::Vector3d q =
          Eigen::Vector3d(grid.x(ii), grid.y(jj), grid.z[grid.index(ii, jj)]) - p;
      const double depth = -normal.dot(q);
      if (depth > 0.0 && q.squaredNorm() < 2.0 * r * depth) r = q.squaredNorm() / (2.0 * depth);
    }
  return r;
}

}  // namespace

bool HeightGrid::valid(int i, int j) const {
  return i >= 0 && j >= 0 && i < nx && j < ny && !std::isnan(z[index(i, j)]);
}

Terrain::Terrain(HeightGrid grid, const std::vector<double>& roughness_m, double max_element_radius,
                 int threads)
    : grid_(std::move(grid)),
      inv_spacing_(1.0 / grid_.spacing),
      max_element_radius_(max_element_radius),
      roughness_(roughness_m) {
  BuildSpheres();
  BuildCandidates(threads > 0 ? threads : omp_get_max_threads());
}

void Terrain::BuildSpheres() {
  const int nx = grid_.nx, ny = grid_.ny;
  const double s = grid_.spacing;
  centre_.assign(static_cast<std::size_t>(nx) * ny, Eigen::Vector3d::Zero());
  radius_.assign(static_cast<std::size_t>(nx) * ny, kInf);
  has_rough_ = has_smooth_ = false;
  sag_ = 0.0;
  max_offset_ = 0.0;
  auto zat = [&](int i, int j) { return grid_.z[grid_.index(i, j)]; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (!grid_.valid(i, j)) continue;
      const int n = grid_.index(i, j);
      const double rough = roughness_[static_cast<std::size_t>(grid_.material[n])];
      if (rough <= 0.0) {
        has_smooth_ = true;
        continue;
      }
      has_rough_ = true;
      // Surface normal from central differences (one-sided at edges and holes).
      const int il = grid_.valid(i - 1, j) ? i - 1 : i, ir = grid_.valid(i + 1, j) ? i + 1 : i;
      const int jd = grid_.valid(i, j - 1) ? j - 1 : j, ju = grid_.valid(i, j + 1) ? j + 1 : j;
      const double dzdx = ir > il ? (zat(ir, j) - zat(il, j)) / ((ir - il) * s) : 0.0;
      const double dzdy = ju > jd ? (zat(i, ju) - zat(i, jd)) / ((ju - jd) * s) : 0.0;
      const Eigen::Vector3d normal = Eigen::Vector3d(-dzdx, -dzdy, 1.0).normalized();
      // R is the sag a rock feels between neighbouring spheres along the
      // surface, on any slope. Along the fall line the nodes are s / n_z
      // apart on the surface, and the sphere is sized from that distance (s
      // on level ground; exact on planes whose fall line follows the grid).
      // Two bounds keep the spheres of steep nodes in check:
      // - the distance is capped at that of a 60-degree face, 2 s. r grows
      //   as d^2 / (8 R): a wall (n_z -> 0) would take a sphere without
      //   bound, and the candidate search with it. The cap keeps r within 4
      //   times its level-ground size (40 s at MinRoughness). On steeper
      //   faces rocks mostly fall and strike the face rather than roll or
      //   slide on it; there the sag along the fall line grows again above R
      //   (the spheres still meet up to 84 degrees at R = s / 10).
      // - a sphere grows past its level-ground size only while it holds no
      //   other node. At a convex break (the crest of a face) the larger
      //   sphere of a steep node would stand above the ground beyond the
      //   break, by up to r (1 - n_z). A plane holds no node inside its
      //   spheres, so this bound leaves the rule exact there.
      const double level = VirtualSphereRadius(rough, s);
      double r = VirtualSphereRadius(rough, s / std::max(normal.z(), kMinFallLineCos));
      if (r > level) r = std::max(level, EmptyRadius(grid_, i, j, normal, r));
      radius_[n] = r;
      max_offset_ = std::max(max_offset_, r * std::hypot(normal.x(), normal.y()));
      // Deepest sag, normal to the surface, at the centre of a cell of
      // surface sides s (across the slope) and s / n_z (along it).
      const double fall = s / normal.z();
      const double half_diagonal2 = 0.25 * (s * s + fall * fall);
      sag_ = std::max(sag_, r * r > half_diagonal2 ? r - std::sqrt(r * r - half_diagonal2) : r);
      centre_[n] = Eigen::Vector3d(grid_.x(i), grid_.y(j), zat(i, j)) - r * normal;
    }
  }
  // A cell takes facets when any corner is smooth (and none is a hole).
  const int cx = std::max(nx - 1, 0), cy = std::max(ny - 1, 0);
  smooth_cell_.assign(static_cast<std::size_t>(cx) * cy, 0);
  for (int j = 0; j < cy; ++j) {
    for (int i = 0; i < cx; ++i) {
      bool all_valid = true, any_smooth = false;
      for (int k = 0; k < 4; ++k) {
        const int ii = i + (k & 1), jj = j + (k >> 1);
        all_valid = all_valid && grid_.valid(ii, jj);
        any_smooth =
            any_smooth || (grid_.valid(ii, jj) && std::isinf(radius_[grid_.index(ii, jj)]));
      }
      smooth_cell_[static_cast<std::size_t>(j) * cx + i] = all_valid && any_smooth;
    }
  }
}

// The nodes that may reach a cell, with their heights over it (reused from
// cell to cell).
struct Terrain::CellScratch {
  std::vector<int> reach;
  std::vector<double> tops, touch;
};

void Terrain::BuildCandidates(int threads) {
  const int cx = std::max(grid_.nx - 1, 0), cy = std::max(grid_.ny - 1, 0);
  const double s = grid_.spacing, a = max_element_radius_;
  const std::size_t cells = static_cast<std::size_t>(cx) * cy;
  ceiling_.assign(cells, -kInf);
  std::vector<double> cell_floor(cells, -kInf);
  list_start_.assign(cells + 1, 0);
  list_.clear();
  double r_max = 0.0;
  for (double r : radius_)
    if (!std::isinf(r)) r_max = std::max(r_max, r);
  // Nodes whose sphere may reach a cell expanded by a: within r + offset + a.
  const int rings = static_cast<int>(std::ceil((r_max + max_offset_ + a) / s)) + 1;
  // Rows in parallel, each into its own list, joined in row order: the
  // same lists at any thread count.
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(cy));
  std::vector<int> counts(cells, 0);
#pragma omp parallel num_threads(threads)
  {
    CellScratch scratch;
#pragma omp for schedule(dynamic, 4)
    for (int j = 0; j < cy; ++j) {
      std::vector<int>& row = rows[static_cast<std::size_t>(j)];
      for (int i = 0; i < cx; ++i) {
        const std::size_t cell = static_cast<std::size_t>(j) * cx + i;
        const std::size_t before = row.size();
        cell_floor[cell] = BuildCellCandidates(i, j, rings, &scratch, &row);
        counts[cell] = static_cast<int>(row.size() - before);
      }
    }
  }
  for (std::size_t cell = 0; cell < cells; ++cell)
    list_start_[cell + 1] = list_start_[cell] + counts[cell];
  list_.reserve(static_cast<std::size_t>(list_start_[cells]));
  for (const std::vector<int>& row : rows) list_.insert(list_.end(), row.begin(), row.end());
  BuildCatchSurface(cell_floor);
  BuildFloorTops();
}

double Terrain::BuildCellCandidates(int i, int j, int rings, CellScratch* scratch,
                                    std::vector<int>* list) {
  const int cx = std::max(grid_.nx - 1, 0);
  const double a = max_element_radius_;
  const std::size_t cell = static_cast<std::size_t>(j) * cx + i;
  const double x0 = grid_.x(i), x1 = grid_.x(i + 1), y0 = grid_.y(j), y1 = grid_.y(j + 1);
  // floor: a lower bound of the obstacle envelope over the cell, the
  // highest of the spheres' lowest points over it (min of a max >= max of mins).
  double floor = -kInf, top = -kInf;
  if (smooth_cell_[cell]) {
    double lo = kInf;
    for (int k = 0; k < 4; ++k) {
      const double z = grid_.z[grid_.index(i + (k & 1), j + (k >> 1))];
      lo = std::min(lo, z);
      top = std::max(top, z);
    }
    floor = lo;
  }
  std::vector<int>& reach = scratch->reach;
  std::vector<double>& tops = scratch->tops;
  std::vector<double>& touch = scratch->touch;
  reach.clear();
  tops.clear();
  touch.clear();
  for (int jj = std::max(j - rings, 0); jj <= std::min(j + 1 + rings, grid_.ny - 1); ++jj) {
    for (int ii = std::max(i - rings, 0); ii <= std::min(i + 1 + rings, grid_.nx - 1); ++ii) {
      const int n = grid_.index(ii, jj);
      const double r = radius_[n];
      if (std::isinf(r)) continue;
      const Eigen::Vector3d& c = centre_[n];
      // Highest point over the cell expanded by a (where an element
      // centred in the cell may touch it).
      const double dx = std::max({x0 - a - c.x(), 0.0, c.x() - x1 - a});
      const double dy = std::max({y0 - a - c.y(), 0.0, c.y() - y1 - a});
      const double near2 = dx * dx + dy * dy;
      if (near2 >= r * r) continue;
      // Highest centre of an element of radius a touching it over the cell.
      const double cdx = std::max({x0 - c.x(), 0.0, c.x() - x1});
      const double cdy = std::max({y0 - c.y(), 0.0, c.y() - y1});
      const double ra = r + a;
      const double cell2 = cdx * cdx + cdy * cdy;
      reach.push_back(n);
      tops.push_back(c.z() + std::sqrt(r * r - near2));
      touch.push_back(cell2 < ra * ra ? c.z() + std::sqrt(ra * ra - cell2) : -kInf);
      // Lowest point over the cell itself, if the sphere covers all of it.
      const double fx = std::max(std::abs(x0 - c.x()), std::abs(x1 - c.x()));
      const double fy = std::max(std::abs(y0 - c.y()), std::abs(y1 - c.y()));
      const double far2 = fx * fx + fy * fy;
      if (far2 < r * r) floor = std::max(floor, c.z() + std::sqrt(r * r - far2));
    }
  }
  // An element that overlaps no sphere by more than its radius has its
  // centre outside every sphere, so above the envelope, so above floor.
  // It touches sphere k only with its centre inside k inflated by a: a
  // sphere whose inflated top over the cell is below floor is buried.
  for (std::size_t k = 0; k < reach.size(); ++k) {
    if (touch[k] < floor) continue;
    list->push_back(reach[k]);
    top = std::max(top, tops[k]);
  }
  ceiling_[cell] = top;
  // The catch surface closes holes of the sphere surface (R > 0.207 s,
  // sharp breaks). Over a rough cell it must stay below the envelope:
  // below floor where a sphere covers the whole cell; where none does (a
  // hole), below the lowest corner less the largest corner roughness.
  if (smooth_cell_[cell] || !CellValid(i, j)) return -kInf;
  double lowest = kInf, roughness = 0.0;
  for (int k = 0; k < 4; ++k) {
    const int n = grid_.index(i + (k & 1), j + (k >> 1));
    lowest = std::min(lowest, grid_.z[n]);
    // The sag between neighbours along the surface.
    if (!std::isinf(radius_[n]))
      roughness = std::max(roughness, roughness_[static_cast<std::size_t>(grid_.material[n])]);
  }
  return std::isfinite(floor) ? floor : lowest - roughness;
}

void Terrain::BuildCatchSurface(const std::vector<double>& cell_floor) {
  const int cx = std::max(grid_.nx - 1, 0), cy = std::max(grid_.ny - 1, 0);
  // The catch surface is the terrain's triangulation with every node lowered
  // to the lowest floor of the rough cells around it: linear on each facet,
  // so below floor wherever all its corners are, and continuous from cell to
  // cell (no step for a rock to catch on).
  catch_z_.assign(grid_.z.size(), kInf);
  for (int j = 0; j < cy; ++j)
    for (int i = 0; i < cx; ++i) {
      const double f = cell_floor[static_cast<std::size_t>(j) * cx + i];
      if (!std::isfinite(f)) continue;
      for (int k = 0; k < 4; ++k) {
        double& z = catch_z_[static_cast<std::size_t>(grid_.index(i + (k & 1), j + (k >> 1)))];
        z = std::min(z, f);
      }
    }
}

void Terrain::BuildFloorTops() {
  const int cx = std::max(grid_.nx - 1, 0), cy = std::max(grid_.ny - 1, 0);
  const std::size_t cells = static_cast<std::size_t>(cx) * cy;
  // Per cell, the highest corner of its floor surface (facets or catch), and
  // the ceiling grows by the floor surfaces an element centred there may touch.
  floor_top_.assign(cells, -kInf);
  floor_up_.assign(2 * cells, Eigen::Vector3d::UnitZ());
  for (int j = 0; j < cy; ++j)
    for (int i = 0; i < cx; ++i) {
      if (!CellValid(i, j)) continue;
      Eigen::Vector3d p[4];
      FloorCorners(i, j, p);
      const std::size_t id = 2 * (static_cast<std::size_t>(j) * cx + i);
      floor_up_[id] = (p[1] - p[0]).cross(p[3] - p[0]).normalized();
      floor_up_[id + 1] = (p[3] - p[0]).cross(p[2] - p[0]).normalized();
      floor_top_[id / 2] = std::max({p[0].z(), p[1].z(), p[2].z(), p[3].z()});
    }
  for (int j = 0; j < cy; ++j)
    for (int i = 0; i < cx; ++i) {
      double& top = ceiling_[static_cast<std::size_t>(j) * cx + i];
      for (int jj = std::max(j - 1, 0); jj <= std::min(j + 1, cy - 1); ++jj)
        for (int ii = std::max(i - 1, 0); ii <= std::min(i + 1, cx - 1); ++ii)
          top = std::max(top, floor_top_[static_cast<std::size_t>(jj) * cx + ii]);
    }
}

double Terrain::CornerHeight(int i, int j, int k) const {
  const int n = grid_.index(i + (k & 1), j + (k >> 1));
  return smooth_cell_[static_cast<std::size_t>(j) * (grid_.nx - 1) + i]
             ? grid_.z[static_cast<std::size_t>(n)]
             : catch_z_[static_cast<std::size_t>(n)];
}

void Terrain::FloorCorners(int i, int j, Eigen::Vector3d p[4]) const {
  for (int k = 0; k < 4; ++k)
    p[k] = Eigen::Vector3d(grid_.x(i + (k & 1)), grid_.y(j + (k >> 1)), CornerHeight(i, j, k));
}

double Terrain::FloorDistance(const Eigen::Vector3d& c, int i, int j, double limit,
                              Eigen::Vector3d* normal, int* triangle) const {
  Eigen::Vector3d p[4];
  FloorCorners(i, j, p);
  // Cells split along the (i, j)-(i+1, j+1) diagonal: (p0, p1, p3), (p0, p3, p2).
  const std::size_t id = 2 * (static_cast<std::size_t>(j) * (grid_.nx - 1) + i);
  Eigen::Vector3d n0, n1;
  const double d0 = FacetDistance(c, p[0], p[1], p[3], floor_up_[id], limit, &n0);
  const double d1 = FacetDistance(c, p[0], p[3], p[2], floor_up_[id + 1], limit, &n1);
  *triangle = d0 <= d1 ? 0 : 1;
  *normal = d0 <= d1 ? n0 : n1;
  return std::min(d0, d1);
}

void Terrain::CellWindow(const Eigen::Vector3d& c, double w, int* i0, int* i1, int* j0,
                         int* j1) const {
  *i0 = std::max(static_cast<int>(std::floor((c.x() - w - grid_.x0) * inv_spacing_)), 0);
  *i1 = std::min(static_cast<int>(std::floor((c.x() + w - grid_.x0) * inv_spacing_)), grid_.nx - 2);
  *j0 = std::max(static_cast<int>(std::floor((c.y() - w - grid_.y0) * inv_spacing_)), 0);
  *j1 = std::min(static_cast<int>(std::floor((c.y() + w - grid_.y0) * inv_spacing_)), grid_.ny - 2);
}

bool Terrain::CellValid(int i, int j) const {
  return grid_.valid(i, j) && grid_.valid(i + 1, j) && grid_.valid(i, j + 1) &&
         grid_.valid(i + 1, j + 1);
}

double Terrain::FloorHeight(double x, double y) const {
  if (!OnSlope(x, y)) return -kInf;
  const double fx = (x - grid_.x0) * inv_spacing_, fy = (y - grid_.y0) * inv_spacing_;
  const int i = std::min(static_cast<int>(fx), grid_.nx - 2);
  const int j = std::min(static_cast<int>(fy), grid_.ny - 2);
  const double u = fx - i, v = fy - j;
  return OnFacets(u, v, CornerHeight(i, j, 0), CornerHeight(i, j, 1), CornerHeight(i, j, 2),
                  CornerHeight(i, j, 3));
}

bool Terrain::Elevation(double x, double y, double* z) const {
  if (!OnSlope(x, y)) return false;
  const double fx = (x - grid_.x0) / grid_.spacing, fy = (y - grid_.y0) / grid_.spacing;
  const int i = std::min(static_cast<int>(fx), grid_.nx - 2);
  const int j = std::min(static_cast<int>(fy), grid_.ny - 2);
  const double u = fx - i, v = fy - j;
  *z = OnFacets(u, v, grid_.z[grid_.index(i, j)], grid_.z[grid_.index(i + 1, j)],
                grid_.z[grid_.index(i, j + 1)], grid_.z[grid_.index(i + 1, j + 1)]);
  return true;
}

bool Terrain::GroundHeight(double x, double y, double* z) const {
  if (!OnSlope(x, y)) return false;
  double top = FloorHeight(x, y);
  // The candidate spheres of the cell: every sphere over it that is not
  // buried under the others (a tilted sphere's top may lie several cells
  // from its node).
  const std::size_t cell = static_cast<std::size_t>(CellOf(x, y));
  for (int k = list_start_[cell]; k < list_start_[cell + 1]; ++k) {
    const std::size_t n = static_cast<std::size_t>(list_[static_cast<std::size_t>(k)]);
    const double r = radius_[n];
    const double dx = x - centre_[n].x(), dy = y - centre_[n].y();
    const double h2 = r * r - dx * dx - dy * dy;
    if (h2 > 0.0) top = std::max(top, centre_[n].z() + std::sqrt(h2));
  }
  *z = top;
  return true;
}

int Terrain::MaterialAt(double x, double y) const {
  // Nearest node: floor(f + 1/2), clamped before the conversion to int.
  const double fx = std::floor((x - grid_.x0) * inv_spacing_ + 0.5);
  const double fy = std::floor((y - grid_.y0) * inv_spacing_ + 0.5);
  const int i = static_cast<int>(std::clamp(fx, 0.0, static_cast<double>(grid_.nx - 1)));
  const int j = static_cast<int>(std::clamp(fy, 0.0, static_cast<double>(grid_.ny - 1)));
  return grid_.material[grid_.index(i, j)];
}

double Terrain::Ceiling(double xmin, double xmax, double ymin, double ymax) const {
  const double s = grid_.spacing;
  const int i0 = std::max(static_cast<int>(std::floor((xmin - grid_.x0) / s)), 0);
  const int i1 = std::min(static_cast<int>(std::floor((xmax - grid_.x0) / s)), grid_.nx - 2);
  const int j0 = std::max(static_cast<int>(std::floor((ymin - grid_.y0) / s)), 0);
  const int j1 = std::min(static_cast<int>(std::floor((ymax - grid_.y0) / s)), grid_.ny - 2);
  double top = -kInf;
  const int cx = grid_.nx - 1;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      top = std::max(top, ceiling_[static_cast<std::size_t>(j) * cx + i]);
  return top;
}

void Terrain::FindContacts(const Eigen::Vector3d& c, double a,
                           std::vector<TerrainContact>* out) const {
  const int cell = CellOf(c.x(), c.y());
  if (has_rough_ && cell >= 0) {
    const int* begin = list_.data() + list_start_[static_cast<std::size_t>(cell)];
    const int* end = list_.data() + list_start_[static_cast<std::size_t>(cell) + 1];
    SphereContacts(c, a, begin, end, out);
  }
  FloorContacts(c, a, out);
}

void Terrain::SphereContacts(const Eigen::Vector3d& c, double a, const int* begin, const int* end,
                             std::vector<TerrainContact>* out) const {
  TerrainContact contact;
  for (const int* it = begin; it != end; ++it)
    if (SphereContact(c, a, *it, &contact)) out->push_back(contact);
}

void Terrain::FloorContacts(const Eigen::Vector3d& c, double a,
                            std::vector<TerrainContact>* out) const {
  // The deepest contact with the floor surface (smooth facets, or the catch
  // surface under rough cells) of the cells under the element.
  const int cx = grid_.nx - 1;
  int i0, i1, j0, j1;
  CellWindow(c, a, &i0, &i1, &j0, &j1);
  TerrainContact best;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const std::size_t id = static_cast<std::size_t>(j) * cx + i;
      if (c.z() - a >= floor_top_[id]) continue;  // above every corner: no touch (or a hole cell)
      Eigen::Vector3d normal;
      int t = 0;
      const double overlap = a - FloorDistance(c, i, j, a - best.overlap, &normal, &t);
      if (overlap > best.overlap) {
        best.overlap = overlap;
        best.normal = normal;
        best.point = c - normal * (a - 0.5 * overlap);
        const std::int64_t facet = 2 * static_cast<std::int64_t>(id) + t;
        best.key = smooth_cell_[id] ? -(facet + 1) : kCatchKey - facet;
      }
    }
  }
  if (best.overlap > 0.0) {
    best.material = MaterialAt(best.point.x(), best.point.y());
    out->push_back(best);
  }
}

double Terrain::Gap(const Eigen::Vector3d& c, double a, double reach) const {
  // Everything an element inside this sphere may touch once its centre moved
  // by up to reach: the candidate spheres and the floor surface of the cells
  // it may be centred over.
  double gap = kInf;
  ForEachCandidate(c, a + reach, [&](int n) { gap = SphereGap(c, a, n, gap); });
  return std::min(gap, FloorGap(c, a, reach, gap));
}

void Terrain::NearSpheres(const Eigen::Vector3d& c, double rb, double skin,
                          std::vector<int>* out) const {
  out->clear();
  if (!has_rough_) return;
  ForEachCandidate(c, rb + skin, [&](int n) {
    const double reach = radius_[n] + rb + skin;
    if ((c - centre_[n]).squaredNorm() < reach * reach) out->push_back(n);
  });
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

double Terrain::FloorGap(const Eigen::Vector3d& c, double a, double reach, double bound) const {
  double gap = bound;
  const int cx = grid_.nx - 1;
  int i0, i1, j0, j1;
  CellWindow(c, a + reach, &i0, &i1, &j0, &j1);
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const std::size_t id = static_cast<std::size_t>(j) * cx + i;
      // Vertically above every floor corner by more than the gap so far: not nearer.
      if (c.z() - a - floor_top_[id] >= gap) continue;
      Eigen::Vector3d normal;
      int t = 0;
      gap = std::min(gap, FloorDistance(c, i, j, gap + a, &normal, &t) - a);
    }
  }
  return gap;
}

}  // namespace rockcal::core
