#include "rockcal/core/rock_shape.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rockcal::core {
namespace {

constexpr Shape kAll[] = {Shape::kSphere, Shape::kCylinder, Shape::kDisc, Shape::kTetrahedron,
                          Shape::kCube};

TEST(RockShape, MassCentreAndSymmetricInertia) {
  const double gamma = 26e3, g = 9.80665, size = 1.3;
  for (Shape shape : kAll) {
    const RockBody b = MakeRockBody(shape, size, gamma, g);
    EXPECT_NEAR(b.mass, gamma * NominalVolume(shape, size) / g, 1e-9) << ShapeName(shape);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& e : b.elements) centre += e;
    EXPECT_NEAR(centre.norm(), 0.0, 1e-12) << ShapeName(shape);
    const Eigen::Matrix3d inertia = ClusterInertiaTensor(b);
    EXPECT_NEAR((inertia - inertia.transpose()).norm(), 0.0, 1e-12);
    const Eigen::Matrix3d off = inertia - Eigen::Matrix3d(inertia.diagonal().asDiagonal());
    EXPECT_NEAR(off.norm(), 0.0, 1e-9 * inertia.norm()) << ShapeName(shape) << "\n" << inertia;
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

TEST(RockShape, ParseNames) {
  Shape s;
  for (Shape shape : kAll) {
    ASSERT_TRUE(ParseShape(ShapeName(shape), &s));
    EXPECT_EQ(s, shape);
  }
  EXPECT_FALSE(ParseShape("blob", &s));
}

}  // namespace
}  // namespace rockcal::core
