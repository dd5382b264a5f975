#include "delaunay.h"
#include "qhull_messages.h"

#include <libqhull_r/qhull_ra.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <tuple>

namespace rockcal::sites {
namespace {

constexpr double kInsideSlack = 1e-10;  // of a barycentric coordinate

}  // namespace

bool Delaunay::Build(const std::vector<double>& u, const std::vector<double>& v,
                     std::string* error) {
  u_ = u;
  v_ = v;
  vertices_.clear();
  const int n = static_cast<int>(u.size());
  std::vector<coordT> points(2 * static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    points[2 * static_cast<std::size_t>(k)] = u[static_cast<std::size_t>(k)];
    points[2 * static_cast<std::size_t>(k) + 1] = v[static_cast<std::size_t>(k)];
  }
  QhullMessages messages;
  qhT qh_qh;
  qhT* qh = &qh_qh;
  qh_zero(qh, messages.file());
  char options[] = "qhull d Qbb Qc Qz Qt";
  const int status =
      qh_new_qhull(qh, 2, n, points.data(), False, options, nullptr, messages.file());
  if (status == 0) {
    facetT* facet;
    vertexT* vertex;
    vertexT** vertexp;
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      std::array<int, 3> t{-1, -1, -1};
      int k = 0;
      FOREACHvertex_(facet->vertices) {
        if (k < 3) t[static_cast<std::size_t>(k)] = qh_pointid(qh, vertex->point);
        ++k;
      }
      if (k == 3) vertices_.push_back(t);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (status != 0 || vertices_.empty()) {
    const std::string why = messages.FirstLine();
    *error = "Qhull: " + (why.empty() ? "no triangle" : why);
    vertices_.clear();
    return false;
  }

  // Counter-clockwise, with twice the area; then each edge's two triangles.
  area2_.resize(vertices_.size());
  struct Edge {
    std::uint64_t key;
    int f, k;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * vertices_.size());
  for (std::size_t f = 0; f < vertices_.size(); ++f) {
    std::array<int, 3>& t = vertices_[f];
    const double a2 = (u_[t[1]] - u_[t[0]]) * (v_[t[2]] - v_[t[0]]) -
                      (v_[t[1]] - v_[t[0]]) * (u_[t[2]] - u_[t[0]]);
    if (a2 < 0) std::swap(t[1], t[2]);
    area2_[f] = std::abs(a2);
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint64_t>(t[static_cast<std::size_t>((k + 1) % 3)]);
      const auto b = static_cast<std::uint64_t>(t[static_cast<std::size_t>((k + 2) % 3)]);
      edges.push_back({std::min(a, b) << 32 | std::max(a, b), static_cast<int>(f), k});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return std::tie(a.key, a.f, a.k) < std::tie(b.key, b.f, b.k);
  });
  neighbours_.assign(vertices_.size(), {-1, -1, -1});
  for (std::size_t e = 0; e + 1 < edges.size(); ++e) {
    if (edges[e].key != edges[e + 1].key) continue;
    neighbours_[static_cast<std::size_t>(edges[e].f)][static_cast<std::size_t>(edges[e].k)] =
        edges[e + 1].f;
    neighbours_[static_cast<std::size_t>(edges[e + 1].f)]
               [static_cast<std::size_t>(edges[e + 1].k)] = edges[e].f;
    ++e;
  }
  return true;
}

void Delaunay::Barycentric(int f, double x, double y, double l[3]) const {
  const std::array<int, 3>& t = vertices_[static_cast<std::size_t>(f)];
  const double x0 = u_[t[0]], y0 = v_[t[0]], x1 = u_[t[1]], y1 = v_[t[1]];
  const double x2 = u_[t[2]], y2 = v_[t[2]];
  const double det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2);
  l[0] = ((y1 - y2) * (x - x2) + (x2 - x1) * (y - y2)) / det;
  l[1] = ((y2 - y0) * (x - x2) + (x0 - x2) * (y - y2)) / det;
  l[2] = 1.0 - l[0] - l[1];
}

bool Delaunay::Locate(int start, double x, double y, int* found) const {
  const int count = size();
  int f = start >= 0 && start < count ? start : 0;
  int from = -1, hull = -1;
  // A walk in a Delaunay triangulation reaches the point (it never cycles);
  // the bound and the search after it are for rounding's sake.
  for (int step = 0; step < count && f >= 0; ++step) {
    int next = -1;
    if (!degenerate(f)) {
      double l[3];
      Barycentric(f, x, y, l);
      const int k = static_cast<int>(std::min_element(l, l + 3) - l);
      if (l[k] >= -kInsideSlack) {
        *found = f;
        return true;
      }
      next = neighbour(f, k);
      if (next < 0) {  // beyond a hull edge: outside the (convex) hull
        *found = f;
        return false;
      }
      hull = f;
    } else {
      // A sliver: on through an edge with the point beyond it, not back.
      const std::array<int, 3>& t = vertices_[static_cast<std::size_t>(f)];
      for (int k = 0; k < 3 && next < 0; ++k) {
        const int n = neighbour(f, k);
        const int a = t[static_cast<std::size_t>((k + 1) % 3)];
        const int b = t[static_cast<std::size_t>((k + 2) % 3)];
        const double side = (u_[b] - u_[a]) * (y - v_[a]) - (v_[b] - v_[a]) * (x - u_[a]);
        if (n >= 0 && n != from && side < 0) next = n;
      }
    }
    from = f;
    f = next;
  }
  for (int g = 0; g < count; ++g) {
    if (degenerate(g)) continue;
    double l[3];
    Barycentric(g, x, y, l);
    if (*std::min_element(l, l + 3) >= -kInsideSlack) {
      *found = g;
      return true;
    }
  }
  *found = hull;
  return false;
}

}  // namespace rockcal::sites
