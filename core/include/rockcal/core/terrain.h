// Terrain: a height field on a regular grid, with one virtual sphere per node.
#ifndef ROCKCAL_CORE_TERRAIN_H_
#define ROCKCAL_CORE_TERRAIN_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
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
  std::int64_t key = 0;    // identifies the obstacle (node or facet) for tangential history
};

// The terrain with its virtual spheres, built once per scene and rebuilt
// cheaply when roughness changes (calibration).
class Terrain final {
 public:
  Terrain() = default;
  // roughness_m[k] is the roughness of material k; max_element_radius bounds
  // the elements that will query this terrain (sizes the clearance ceiling).
  Terrain(HeightGrid grid, const std::vector<double>& roughness_m, double max_element_radius);

  const HeightGrid& grid() const { return grid_; }
  // Interpolated ground elevation (the triangulated surface); false over a hole
  // or outside the grid.
  bool Elevation(double x, double y, double* z) const;
  // False when (x, y) is outside the grid or in a cell with a hole corner:
  // a rock whose centre gets there has left the slope.
  bool OnSlope(double x, double y) const;
  // Material of the node nearest to (x, y) (clamped to the grid).
  int MaterialAt(double x, double y) const;
  // Upper bound of every obstacle (virtual sphere or facet) over the plan
  // rectangle [xmin, xmax] x [ymin, ymax]; -inf over nothing.
  double Ceiling(double xmin, double xmax, double ymin, double ymax) const;
  // Appends the contacts of an element sphere (centre c, radius a) to `out`.
  // Virtual spheres of every rough node nearby; for smooth cells the deepest
  // facet contact.
  void FindContacts(const Eigen::Vector3d& c, double a, std::vector<TerrainContact>* out) const;
  // Smallest gap between an element sphere and any obstacle near it (may be
  // negative: overlap); +inf when nothing is within `reach` horizontally.
  double Gap(const Eigen::Vector3d& c, double a, double reach) const;

  // Deepest sag of the virtual-sphere surface below the nodes: at a cell
  // centre, r - sqrt(r^2 - s^2/2) for the largest sphere radius r in use (r
  // itself where the four spheres leave a hole, R > 0.207 s); 0 when smooth.
  double sag() const { return sag_; }
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
  void BuildSpheres(const std::vector<double>& roughness_m);
  void BuildCeiling();

  HeightGrid grid_;
  double max_element_radius_ = 0.0;
  std::vector<Eigen::Vector3d> centre_;  // per node
  std::vector<double> radius_;           // per node, +inf when smooth or hole
  std::vector<std::uint8_t> smooth_cell_;  // per cell: a corner is smooth
  std::vector<double> ceiling_;          // per cell
  bool has_rough_ = false, has_smooth_ = false;
  double sag_ = 0.0;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_TERRAIN_H_
