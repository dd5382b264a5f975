// Terrain: a height field on a regular grid, with one virtual sphere per node.
#ifndef ROCKCAL_CORE_TERRAIN_H_
#define ROCKCAL_CORE_TERRAIN_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace rockcal::core {

// The terrain as data: node (i, j) is at (x0 + i*spacing, y0 + j*spacing) with
// elevation z[j*nx + i]; NaN elevation marks a hole (no data). material[j*nx+i]
// indexes Scene::materials.
struct HeightGrid {
  double x0 = 0.0, y0 = 0.0;
  double spacing = 1.0;  // s [m]
  int nx = 0, ny = 0;    // node counts
  std::vector<double> z;
  std::vector<int> material;

  int index(int i, int j) const { return j * nx + i; }
  bool valid(int i, int j) const;  // inside and not a hole
  double x(int i) const { return x0 + i * spacing; }
  double y(int j) const { return y0 + j * spacing; }
};

// A contact candidate found by Terrain::FindContacts.
struct TerrainContact {
  Eigen::Vector3d normal;  // unit, from the terrain towards the element
  Eigen::Vector3d point;   // contact point (middle of the overlap)
  double overlap = 0.0;    // > 0
  int material = 0;
  std::int64_t key = 0;  // identifies the obstacle (node or facet) for tangential history
};

// The terrain with its virtual spheres, built once per scene and rebuilt
// cheaply when roughness changes (calibration).
class Terrain final {
 public:
  Terrain() = default;
  // roughness_m[k] is the roughness of material k; max_element_radius bounds
  // the elements that will query this terrain (sizes the clearance ceiling).
  // Built on `threads` threads (0: OpenMP's default), the same at any count.
  Terrain(HeightGrid grid, const std::vector<double>& roughness_m, double max_element_radius,
          int threads = 0);

  const HeightGrid& grid() const { return grid_; }
  // Interpolated ground elevation (the triangulated surface); false over a hole
  // or outside the grid.
  bool Elevation(double x, double y, double* z) const;
  // The surface a rock touches at (x, y): the top of the virtual spheres
  // there (they sag below the triangulated surface between the nodes, by up
  // to `sag()`), or of the floor where that is higher (smooth facets, the
  // catch surface). Bounce and scar heights are measured from it, so a rock
  // rolling on the spheres is never below the ground. False off the slope.
  bool GroundHeight(double x, double y, double* z) const;
  // False when (x, y) is outside the grid or in a cell with a hole corner:
  // a rock whose centre gets there has left the slope.
  bool OnSlope(double x, double y) const { return CellOnSlope(CellOf(x, y)); }
  // The same for a cell index from CellOf (-1: off the grid).
  bool CellOnSlope(int cell) const {
    return cell >= 0 && floor_top_[static_cast<std::size_t>(cell)] > -kNoFloor;
  }
  // Index j * (nx - 1) + i of the grid cell under (x, y); -1 off the grid.
  int CellOf(double x, double y) const {
    // A point on an edge is on the grid: the product with the rounded
    // reciprocal may land a few ulps outside, hence the 1e-9 cells.
    const double fx = (x - grid_.x0) * inv_spacing_, fy = (y - grid_.y0) * inv_spacing_;
    constexpr double kEdge = 1e-9;
    if (!(fx >= -kEdge && fy >= -kEdge && fx <= grid_.nx - 1 + kEdge && fy <= grid_.ny - 1 + kEdge))
      return -1;
    const int i = std::min(static_cast<int>(fx), grid_.nx - 2);
    const int j = std::min(static_cast<int>(fy), grid_.ny - 2);
    return j * (grid_.nx - 1) + i;
  }
  // Material of the node nearest to (x, y) (clamped to the grid).
  int MaterialAt(double x, double y) const;
  // Upper bound of every obstacle (virtual sphere or facet) that an element
  // centred over the plan rectangle [xmin, xmax] x [ymin, ymax] may touch;
  // -inf over nothing.
  double Ceiling(double xmin, double xmax, double ymin, double ymax) const;
  // Appends the contacts of an element sphere (centre c, radius a <= the
  // max_element_radius given at construction) to `out`: the candidate virtual
  // spheres of the cell below c, and the deepest facet contact of smooth cells.
  void FindContacts(const Eigen::Vector3d& c, double a, std::vector<TerrainContact>* out) const;
  // Smallest gap between an element sphere and any obstacle it may touch
  // while its centre moves by at most `reach` (negative: overlap); +inf when none.
  double Gap(const Eigen::Vector3d& c, double a, double reach) const;
  // The same for the floor surface alone (smooth facets and the catch surface
  // under rough cells), never more than `bound`: while the sphere's centre
  // moves by less than min(result, reach) it cannot touch the floor.
  double FloorGap(const Eigen::Vector3d& c, double a, double reach,
                  double bound = std::numeric_limits<double>::infinity()) const;
  // min(gap, the gap between the sphere (c, a) and virtual sphere n); the
  // root is taken only when sphere n is nearer than `gap`.
  double SphereGap(const Eigen::Vector3d& c, double a, int n, double gap) const {
    const double beat = gap + radius_[static_cast<std::size_t>(n)] + a;
    const double d2 = (c - centre_[static_cast<std::size_t>(n)]).squaredNorm();
    if (beat > 0.0 && d2 >= beat * beat) return gap;
    return std::min(gap, std::sqrt(d2) - radius_[static_cast<std::size_t>(n)] - a);
  }

