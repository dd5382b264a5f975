#include "rockcal/core/clump.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace rockcal::core {
namespace {

// A box [0, a] x [0, b] x [0, c] as 12 outward triangles.
Polyhedron BoxPolyhedron(double a, double b, double c) {
  Polyhedron p;
  for (int k = 0; k < 8; ++k)
    p.vertices.emplace_back((k & 1) ? a : 0.0, (k & 2) ? b : 0.0, (k & 4) ? c : 0.0);
  p.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return p;
}

TEST(PolyhedronMassProperties, BoxIsExact) {
  const double a = 2.0, b = 1.0, c = 0.5, v = a * b * c;
  const MassProperties m = PolyhedronMassProperties(BoxPolyhedron(a, b, c));
  EXPECT_NEAR(m.volume, v, 1e-12);
  EXPECT_NEAR(m.surface, 2 * (a * b + b * c + c * a), 1e-12);
  EXPECT_NEAR((m.centroid - Eigen::Vector3d(a, b, c) / 2).norm(), 0.0, 1e-12) << m.centroid;
  const Eigen::Vector3d exact = v / 12.0 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b);
  EXPECT_NEAR((m.inertia.diagonal() - exact).norm(), 0.0, 1e-12) << m.inertia;
  EXPECT_NEAR(m.inertia(0, 1), 0.0, 1e-12);
}

TEST(PolyhedronMassProperties, TurnedBoxHasItsPrincipalFrame) {
  Polyhedron p = BoxPolyhedron(0.5, 2.0, 1.0);
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (auto& v : p.vertices) v = turn * v + Eigen::Vector3d(5, -1, 2);
  MassProperties m;
  const Polyhedron principal = ToPrincipalFrame(p, &m);
  // x along the longest side (2.0), z along the shortest (0.5).
  Eigen::Vector3d lo = principal.vertices[0], hi = lo;
  for (const auto& v : principal.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  EXPECT_NEAR(((hi - lo) - Eigen::Vector3d(2.0, 1.0, 0.5)).norm(), 0.0, 1e-9) << (hi - lo);
  EXPECT_NEAR(PolyhedronMassProperties(principal).centroid.norm(), 0.0, 1e-12);
}

TEST(ScannedBody, MassAndInertiaComeFromTheHull) {
  const ScannedShape s = MakeScannedShape(BoxPolyhedron(2.0, 1.0, 0.5), ClumpOptions(), "b", "b");
  const double mass = 2600.0;
  const RockBody body = ScannedBody(s, 2.0, mass);  // sides 4 x 2 x 1 m
  EXPECT_EQ(body.shape, Shape::kScanned);
  EXPECT_EQ(body.mass, mass);
  const Eigen::Vector3d exact = mass / 12.0 * Eigen::Vector3d(4 + 1, 16 + 1, 16 + 4);
  EXPECT_NEAR((body.inertia - exact).norm() / exact.norm(), 0.0, 1e-12) << body.inertia;
  EXPECT_NEAR(body.frontal_area, 2 * (8 + 2 + 4) / 4.0, 1e-12);
  EXPECT_EQ(body.elements.size(), static_cast<std::size_t>(ClumpOptions().spheres));
  EXPECT_NEAR(body.element_radius, 2.0 * s.clump.radius, 1e-15);
}

}  // namespace
}  // namespace rockcal::core
