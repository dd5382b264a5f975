#include "rockcal/core/rock_shape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace rockcal::core {
namespace {

constexpr Shape kAll[] = {Shape::kSphere, Shape::kCylinder, Shape::kDisc, Shape::kTetrahedron,
                          Shape::kCube};

TEST(RockShape, MassCentreAndSymmetricInertia) {
  const double gamma = 26e3, g = 9.80665, size = 1.3;
  for (Shape shape : kAll) {
    const RockBody b = MakeRockBody(shape, size, gamma, g);
    EXPECT_NEAR(b.mass, gamma * NominalVolume(shape, size) / g, 1e-9) << ShapeToString(shape);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& e : b.elements) centre += e;
    EXPECT_NEAR(centre.norm(), 0.0, 1e-12) << ShapeToString(shape);
    const Eigen::Matrix3d inertia = ClusterInertiaTensor(b);
    EXPECT_NEAR((inertia - inertia.transpose()).norm(), 0.0, 1e-12);
    const Eigen::Matrix3d off = inertia - Eigen::Matrix3d(inertia.diagonal().asDiagonal());
    EXPECT_NEAR(off.norm(), 0.0, 1e-9 * inertia.norm()) << ShapeToString(shape) << "\n" << inertia;
    EXPECT_GT(b.inertia.minCoeff(), 0.0);
  }
}

TEST(RockShape, GeometryOfEachShape) {
  const double size = 2.0;
  // Sphere: one element of diameter = size, I = 2/5 m r^2.
  RockBody s = MakeRockBody(Shape::kSphere, size, 1.0, 1.0);
  EXPECT_EQ(s.elements.size(), 1u);
  EXPECT_DOUBLE_EQ(s.element_radius, 1.0);
  EXPECT_NEAR(s.inertia.x(), 0.4 * s.mass, 1e-12);
  EXPECT_NEAR(NominalVolume(Shape::kSphere, size), M_PI * 8 / 6, 1e-12);
  // Cube of side 2: eight elements of radius 0.5 filling the box; isotropic.
  RockBody c = MakeRockBody(Shape::kCube, size, 1.0, 1.0);
  EXPECT_EQ(c.elements.size(), 8u);
  EXPECT_NEAR(c.bounding_radius, std::sqrt(3.0) * 0.5 + 0.5, 1e-12);
  EXPECT_NEAR(c.inertia.x(), c.inertia.z(), 1e-12);
  EXPECT_NEAR(NominalVolume(Shape::kCube, size), 8.0, 1e-12);
  // Tetrahedron of height 2: four touching elements spanning that height; isotropic.
  RockBody t = MakeRockBody(Shape::kTetrahedron, size, 1.0, 1.0);
  EXPECT_EQ(t.elements.size(), 4u);
  EXPECT_NEAR((t.elements[0] - t.elements[2]).norm(), 2 * t.element_radius, 1e-12);
  EXPECT_NEAR(t.inertia.x(), t.inertia.y(), 1e-12);
  EXPECT_NEAR(t.inertia.x(), t.inertia.z(), 1e-12);
  // Cylinder: two elements along x, so the x moment is the smallest.
  RockBody y = MakeRockBody(Shape::kCylinder, size, 1.0, 1.0);
  EXPECT_EQ(y.elements.size(), 2u);
  EXPECT_LT(y.inertia.x(), y.inertia.y());
  EXPECT_NEAR(y.inertia.y(), y.inertia.z(), 1e-12);
  // Disc: three touching elements in the xy plane; z moment the largest.
  RockBody d = MakeRockBody(Shape::kDisc, size, 1.0, 1.0);
  EXPECT_EQ(d.elements.size(), 3u);
  EXPECT_NEAR((d.elements[0] - d.elements[1]).norm(), 2 * d.element_radius, 1e-12);
  EXPECT_NEAR(d.inertia.x(), d.inertia.y(), 1e-12);
  EXPECT_GT(d.inertia.z(), d.inertia.x());
}