  // The candidate virtual spheres (sorted node indices) that a body inside the
  // sphere (c, rb) may touch while c moves by less than `skin`: a rock's
  // neighbour list, valid until it has moved that far.
  void NearSpheres(const Eigen::Vector3d& c, double rb, double skin, std::vector<int>* out) const;
  // The pieces of FindContacts, for callers that keep their own candidate
  // list (a rock's neighbour list): the contacts with the spheres of
  // [begin, end); the deepest contact with the floor surface (smooth facets,
  // or the catch surface) under an element.
  void SphereContacts(const Eigen::Vector3d& c, double a, const int* begin, const int* end,
                      std::vector<TerrainContact>* out) const;
  void FloorContacts(const Eigen::Vector3d& c, double a, std::vector<TerrainContact>* out) const;
  // The contact of the element sphere (c, a) with virtual sphere n; false
  // when they do not overlap. SphereContacts is this over a list.
  bool SphereContact(const Eigen::Vector3d& c, double a, int n, TerrainContact* out) const {
    const double r = radius_[static_cast<std::size_t>(n)];
    const Eigen::Vector3d d = c - centre_[static_cast<std::size_t>(n)];
    const double limit = a + r;
    const double d2 = d.squaredNorm();
    if (d2 >= limit * limit) return false;
    const double dist = std::sqrt(d2);
    out->normal = d / dist;
    out->overlap = limit - dist;
    out->point = c - out->normal * (a - 0.5 * out->overlap);
    out->material = grid_.material[static_cast<std::size_t>(n)];
    out->key = n;
    return true;
  }

  // Deepest sag of the virtual-sphere surface below the nodes, measured
  // normal to the surface: at a cell centre, r - sqrt(r^2 - h^2) with h half
  // the cell's surface diagonal (s / sqrt(2) on level ground), the largest
  // over the nodes (r itself where the four spheres leave a hole: R > 0.207 s
  // on level ground, faces steeper than the cap of BuildSpheres); 0 when
  // smooth.
  double sag() const { return sag_; }
  // The lowest support under (x, y): the facet surface in a smooth cell, the
  // catch surface that closes holes of the virtual-sphere surface in a rough
  // one (continuous, below the spheres); -inf off the slope. A rock centre
  // below it by more than the rock's radius has tunneled.
  double FloorHeight(double x, double y) const;
  // Mean number of candidate virtual spheres per cell (cost of a contact search).
  double mean_candidates() const {
    return list_start_.size() > 1 ? static_cast<double>(list_.size()) / (list_start_.size() - 1)
                                  : 0.0;
  }
  bool has_rough() const { return has_rough_; }
  bool has_smooth() const { return has_smooth_; }
  double xmin() const { return grid_.x0; }
  double ymin() const { return grid_.y0; }
  double xmax() const { return grid_.x0 + (grid_.nx - 1) * grid_.spacing; }
  double ymax() const { return grid_.y0 + (grid_.ny - 1) * grid_.spacing; }
  // Virtual sphere of node n (radius +inf for smooth nodes).
  const Eigen::Vector3d& sphere_centre(int n) const { return centre_[n]; }
  double sphere_radius(int n) const { return radius_[n]; }

