// Rocks of a scanned shape: the mass properties of a closed triangulated
// polyhedron (its convex hull) and a clump of overlapping equal spheres that
// fills it (docs/rock-shapes.md). Pure geometry: the hull itself is computed,
// and shape files read, in sites/ (sites/include/rockcal/sites/shape_file.h).
#ifndef ROCKCAL_CORE_CLUMP_H_
#define ROCKCAL_CORE_CLUMP_H_

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "rockcal/core/rock_shape.h"

namespace rockcal::core {

// A closed triangulated surface: every triangle's vertices counter-clockwise
// seen from outside (outward normals).
struct Polyhedron {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;
};

// Volume, centroid, surface and inertia of a solid polyhedron of unit
// density, exact (the divergence theorem over its triangles: each triangle
// and the origin span a signed tetrahedron whose integrals of 1, x, x x^T
// are closed-form; e.g. Tonon 2005, J. Math. Stat. 1:8-11).
struct MassProperties {
  double volume = 0.0;                                   // m^3
  double surface = 0.0;                                  // m^2
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();    // m
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();     // about the centroid, m^5 (unit density)
};
MassProperties PolyhedronMassProperties(const Polyhedron& p);

// What the spread of the clump's centres is fitted to, beside the volume.
enum class ClumpTarget {
  kMoments,  // the hull's three principal moments (the sides follow)
  kSides,    // the hull's bounding box along its principal axes (the moments follow)
};
const char* ClumpTargetToString(ClumpTarget target);
// Parses "moments" or "sides"; false otherwise.
bool StringToClumpTarget(const std::string& name, ClumpTarget* target);

// The clump fit's settings (defaults measured on the Authume shapes,
// docs/rock-shapes.md).
struct ClumpOptions {
  int spheres = 16;       // the sphere budget N, 1..64
  // Grid cells per side of the bounding box: the hull's interior points for
  // the centres' k-means (grid^3 cells) and the union's columns for its
  // volume and moments (grid^2 columns, exact along each), 16..200.
  int grid = 40;
  int lloyd_iterations = 200;  // at most, of the centres' k-means (it stops when none moves), >= 1
  int fit_iterations = 25;    // iterations of the radius / spread fit, >= 1
  ClumpTarget target = ClumpTarget::kMoments;
  bool IsValid(std::string* error) const;
};

// A clump of N equal spheres in the hull's principal frame, and how well its
// union matches the hull (uniform density both).
struct Clump {
  std::vector<Eigen::Vector3d> centres;  // m, principal frame
  double radius = 0.0;                  // m
  double hull_volume = 0.0;             // m^3, exact
  Eigen::Vector3d hull_moments = Eigen::Vector3d::Zero();  // principal moments / density, m^5, exact
  Eigen::Vector3d hull_sides = Eigen::Vector3d::Zero();    // bounding box along the principal axes, m
  double union_volume = 0.0;            // m^3, grid estimate
  Eigen::Vector3d union_moments = Eigen::Vector3d::Zero();  // about the hull's axes / density, m^5
  Eigen::Vector3d union_sides = Eigen::Vector3d::Zero();    // m, exact (centres +- radius)
  double volume_error = 0.0;            // union / hull - 1
  double moment_error = 0.0;            // max_k |union_k / hull_k - 1|
  double side_error = 0.0;              // max_k |union side_k / hull side_k - 1|
};

// A scanned shape ready to make rocks of: the hull moved to its principal
// frame (centroid at the origin, axes by increasing moment: x the longest),
// its mass properties there and its clump.
struct ScannedShape {
  std::string name;          // for messages and reports (the file's stem)
  std::string file;          // the shape file, as given
  Polyhedron hull;           // principal frame, m
  MassProperties mass;       // of `hull` (centroid 0, inertia diagonal)
  Clump clump;
};

// Moves `hull` to its principal frame: returns the rotated, centred copy and
// its mass properties (inertia diagonal, ascending; a right-handed frame).
Polyhedron ToPrincipalFrame(const Polyhedron& hull, MassProperties* props);

// Fits N equal overlapping spheres to the convex polyhedron `hull` (given in
// its principal frame). Centres: a centroidal Voronoi tessellation of the
// hull's volume (Lloyd 1982, IEEE Trans. Inf. Theory 28:129-137; Du, Faber
// & Gunzburger 1999, SIAM Review 41:637-676) by k-means of a regular grid of
// interior points, seeded by farthest-point sampling; then a common radius
// and a stretch of the centres along each principal axis, fitted so that the
// union's volume and either its three second moments (kMoments) or its
// bounding box (kSides) match the hull's (the union's integrals over
// columns, exact along each). Deterministic (serial).
Clump FitClump(const Polyhedron& hull, const ClumpOptions& options);

// The union of spheres of `radius` at `centres`: its volume [m^3] and its
// principal-axis moments about the origin (unit density) on `grid` x `grid`
// columns (exact along each), as FitClump measures them.
double UnionIntegrals(const std::vector<Eigen::Vector3d>& centres, double radius, int grid,
                      Eigen::Vector3d* moments);

// Builds the whole scanned shape from a closed convex polyhedron (any frame).
ScannedShape MakeScannedShape(const Polyhedron& hull, const ClumpOptions& options,
                              const std::string& name, const std::string& file);

// `hull` stretched along its principal axes so that its bounding box there
// is `sides` (L1 >= L2 >= L3 along x, y, z), then moved to its principal
// frame again.
Polyhedron StretchToSides(const Polyhedron& principal_hull, const Eigen::Vector3d& sides);

// `shape` scaled by `scale` in every length (its clump with it: the fit's
// relative errors do not change).
ScannedShape ScaleShape(const ScannedShape& shape, double scale);

// The rigid body of `shape` scaled by `scale` (lengths) with `mass` [kg]:
// elements from the clump, mass and inertia from the hull (its principal
// moments times mass / volume), frontal area a quarter of its surface.
RockBody ScannedBody(const ScannedShape& shape, double scale, double mass);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_CLUMP_H_