// The frontal area undergrowth acts on is the mean projected area, surface
// / 4 for a convex solid: pi r^2 for a sphere, 6 s^2 / 4 for a cube, half
// the sides' pairwise products summed for a box, whatever its mass.
TEST(RockShape, FrontalAreaIsTheMeanProjectedArea) {
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(MakeRockBody(Shape::kSphere, 0.6, 26e3, 9.81).frontal_area, pi * 0.09, 1e-12);
  EXPECT_NEAR(MakeRockBody(Shape::kCube, 0.5, 26e3, 9.81).frontal_area, 1.5 * 0.25, 1e-12);
  const RockBody box = MakeBoxBody(Eigen::Vector3d(1.6, 1.3, 1.0), 500.0);
  EXPECT_NEAR(box.frontal_area, 0.5 * (1.6 * 1.3 + 1.3 * 1.0 + 1.6 * 1.0), 1e-12);
  EXPECT_EQ(WithMass(box, 900.0).frontal_area, box.frontal_area);
  // A cylinder of length s and diameter s / 2: two ends and the side.
  const double s = 0.8;
  EXPECT_NEAR(MakeRockBody(Shape::kCylinder, s, 26e3, 9.81).frontal_area,
              (2 * pi * (s / 4) * (s / 4) + pi * (s / 2) * s) / 4, 1e-12);
}

TEST(RockShape, ParseNames) {
  Shape s;
  for (Shape shape : kAll) {
    ASSERT_TRUE(StringToShape(ShapeToString(shape), &s));
    EXPECT_EQ(s, shape);
  }
  EXPECT_FALSE(StringToShape("blob", &s));
}


// A box of equal sides is the cube cluster; a longer box gets more elements
// along its longer sides, none more than a diameter apart, the outermost
// touching its faces.
TEST(RockShape, BoxClusters) {
  const RockBody cube = MakeRockBody(Shape::kCube, 0.8, 26e3, 9.81);
  const RockBody box = MakeBoxBody(Eigen::Vector3d(0.8, 0.8, 0.8), cube.mass);
  ASSERT_EQ(box.elements.size(), 8u);
  EXPECT_NEAR(box.element_radius, cube.element_radius, 1e-15);
  EXPECT_NEAR(box.bounding_radius, cube.bounding_radius, 1e-12);
  EXPECT_NEAR((box.inertia - cube.inertia).norm(), 0.0, 1e-9 * cube.inertia.norm());

  const Eigen::Vector3d sides(1.6, 1.3, 1.0);
  const RockBody b = MakeBoxBody(sides, 1000.0);
  const double a = 0.25;  // a quarter of the shortest side
  EXPECT_NEAR(b.element_radius, a, 1e-15);
  EXPECT_EQ(b.elements.size(), 4u * 3u * 2u) << "elements along 1.6, 1.3, 1.0 m";
  EXPECT_EQ(b.mass, 1000.0);
  EXPECT_EQ(b.shape, Shape::kBox);
  EXPECT_EQ(b.size, 1.6);
  for (int k = 0; k < 3; ++k) {
    double lo = 1e9, hi = -1e9;
    for (const auto& e : b.elements) {
      lo = std::min(lo, e[k] - a);
      hi = std::max(hi, e[k] + a);
    }
    EXPECT_NEAR(lo, -sides[k] / 2, 1e-12) << "axis " << k;
    EXPECT_NEAR(hi, sides[k] / 2, 1e-12) << "axis " << k;
  }
  // Longest axis has the smallest moment of inertia.
  EXPECT_LT(b.inertia.x(), b.inertia.y());
  EXPECT_LT(b.inertia.y(), b.inertia.z());
  // By unit weight: mass from the box's volume.
  const RockBody w = MakeRockBody(Shape::kBox, 1.6, 26e3, 9.81, Eigen::Vector3d(16, 13, 10));
  EXPECT_NEAR(w.mass, 26e3 * 1.6 * 1.3 * 1.0 / 9.81, 1e-9);
  EXPECT_NEAR(NominalVolume(Shape::kBox, 1.6, Eigen::Vector3d(16, 13, 10)), 2.08, 1e-12);
  // WithMass scales mass and inertia together.
  const RockBody heavy = WithMass(b, 3000.0);
  EXPECT_NEAR((heavy.inertia - 3.0 * b.inertia).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace rockcal::core
