// Rock shapes as rigid clusters of equal spheres (CRSP-3D manual, Figure 37).
#ifndef ROCKCAL_CORE_ROCK_SHAPE_H_
#define ROCKCAL_CORE_ROCK_SHAPE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace rockcal::core {

enum class Shape { kSphere, kCylinder, kDisc, kTetrahedron, kCube };

const char* ShapeName(Shape shape);
// Parses "sphere", "cylinder", "disc", "tetrahedron", "cube"; false otherwise.
bool ParseShape(const std::string& name, Shape* shape);
// The names ParseShape accepts, comma separated (for error messages).
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
};

// Nominal volume of `shape` at `size` (m^3).
double NominalVolume(Shape shape, double size);
// Builds the body of `shape` at `size` [m] with unit weight gamma [N/m^3] and
// gravity g [m/s^2]: mass = gamma * volume / g.
RockBody MakeRockBody(Shape shape, double size, double unit_weight, double gravity);
// Full inertia tensor of the cluster about its centre of mass (for tests).
Eigen::Matrix3d ClusterInertiaTensor(const RockBody& body);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_ROCK_SHAPE_H_