 private:
  void BuildSpheres();
  // Per cell: the virtual spheres an element centred in it may touch (those
  // reaching the cell that are not buried under the others), and the ceiling.
  void BuildCandidates(int threads);
  struct CellScratch;
  // The candidates of cell (i, j) (appended to *list) and its ceiling, from
  // the nodes within `rings` cells; returns the floor of its catch surface
  // (-inf: a smooth cell or a hole).
  double BuildCellCandidates(int i, int j, int rings, CellScratch* scratch, std::vector<int>* list);
  // catch_z_ from the floors of the rough cells (BuildCellCandidates).
  void BuildCatchSurface(const std::vector<double>& cell_floor);
  // floor_top_ and floor_up_ per cell, and the ceilings raised by the floor
  // surfaces of the neighbouring cells.
  void BuildFloorTops();
  bool CellValid(int i, int j) const;  // all four corners are data
  // The cells (i0..i1, j0..j1) overlapping the plan square of half-width w around c.
  void CellWindow(const Eigen::Vector3d& c, double w, int* i0, int* i1, int* j0, int* j1) const;
  // Calls f(node) for every candidate sphere of the cells within plan
  // half-width w of c (a sphere may come once per cell that lists it).
  template <class F>
  void ForEachCandidate(const Eigen::Vector3d& c, double w, F f) const {
    int i0, i1, j0, j1;
    CellWindow(c, w, &i0, &i1, &j0, &j1);
    const int cx = grid_.nx - 1;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t id = static_cast<std::size_t>(j) * cx + i;
        for (int k = list_start_[id]; k < list_start_[id + 1]; ++k)
          f(list_[static_cast<std::size_t>(k)]);
      }
  }
  // Corner k (bit 0: +i, bit 1: +j) of cell (i, j) on its floor surface: the
  // terrain for a smooth cell, the catch surface for a rough one.
  double CornerHeight(int i, int j, int k) const;
  // The four corners of cell (i, j) on its floor surface, in CornerHeight order.
  void FloorCorners(int i, int j, Eigen::Vector3d p[4]) const;
  // Signed one-sided distance from c to the floor surface of cell (i, j); a
  // result >= limit is only a lower bound (and sets no normal).
  double FloorDistance(const Eigen::Vector3d& c, int i, int j, double limit,
                       Eigen::Vector3d* normal, int* triangle) const;

  static constexpr double kNoFloor = std::numeric_limits<double>::infinity();

  HeightGrid grid_;
  double inv_spacing_ = 1.0;
  double max_element_radius_ = 0.0;
  std::vector<double> roughness_;          // per material, R [m] (0: smooth)
  std::vector<Eigen::Vector3d> centre_;    // per node
  std::vector<double> radius_;             // per node, +inf when smooth or hole
  std::vector<std::uint8_t> smooth_cell_;  // per cell: a corner is smooth
  std::vector<double>
      ceiling_;  // per cell: no obstacle an element centred there may touch is higher
  std::vector<int> list_start_, list_;  // per cell, candidate sphere nodes (CSR)
  std::vector<double> catch_z_;    // per node, height of the catch surface (+inf: no rough cell)
  std::vector<double> floor_top_;  // per cell, highest corner of its floor surface (-inf: hole)
  std::vector<Eigen::Vector3d> floor_up_;  // per cell, unit upward normals of its two floor facets
  bool has_rough_ = false, has_smooth_ = false;
  double sag_ = 0.0;
  double max_offset_ = 0.0;  // largest plan distance from a node to its sphere centre
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_TERRAIN_H_
