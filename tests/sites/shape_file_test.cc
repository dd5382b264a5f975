#include "rockcal/sites/shape_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "../core/scene_fixtures.h"
#include "rockcal/core/clump.h"
#include "rockcal/core/simulate.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

constexpr double kPi = 3.14159265358979323846;

// n points on the ellipsoid of semi-axes (a, b, c): a Fibonacci spiral on
// the unit sphere, stretched.
std::vector<Eigen::Vector3d> EllipsoidPoints(int n, const Eigen::Vector3d& semi) {
  std::vector<Eigen::Vector3d> p;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (k + 0.5) * 2.0 / n, r = std::sqrt(1.0 - z * z);
    p.emplace_back(semi.x() * r * std::cos(golden * k), semi.y() * r * std::sin(golden * k),
                   semi.z() * z);
  }
  return p;
}

// Points on the surface of a cube of side s centred at `centre`: a 5 x 5
// grid on each face.
std::vector<Eigen::Vector3d> CubePoints(double s, const Eigen::Vector3d& centre) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int k = 0; k <= 4; ++k)
        if (i == 0 || i == 4 || j == 0 || j == 4 || k == 0 || k == 4)
          p.push_back(centre + s * Eigen::Vector3d(i / 4.0 - 0.5, j / 4.0 - 0.5, k / 4.0 - 0.5));
  return p;
}

// The clump of `points` against the exact solid's volume and principal
// moments (unit density, ascending).
void ExpectClumpMatches(const std::vector<Eigen::Vector3d>& points, double volume,
                        const Eigen::Vector3d& moments, const char* what) {
  const core::Polyhedron hull = ConvexHull(points, what);
  const core::ScannedShape s = core::MakeScannedShape(hull, core::ClumpOptions(), what, what);
  const core::Clump& c = s.clump;
  EXPECT_NEAR(c.union_volume / volume, 1.0, 0.03)
      << what << ": union volume " << c.union_volume << " exact " << volume << " hull "
      << c.hull_volume << ", " << c.centres.size() << " spheres of radius " << c.radius;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(c.union_moments[k] / moments[k], 1.0, 0.05)
        << what << ": principal moment " << k << " of the union " << c.union_moments[k]
        << " exact " << moments[k] << " hull " << c.hull_moments[k];
  }
  // The rigid body's properties are the hull's: within the sampling's error of the solid.
  EXPECT_NEAR(c.hull_volume / volume, 1.0, 0.03) << what << ": hull " << c.hull_volume;
}

TEST(Clump, SampledSphereMatchesVolumeAndMoments) {
  const double r = 0.5;
  const double v = 4.0 / 3.0 * kPi * r * r * r;
  ExpectClumpMatches(EllipsoidPoints(600, Eigen::Vector3d::Constant(r)), v,
                     Eigen::Vector3d::Constant(0.4 * v * r * r), "sphere");
}

TEST(Clump, CubeMatchesVolumeAndMoments) {
  const double s = 0.8, v = s * s * s;
  ExpectClumpMatches(CubePoints(s, Eigen::Vector3d(3, -2, 1)), v,
                     Eigen::Vector3d::Constant(v * s * s / 6.0), "cube");
}

TEST(Clump, ElongatedEllipsoidMatchesVolumeAndMoments) {
  const Eigen::Vector3d semi(1.5, 0.6, 0.4);
  const double v = 4.0 / 3.0 * kPi * semi.prod();
  const Eigen::Vector3d sq = semi.cwiseProduct(semi);
  // Ascending: the smallest moment about the longest axis.
  ExpectClumpMatches(EllipsoidPoints(1500, semi), v,
                     v / 5.0 * Eigen::Vector3d(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()),
                     "ellipsoid");
}

// A block dropped flat from 20 m on level ground with restitution e, on the
// production path (as restitution_heavy_test.cc's built-in cube): the first
// rebound's apex ratio of the block's lowest point.
double FlatLandingApexRatio(double e, const core::RockGroup& group) {
  core::Scene scene = core::testing::FlatScene(core::testing::SmoothMaterial(e, 0.005, 0.5));
  scene.groups = {group};
  scene.groups[0].release.orientation = Eigen::Quaterniond::Identity();
  scene.options.max_time = 4.5;
  scene.options.record.trajectories = 1;
  scene.options.record.sample_seconds = 1e-4;
  const core::SimulationResult result = core::Simulate(scene);
  const auto& tr = result.rocks[0].trajectory;
  const core::RockBody body = core::GroupRockBody(group, 0, 0.0, scene.gravity);
  double below = 0.0;  // the lowest point below the centre, identity orientation
  for (const auto& el : body.elements) below = std::max(below, body.element_radius - el.z());
  EXPECT_NEAR(tr[0].x.z() - below, 20.0, 1e-9);
  return (core::testing::FirstApex(tr) - below) / (tr[0].x.z() - below);
}

