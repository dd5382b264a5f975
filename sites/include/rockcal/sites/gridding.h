// Scattered points -> height grid: the one gridding rule every point source
// (inline points, points files, LIDAR) goes through.
#ifndef ROCKCAL_SITES_GRIDDING_H_
#define ROCKCAL_SITES_GRIDDING_H_

#include <Eigen/Core>
#include <vector>

#include "rockcal/core/terrain.h"

namespace rockcal::sites {

// Nodes needed along an axis of length `extent` at `spacing`:
// floor(extent / spacing + 1e-6) + 1 (the last node is at or just inside the
// end; the 1e-6 absorbs rounding so an extent of k spacings gives k + 1).
long NodeCount(double extent, double spacing);

// What GridPoints did, for the site notes.
struct GriddingReport {
  int from_cell = 0;          // nodes fitted from the points of their own cell
  int from_neighbours = 0;    // nodes fitted from points around them (filled)
  int cell_mean = 0;          // nodes given the plain mean of their own points
  int holes = 0;              // nodes with no data near enough (NaN)
  double data_spacing = 0.0;  // d = sqrt(bounding-box area / point count) [m]
  double hole_radius = 0.0;   // R = 2 max(spacing, d) [m]
};

// Grids scattered points (SI). The grid spans the plan bounding box of the
// points: origin (min x, min y), NodeCount() nodes per axis. Each point
// belongs to its nearest node (its "cell"). A node's elevation is, in order:
//  1. its own points spread over the cell (at least 3 points whose plan
//     standard deviation is >= spacing/10 in every direction) or surround
//     the node (they do not all lie in one open half-plane through the node,
//     or one is at the node; for a node on the edge of the grid the outside
//     of the grid counts as covered): the least-squares plane through them
//     evaluated at the node, i.e. their mean corrected to the node by their
//     slope;
//  2. else, if a point lies within R = 2 max(spacing, d) of the node and the
//     points within 2R surround it: the plane through those points, weighted
//     by 1 / (r^2 + (spacing/2)^2)^2 (r = distance to the node), evaluated at
//     the node -- interpolation only, never extrapolation past the data;
//  3. else, if it has own points: their mean elevation;
//  4. else a hole (NaN).
// A plane fit whose points are collinear keeps only the slope along the line.
// Planar data are reproduced exactly at every node that is not a hole.
// Material indices are all 0.
core::HeightGrid GridPoints(const std::vector<Eigen::Vector3d>& points, double spacing,
                            GriddingReport* report = nullptr);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_GRIDDING_H_
