// Scanned rock shapes from files: a point cloud (x y z text, as
// ReadPointsFile) or a closed ASCII STL surface, turned into its convex hull
// (Qhull) and a clump of equal spheres (core/clump.h). docs/rock-shapes.md.
#ifndef ROCKCAL_SITES_SHAPE_FILE_H_
#define ROCKCAL_SITES_SHAPE_FILE_H_

#include <memory>
#include <string>
#include <vector>

#include "rockcal/core/clump.h"

namespace rockcal::sites {

// The fewest points a shape file may hold (a hull needs 4; fewer than this
// cannot describe a block's shape).
inline constexpr std::size_t kMinShapePoints = 8;

// The points of a shape file in metres (`length_scale` per file unit): a
// file ending in ".stl" (any case) must be a closed surface (every edge
// shared by exactly two triangles; its vertices are the points); any other
// is a points file. Throws InputError naming the file: unreadable, too few
// points, an open surface (with the number of open edges).
std::vector<Eigen::Vector3d> ReadShapePoints(const std::string& path, double length_scale);

// The convex hull of `points` as a closed polyhedron with outward faces
// (Qhull "Qt": triangulated). Throws InputError(`path`, ...) when the hull
// is degenerate: all points on a plane or a line, or a hull thinner than a
// thousandth of its length.
core::Polyhedron ConvexHull(const std::vector<Eigen::Vector3d>& points, const std::string& path);

// Reads `path`, takes its hull and fits the clump: the shape in its
// principal frame at the file's scale.
std::shared_ptr<const core::ScannedShape> LoadScannedShape(const std::string& path,
                                                           double length_scale,
                                                           const core::ClumpOptions& options);

// `shape` stretched along its principal axes to the sides (L1, L2, L3) and
// its clump fitted again at that size.
std::shared_ptr<const core::ScannedShape> ShapeAtSides(const core::ScannedShape& shape,
                                                       const Eigen::Vector3d& sides,
                                                       const core::ClumpOptions& options);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SHAPE_FILE_H_
