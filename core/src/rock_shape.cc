#include "rockcal/core/rock_shape.h"

#include <algorithm>
#include <cmath>

#include "rockcal/core/name_table.h"
#include "rockcal/core/numbers.h"

namespace rockcal::core {
namespace {

// The shapes by name; a scanned shape is read from its file, never named.
constexpr Named<Shape> kShapes[] = {
    {Shape::kSphere, "sphere"},           {Shape::kCylinder, "cylinder"}, {Shape::kDisc, "disc"},
    {Shape::kTetrahedron, "tetrahedron"}, {Shape::kCube, "cube"},         {Shape::kBox, "box"},
    {Shape::kScanned, "scanned"}};

}  // namespace

const char* ShapeToString(Shape shape) { return NameOf(kShapes, shape); }

bool StringToShape(const std::string& name, Shape* shape) {
  Shape named = Shape::kScanned;
  if (!IdOf(kShapes, name, &named) || named == Shape::kScanned) return false;
  *shape = named;
  return true;
}

const char* ShapeNames() {
  static const std::string names = [] {
    std::string list;
    for (const Named<Shape>& s : kShapes)
      if (s.id != Shape::kScanned) list += std::string(list.empty() ? "" : ", ") + s.name;
    return list;
  }();
  return names.c_str();
}

namespace {

// The sides of a box of longest side `size` in proportions `box`.
Eigen::Vector3d BoxSides(double size, const Eigen::Vector3d& box) {
  return size * box / box.maxCoeff();
}

// Radius of the sphere that just holds every element.
void Finish(RockBody* body) {
  body->inertia = ClusterInertiaTensor(*body).diagonal();
  double reach = 0.0;
  for (const auto& e : body->elements) reach = std::max(reach, e.norm());
  body->bounding_radius = reach + body->element_radius;
}

}  // namespace

double NominalVolume(Shape shape, double size, const Eigen::Vector3d& box) {
  const double s3 = size * size * size;
  switch (shape) {
    case Shape::kSphere:
      return kPi * s3 / 6.0;  // diameter = size
    case Shape::kCylinder:
      return kPi * s3 / 16.0;  // length = size, diameter = size / 2
    case Shape::kDisc:
      return std::sqrt(3.0) * s3 / 8.0;  // triangle of side size, thickness size / 2
    case Shape::kTetrahedron: {
      const double edge = size * std::sqrt(1.5);  // regular, height = size
      return edge * edge * edge / (6.0 * std::sqrt(2.0));
    }
    case Shape::kCube:
      return s3;
    case Shape::kBox:
      return BoxSides(size, box).prod();
    case Shape::kScanned:
      return 0.0;
  }
  return 0.0;
}

double NominalSurface(Shape shape, double size, const Eigen::Vector3d& box) {
  const double s2 = size * size;
  switch (shape) {
    case Shape::kSphere:
      return kPi * s2;
    case Shape::kCylinder:
      return 2.0 * kPi * s2 / 16.0 + kPi * s2 / 2.0;  // two ends of radius size / 4, the side
    case Shape::kDisc:
      return std::sqrt(3.0) / 2.0 * s2 + 1.5 * s2;  // two triangles, three sides of size x size / 2
    case Shape::kTetrahedron: {
      const double edge = size * std::sqrt(1.5);
      return std::sqrt(3.0) * edge * edge;
    }
    case Shape::kCube:
      return 6.0 * s2;
    case Shape::kBox: {
      const Eigen::Vector3d d = BoxSides(size, box);
      return 2.0 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
    }
    case Shape::kScanned:
      return 0.0;
  }
  return 0.0;
}

RockBody MakeBoxBody(const Eigen::Vector3d& dims, double mass) {
  RockBody body;
  body.shape = Shape::kBox;
  body.size = dims.maxCoeff();
  body.mass = mass;
  body.frontal_area = NominalSurface(Shape::kBox, body.size, dims) / 4.0;
  const double a = dims.minCoeff() / 4.0;
  body.element_radius = a;
  int n[3];
  double first[3], pitch[3];
  for (int k = 0; k < 3; ++k) {
    const double span = dims[k] - 2.0 * a;  // between the outermost centres
    n[k] = std::max(2, static_cast<int>(std::ceil(span / (2.0 * a) - 1e-9)) + 1);
    first[k] = -0.5 * span;
    pitch[k] = span / (n[k] - 1);
  }
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k)
        body.elements.emplace_back(first[0] + i * pitch[0], first[1] + j * pitch[1],
                                   first[2] + k * pitch[2]);
  Finish(&body);
  return body;
}

RockBody WithMass(RockBody body, double mass) {
  const double scale = mass / body.mass;
  body.mass = mass;
  body.inertia *= scale;
  return body;
}

RockBody MakeRockBody(Shape shape, double size, double unit_weight, double gravity,
                      const Eigen::Vector3d& box) {
  if (shape == Shape::kBox) {
    const Eigen::Vector3d dims = BoxSides(size, box);
    return MakeBoxBody(dims, unit_weight * dims.prod() / gravity);
  }
  RockBody body;
  body.shape = shape;
  body.size = size;
  body.mass = unit_weight * NominalVolume(shape, size) / gravity;
  body.frontal_area = NominalSurface(shape, size) / 4.0;
  const double q = size / 4.0;
  switch (shape) {
    case Shape::kSphere:
      body.element_radius = size / 2.0;
      body.elements = {Eigen::Vector3d::Zero()};
      break;
    case Shape::kCylinder:
      body.element_radius = q;
      body.elements = {{-q, 0, 0}, {q, 0, 0}};
      break;
    case Shape::kDisc: {
      // Touching spheres at the corners of an equilateral triangle of side size/2.
      body.element_radius = q;
      const double rc = (size / 2.0) / std::sqrt(3.0);  // circumradius
      for (int k = 0; k < 3; ++k) {
        const double a = 2.0 * kPi * k / 3.0;
        body.elements.emplace_back(rc * std::cos(a), rc * std::sin(a), 0.0);
      }
      break;
    }
    case Shape::kTetrahedron: {
      // Touching spheres at the corners of a regular tetrahedron; overall height = size.
      const double edge = size / (1.0 + std::sqrt(2.0 / 3.0));
      body.element_radius = edge / 2.0;
      const double h = edge / 2.0, w = edge / (2.0 * std::sqrt(2.0));
      body.elements = {{h, 0, -w}, {-h, 0, -w}, {0, h, w}, {0, -h, w}};
      break;
    }
    case Shape::kCube:
      body.element_radius = q;
      for (int i = 0; i < 8; ++i)
        body.elements.emplace_back((i & 1) ? q : -q, (i & 2) ? q : -q, (i & 4) ? q : -q);
      break;
    case Shape::kBox:      // handled above
    case Shape::kScanned:  // ScannedBody (clump.h)
      break;
  }
  Finish(&body);
  return body;
}

Eigen::Matrix3d ClusterInertiaTensor(const RockBody& body) {
  const double me = body.mass / static_cast<double>(body.elements.size());
  const double a = body.element_radius;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (const auto& d : body.elements) {
    inertia += 0.4 * me * a * a * Eigen::Matrix3d::Identity();
    inertia += me * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  return inertia;
}

}  // namespace rockcal::core