TEST(Clump, CubeShapedCloudReboundsLikeTheBuiltInCube) {
  const double size = 0.8;
  core::ClumpOptions options;
  options.spheres = 8;
  const auto shape = std::make_shared<const core::ScannedShape>(core::MakeScannedShape(
      ConvexHull(CubePoints(size, Eigen::Vector3d(1, 2, 3)), "cube"), options, "cube", "cube"));
  core::RockGroup scanned = core::testing::PointGroup(core::Shape::kScanned, size, 10, 10, 20);
  scanned.scanned = shape;
  const core::RockGroup cube = core::testing::PointGroup(core::Shape::kCube, size, 10, 10, 20);
  for (double e : {0.2, 0.5, 0.8}) {
    const double a = FlatLandingApexRatio(e, scanned), b = FlatLandingApexRatio(e, cube);
    // The built-in cube's own test (restitution_heavy_test.cc) holds it within 2 % of e.
    EXPECT_NEAR(std::sqrt(a) / e, 1.0, 0.02) << "scanned cube, e = " << e
                                             << " rebound/impact speed = " << std::sqrt(a);
    EXPECT_NEAR(std::sqrt(a) / std::sqrt(b), 1.0, 0.02)
        << "e = " << e << ": scanned " << std::sqrt(a) << " built-in " << std::sqrt(b);
  }
}

TEST(ShapeFile, ReadsAPointCloudAndAClosedStl) {
  TempDir dir;
  std::ostringstream xyz;
  for (const auto& p : CubePoints(1.0, Eigen::Vector3d::Zero()))
    xyz << p.x() << " " << p.y() << " " << p.z() << "\n";
  const std::string cloud = dir.Write("cube.xyz", xyz.str());
  const auto shape = LoadScannedShape(cloud, 1.0, core::ClumpOptions());
  EXPECT_NEAR(shape->mass.volume, 1.0, 1e-12);
  EXPECT_EQ(shape->name, "cube");
  // A closed cube of side 2 as STL: 8 vertices, 12 outward triangles.
  std::vector<Eigen::Vector3d> v;
  for (int k = 0; k < 8; ++k) v.emplace_back((k & 1) ? 2 : 0, (k & 2) ? 2 : 0, (k & 4) ? 2 : 0);
  const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  std::ostringstream stl;
  stl << "solid c\n";
  for (const auto& f : faces) {
    stl << "facet normal 0 0 0\nouter loop\n";
    for (int k : f) stl << "vertex " << v[k].x() << " " << v[k].y() << " " << v[k].z() << "\n";
    stl << "endloop\nendfacet\n";
  }
  stl << "endsolid c\n";
  const std::string closed = dir.Write("c.stl", stl.str());
  EXPECT_EQ(ReadShapePoints(closed, 1.0).size(), 8u);
  const auto box = LoadScannedShape(closed, 0.5, core::ClumpOptions());  // file in half-metres
  EXPECT_NEAR(box->mass.volume, 1.0, 1e-12);
  EXPECT_NEAR(box->mass.surface, 6.0, 1e-12);
}

TEST(ShapeFile, BadFilesNameTheFile) {
  TempDir dir;
  EXPECT_THAT(ErrorOf([&] { ReadShapePoints(dir.path() + "/missing.xyz", 1.0); }),
              HasSubstr("missing.xyz"));
  const std::string few = dir.Write("few.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  EXPECT_THAT(ErrorOf([&] { ReadShapePoints(few, 1.0); }),
              ::testing::AllOf(HasSubstr("few.xyz"), HasSubstr("too few points: 4")));
  std::ostringstream flat;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) flat << i << " " << j << " 2\n";
  const std::string plane = dir.Write("flat.xyz", flat.str());
  EXPECT_THAT(ErrorOf([&] { ConvexHull(ReadShapePoints(plane, 1.0), plane); }),
              ::testing::AllOf(HasSubstr("flat.xyz"), HasSubstr("degenerate")));
  const std::string open = dir.Write(
      "open.stl",
      "solid o\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nendsolid o\n");
  EXPECT_THAT(ErrorOf([&] { ReadShapePoints(open, 1.0); }),
              ::testing::AllOf(HasSubstr("open.stl"), HasSubstr("not a closed surface")));
}

}  // namespace
}  // namespace rockcal::sites
