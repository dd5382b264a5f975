#include "rockcal/sites/shape_file.h"

#include <libqhull_r/qhull_ra.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <tuple>

#include "rockcal/core/error.h"
#include "rockcal/sites/point_files.h"
#include "rockcal/sites/stl.h"
#include "rockcal/sites/text_reader.h"
#include "qhull_messages.h"

namespace rockcal::sites {
namespace {

bool EndsWithStl(const std::string& path) {
  if (path.size() < 4) return false;
  return Lower(path.substr(path.size() - 4)) == ".stl";
}

// The file's stem: "blocks/SP1A.xyz" -> "SP1A".
std::string Stem(const std::string& path) {
  const auto slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const auto dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

}  // namespace

std::vector<Eigen::Vector3d> ReadShapePoints(const std::string& path, double length_scale) {
  std::vector<Eigen::Vector3d> points;
  if (EndsWithStl(path)) {
    const std::vector<Triangle> triangles = ReadStl(path, StlAxes::kXYZ, length_scale);
    // Vertices merged where their coordinates are equal; each undirected
    // edge must border exactly two triangles.
    std::map<std::tuple<double, double, double>, int> index;
    auto id = [&](const Eigen::Vector3d& v) {
      const auto key = std::make_tuple(v.x(), v.y(), v.z());
      const auto it = index.find(key);
      if (it != index.end()) return it->second;
      const int k = static_cast<int>(points.size());
      index.emplace(key, k);
      points.push_back(v);
      return k;
    };
    std::map<std::pair<int, int>, int> edges;
    for (const Triangle& t : triangles) {
      const int a = id(t.a), b = id(t.b), c = id(t.c);
      for (auto [p, q] : {std::pair<int, int>{a, b}, {b, c}, {c, a}})
        ++edges[{std::min(p, q), std::max(p, q)}];
    }
    long open = 0;
    for (const auto& e : edges)
      if (e.second != 2) ++open;
    if (open > 0) {
      throw InputError(path, "not a closed surface: " + std::to_string(open) + " of " +
                                 std::to_string(edges.size()) +
                                 " edges do not border exactly two triangles (expected a "
                                 "closed STL surface, or a point cloud)");
    }
  } else {
    points = ReadPointsFile(path);
    for (auto& p : points) p *= length_scale;
  }
  if (points.size() < kMinShapePoints) {
    throw InputError(path, "too few points: " + std::to_string(points.size()) +
                               " (expected at least " + std::to_string(kMinShapePoints) +
                               " points of the block's surface)");
  }
  return points;
}

core::Polyhedron ConvexHull(const std::vector<Eigen::Vector3d>& points, const std::string& path) {
  const int n = static_cast<int>(points.size());
  if (n < 4) throw InputError(path, "too few points for a hull: " + std::to_string(n));
  std::vector<coordT> coords(3 * static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d)
      coords[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(d)] =
          points[static_cast<std::size_t>(k)][d];
  QhullMessages messages;
  qhT qh_qh;
  qhT* qh = &qh_qh;
  qh_zero(qh, messages.file());
  char options[] = "qhull Qt";
  const int status = qh_new_qhull(qh, 3, n, coords.data(), False, options, nullptr, messages.file());
  core::Polyhedron hull;
  if (status == 0) {
    std::map<int, int> used;  // Qhull point id -> hull vertex
    facetT* facet;
    vertexT* vertex;
    vertexT** vertexp;
    FORALLfacets {
      std::array<int, 3> f{-1, -1, -1};
      int k = 0;
      FOREACHvertex_(facet->vertices) {
        if (k < 3) {
          const int pid = qh_pointid(qh, vertex->point);
          auto it = used.find(pid);
          if (it == used.end()) {
            it = used.emplace(pid, static_cast<int>(hull.vertices.size())).first;
            hull.vertices.push_back(points[static_cast<std::size_t>(pid)]);
          }
          f[static_cast<std::size_t>(k)] = it->second;
        }
        ++k;
      }
      if (k != 3) continue;
      // Outward: the same side as Qhull's facet normal.
      const Eigen::Vector3d a = hull.vertices[static_cast<std::size_t>(f[0])];
      const Eigen::Vector3d nrm = (hull.vertices[static_cast<std::size_t>(f[1])] - a)
                                      .cross(hull.vertices[static_cast<std::size_t>(f[2])] - a);
      const Eigen::Vector3d qn(facet->normal[0], facet->normal[1], facet->normal[2]);
      if (nrm.dot(qn) < 0) std::swap(f[1], f[2]);
      hull.faces.push_back(f);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (status != 0 || hull.faces.size() < 4) {
    const std::string why = messages.FirstLine();
    throw InputError(path, "degenerate hull: the points lie on a plane or a line (Qhull: " +
                               (why.empty() ? std::string("no facets") : why.substr(0, 120)) +
                               "); expected points around a solid block");
  }
  // A hull far thinner than long is a flat scan, not a block.
  core::MassProperties m;
  const core::Polyhedron principal = core::ToPrincipalFrame(hull, &m);
  Eigen::Vector3d lo = principal.vertices[0], hi = lo;
  for (const auto& v : principal.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3d sides = hi - lo;
  if (!(m.volume > 0) || sides.minCoeff() < 1e-3 * sides.maxCoeff()) {
    throw InputError(path, "degenerate (flat) hull: sides " + std::to_string(sides.x()) + " x " +
                               std::to_string(sides.y()) + " x " + std::to_string(sides.z()) +
                               " m along its principal axes; expected the thinnest at least "
                               "1/1000 of the longest");
  }
  return hull;
}

std::shared_ptr<const core::ScannedShape> LoadScannedShape(const std::string& path,
                                                           double length_scale,
                                                           const core::ClumpOptions& options) {
  const core::Polyhedron hull = ConvexHull(ReadShapePoints(path, length_scale), path);
  return std::make_shared<const core::ScannedShape>(
      core::MakeScannedShape(hull, options, Stem(path), path));
}

std::shared_ptr<const core::ScannedShape> ShapeAtSides(const core::ScannedShape& shape,
                                                       const Eigen::Vector3d& sides,
                                                       const core::ClumpOptions& options) {
  return std::make_shared<const core::ScannedShape>(core::MakeScannedShape(
      core::StretchToSides(shape.hull, sides), options, shape.name, shape.file));
}

}  // namespace rockcal::sites
