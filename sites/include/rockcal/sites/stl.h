// ASCII STL surfaces (a triangulated terrain, e.g. one file per material
// zone) and their exact sampling on a grid.
#ifndef ROCKCAL_SITES_STL_H_
#define ROCKCAL_SITES_STL_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "rockcal/core/terrain.h"

namespace rockcal::sites {

struct Triangle {
  Eigen::Vector3d a, b, c;
};

// How the file's axes map onto the site frame (Z up).
enum class StlAxes {
  kXYZ,  // the file is Z-up already
  kXZY,  // the file is Y-up: (x, y, z)_file -> (x, z, y)
};
// Parses "xyz" or "xzy"; false otherwise.
bool StringToStlAxes(const std::string& name, StlAxes* axes);

// Reads an ASCII STL ("solid ... facet normal ... outer loop vertex x y z
// (x3) endloop endfacet ... endsolid"), maps its axes and multiplies every
// coordinate by `length_scale`. Binary STL is rejected with a message saying
// so. Any other deviation is InputError "file:LINE: ...".
std::vector<Triangle> ReadStl(const std::string& path, StlAxes axes, double length_scale);

// A set of triangles with the material index its nodes take.
struct TriangleSet {
  std::vector<Triangle> triangles;
  int material = 0;
};

// Samples the triangulated surface exactly on a grid of `spacing` spanning
// the plan bounding box of every vertex (origin at the minimum x and y, node
// counts floor(extent / spacing) + 1). Each node takes the elevation of the
// triangle above it in plan (linear interpolation inside the triangle, edges
// included); where several cover it (vertical walls, overhangs, shared
// edges) the highest, and on a tie the first in set order. The node's
// material is that triangle's set's. Triangles with no plan area (vertical)
// cover nothing; nodes under no triangle are holes (NaN).
core::HeightGrid SampleTriangles(const std::vector<TriangleSet>& sets, double spacing);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_STL_H_
