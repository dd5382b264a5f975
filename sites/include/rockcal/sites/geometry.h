// Plan geometry of sites: polygons (material and release zones) and where a
// plan point lies on a height grid.
#ifndef ROCKCAL_SITES_GEOMETRY_H_
#define ROCKCAL_SITES_GEOMETRY_H_

#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

#include "rockcal/core/polygon.h"
#include "rockcal/core/terrain.h"

namespace rockcal::sites {

using Polygon = std::vector<Eigen::Vector2d>;

// Signed area (positive counter-clockwise).
double SignedArea(const Polygon& polygon);

// The first pair of edges (i, j), i < j, edge k running from vertex k to
// vertex k + 1 (the last edge closes the ring; repeated vertices are dropped
// first), that cross or touch although
// they are not neighbours, or that overlap as neighbours; nullopt when the
// polygon is simple.
std::optional<std::pair<int, int>> FindSelfIntersection(const Polygon& polygon);

// True when p is inside the polygon or on its boundary (within 1e-9 of the
// polygon's size). Even-odd rule, so a self-intersecting polygon keeps the
// parts covered an odd number of times.
using core::PointInPolygon;

// True when (x, y) is on the slope: inside the grid and in a cell whose four
// corner nodes have elevations (no hole). The same rule as
// core::Terrain::OnSlope, so a release point accepted here can start a rock.
bool OnTerrain(const core::HeightGrid& grid, double x, double y);

// Elevation of the grid's triangulated surface at (x, y) (each cell split
// along the diagonal from (i, j) to (i+1, j+1)); nullopt off the terrain.
std::optional<double> ElevationAt(const core::HeightGrid& grid, double x, double y);

// Looks for a point of the polygon (boundary and interior, sampled every
// `step`) that is off the terrain; returns the first one found (vertices
// first), or nullopt when the whole polygon lies on the terrain.
std::optional<Eigen::Vector2d> FindOffTerrain(const core::HeightGrid& grid, const Polygon& polygon,
                                              double step);

// Number of grid nodes (holes included) inside the polygon.
int NodesInside(const core::HeightGrid& grid, const Polygon& polygon);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_GEOMETRY_H_
