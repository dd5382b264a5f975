// Rock shapes as rigid clusters of equal spheres (CRSP-3D manual, Figure 37).
#ifndef ROCKCAL_CORE_ROCK_SHAPE_H_
#define ROCKCAL_CORE_ROCK_SHAPE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace rockcal::core {

// kScanned: a clump fitted to a scanned shape's hull (clump.h); never parsed
// by name (a site names the shape's file instead).
enum class Shape { kSphere, kCylinder, kDisc, kTetrahedron, kCube, kBox, kScanned };

const char* ShapeToString(Shape shape);
// Parses "sphere", "cylinder", "disc", "tetrahedron", "cube", "box"; false
// otherwise (also for "scanned").
bool StringToShape(const std::string& name, Shape* shape);
// The names StringToShape accepts, comma separated (for error messages).
const char* ShapeNames();

// A rigid body made of equal spheres, in its principal frame (centre of mass at
// the origin, inertia diagonal).
struct RockBody {
  Shape shape = Shape::kSphere;
  double size = 1.0;            // m, the shape's nominal size (see README)
  double mass = 0.0;            // kg
  double element_radius = 0.0;  // m
  std::vector<Eigen::Vector3d> elements;  // element centres, body frame
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();  // principal moments, kg m^2
  double bounding_radius = 0.0;  // max |element| + element_radius
  // Mean projected area of the nominal solid over all orientations, its
  // surface / 4 (Cauchy's formula for convex bodies; pi r^2 for a sphere),
  // m^2: the frontal area undergrowth acts on (Material::vegetation_pa).
  double frontal_area = 0.0;
};

// Nominal volume of `shape` at `size` (m^3); 0 for kScanned (its hull's). A box's size is its longest
// side L1, its other sides in `box` proportions (L1 : L2 : L3, any scale).
double NominalVolume(Shape shape, double size,
                     const Eigen::Vector3d& box = Eigen::Vector3d::Ones());
// Nominal surface area of `shape` at `size` (m^2), same solids as NominalVolume.
double NominalSurface(Shape shape, double size,
                      const Eigen::Vector3d& box = Eigen::Vector3d::Ones());
// Builds the body of `shape` at `size` [m] with unit weight gamma [N/m^3] and
// gravity g [m/s^2]: mass = gamma * volume / g.
RockBody MakeRockBody(Shape shape, double size, double unit_weight, double gravity,
                      const Eigen::Vector3d& box = Eigen::Vector3d::Ones());
// A box of sides dims (L1, L2, L3 along the body's x, y, z; m) and `mass`
// [kg], built of equal spheres of radius min(dims) / 4: along each side as
// many as keep neighbours at most one diameter apart, the outermost touching
// the box's faces (a cube gives the 2 x 2 x 2 cluster of Shape::kCube).
RockBody MakeBoxBody(const Eigen::Vector3d& dims, double mass);
// `body` with its mass (and inertia) scaled to `mass` [kg].
RockBody WithMass(RockBody body, double mass);
// Full inertia tensor of the cluster about its centre of mass (for tests).
Eigen::Matrix3d ClusterInertiaTensor(const RockBody& body);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_ROCK_SHAPE_H_
