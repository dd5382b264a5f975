// Onto a height grid: the one gridding rule every point source (inline
// points, points files, LIDAR) goes through (the points are triangulated,
// Delaunay, GDAL's, and each grid node takes the linear interpolation of the
// triangle it lies in), and the one bilinear resampling of nodes onto another
// spacing (rasters, and every terrain onto its virtual-sphere spacing).
#ifndef ROCKCAL_SITES_GRIDDING_H_
#define ROCKCAL_SITES_GRIDDING_H_

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "rockcal/core/terrain.h"

namespace rockcal::sites {

// Nodes needed along an axis of length `extent` at `spacing`:
// floor(extent / spacing + 1e-6) + 1 (the last node is at or just inside the
// end; the 1e-6 absorbs rounding so an extent of k spacings gives k + 1).
long NodeCount(double extent, double spacing);

struct GriddingOptions {
  double spacing = 1.0;  // grid spacing [m], > 0
  // A node in a triangle with an edge longer than this [m] is a hole: gaps
  // in the data wider than max_edge are not bridged. Default: no limit.
  double max_edge = std::numeric_limits<double>::infinity();

  // False, with *error naming the field, its value and the rule, unless
  // spacing > 0 and max_edge > 0 (both finite but max_edge, which may be inf).
  bool IsValid(std::string* error) const;
};

// What GridPoints did, for the site notes.
struct GriddingReport {
  int points = 0;        // points given
  int merged = 0;        // points dropped by averaging those at the same plan position
  int triangles = 0;     // triangles of the Delaunay triangulation
  int nodes = 0;         // nodes interpolated
  int outside_hull = 0;  // holes: nodes outside the convex hull of the points
  int long_edge = 0;     // holes: nodes in a triangle with an edge > max_edge
};

// Grids scattered points (SI). The grid spans the plan bounding box of the
// points: origin (min x, min y), NodeCount() nodes per axis. Points at the
// same plan position (x and y equal) become one point at their mean
// elevation. The rest are triangulated (Delaunay in plan, by Qhull as GDAL
// does it; GDAL itself is not loaded) and every node inside the convex hull
// takes the linear interpolation of the three corners of its triangle
// (nodes on an edge or a corner belong to either triangle: the values
// agree). Nodes outside the hull are holes (NaN), except that a node within
// 1e-6 spacings of it (the rounding slack of NodeCount) takes the
// triangle's plane; a node whose triangle has an edge longer than
// options.max_edge is a hole too (a node on an edge shared with a triangle
// without a long edge takes that one). Planar data are reproduced exactly
// (to rounding) at every node that is not a hole. Material indices are all 0.
// Returns false with *error saying what was expected when the options are
// not valid, or fewer than 3 distinct plan positions remain or all of them
// lie on one line.
bool GridPoints(const std::vector<Eigen::Vector3d>& points, const GriddingOptions& options,
                core::HeightGrid* grid, GriddingReport* report, std::string* error);

// Nodes `cell` [m] apart, `ncols` x `nrows` of them from (x0, y0), with
// elevation z_at(i, j) (NaN for a hole), onto `spacing` [m]. When spacing
// equals cell (to 1e-9 relative) the nodes are kept as they are; otherwise
// the new grid starts at the same node (x0, y0), covers the same extent
// (NodeCount nodes per axis) and each node takes the bilinear interpolation
// of the four surrounding nodes, a hole when any of them that has a positive
// weight is one. Material indices are all 0.
core::HeightGrid ResampleNodes(int ncols, int nrows, double cell, double x0, double y0,
                               const std::function<double(int, int)>& z_at, double spacing);

// `grid` onto `spacing` as ResampleNodes does; each new node takes the
// material of the nearest old node (halfway between two: the higher index).
core::HeightGrid ResampleGrid(const core::HeightGrid& grid, double spacing);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_GRIDDING_H_
