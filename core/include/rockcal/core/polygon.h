// Plan polygons: the one point-in-polygon test of rockcal, used by the
// simulator (a release point in its zone) and by sites/ (material and release
// zones).
#ifndef ROCKCAL_CORE_POLYGON_H_
#define ROCKCAL_CORE_POLYGON_H_

#include <Eigen/Core>
#include <vector>

namespace rockcal::core {

// True when p is inside the polygon or on its boundary (within 1e-9 of the
// polygon's size). Even-odd rule, so a self-intersecting polygon keeps the
// parts covered an odd number of times. False for fewer than 3 vertices.
bool PointInPolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p);

// The disc of `radius` about `centre` as a plan polygon of kDiscVertices
// vertices on its circle, counter-clockwise from +x: a release point's
// position spread, released as a zone. radius > 0.
inline constexpr int kDiscVertices = 24;
std::vector<Eigen::Vector2d> DiscPolygon(const Eigen::Vector2d& centre, double radius);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_POLYGON_H_
