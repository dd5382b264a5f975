// The scanned shapes section of report.html: each shape file's clump drawn
// over its hull in three orthographic views, with its sphere count and the
// union's volume, moment and side errors against the hull.
#include <algorithm>
#include <cmath>

#include "rockcal/core/clump.h"
#include "rockcal/reports/svg.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// The convex hull of 2-D points (Andrew's monotone chain), counter-clockwise.
std::vector<Eigen::Vector2d> Hull2d(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  std::size_t k = 0;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Three views (along z: x-y; along y: x-z; along x: y-z) of `s`, one scale.
std::string Drawing(const core::ScannedShape& s) {
  const double size = 110.0, pad = 8.0;
  const core::Clump& c = s.clump;
  double reach = 0.0;
  for (const auto& v : s.hull.vertices) reach = std::max(reach, v.cwiseAbs().maxCoeff());
  for (const auto& e : c.centres) reach = std::max(reach, e.cwiseAbs().maxCoeff() + c.radius);
  const double scale = (size / 2 - pad) / std::max(reach, 1e-12);
  const int axes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  const char* names[3] = {"top (x-y)", "side (x-z)", "end (y-z)"};
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + svg::Px(3 * size) +
                    "\" height=\"" + svg::Px(size + 14) + "\" viewBox=\"0 0 " + svg::Px(3 * size) +
                    " " + svg::Px(size + 14) + "\"><title>" + svg::Escape(s.name) +
                    ": clump over hull</title>";
  for (int v = 0; v < 3; ++v) {
    const double ox = v * size + size / 2, oy = size / 2;
    auto px = [&](double a) { return svg::Px(ox + scale * a); };
    auto py = [&](double b) { return svg::Px(oy - scale * b); };
    std::vector<Eigen::Vector2d> p;
    for (const auto& q : s.hull.vertices) p.emplace_back(q[axes[v][0]], q[axes[v][1]]);
    std::string path;
    for (const auto& q : Hull2d(p)) path += (path.empty() ? "M" : "L") + px(q.x()) + " " + py(q.y());
    out += "<path d=\"" + path + "Z\" fill=\"#ddd\" stroke=\"#555\" stroke-width=\"1\"/>";
    for (const auto& e : c.centres)
      out += "<circle cx=\"" + px(e[axes[v][0]]) + "\" cy=\"" + py(e[axes[v][1]]) + "\" r=\"" +
             svg::Px(scale * c.radius) + "\" fill=\"" + svg::Colour(0) +
             "\" fill-opacity=\"0.25\" stroke=\"" + svg::Colour(0) + "\" stroke-width=\"0.8\"/>";
    out += "<text x=\"" + svg::Px(ox) + "\" y=\"" + svg::Px(size + 10) +
           "\" font-size=\"10\" text-anchor=\"middle\">" + names[v] + "</text>";
  }
  return out + "</svg>";
}

}  // namespace

bool HasScannedShapes(const core::Scene& scene) { return !scene.ScannedShapes().empty(); }

std::string ScannedShapesSection(const Context& c) {
  const std::vector<core::ShapeUse> uses = c.scene.ScannedShapes();
  std::string s =
      "<p>Rocks of a scanned shape: the convex hull of the shape file (grey) gives the "
      "rock's mass and inertia; a clump of equal overlapping spheres (blue) is what touches "
      "the ground. Errors are the clump's union against the hull (worst over the blocks "
      "scaled to their sides; a group's rocks of one size range share one fit). See "
      "docs/rock-shapes.md.</p><table class=\"stats\"><thead><tr><th>shape</th><th>file</th>"
      "<th>blocks</th><th>spheres</th><th>hull volume</th><th>volume error</th>"
      "<th>moment error</th><th>side error</th><th>drawing</th></tr></thead><tbody>";
  for (const core::ShapeUse& u : uses) {
    s += "<tr><th>" + Escape(u.name) + "</th>" + Td(u.file) + Td(Int(u.uses), true) +
         Td(Int(u.spheres), true) +
         Td(Show(u.min_volume) + (u.max_volume > u.min_volume ? "-" + Show(u.max_volume) : "") +
                " m³",
            true) +
         Td(html::ShowPercent(u.volume_error), true) + Td(html::ShowPercent(u.moment_error), true) +
         Td(html::ShowPercent(u.side_error), true) + "<td>" + Drawing(*u.first) + "</td></tr>";
  }
  return s + "</tbody></table>";
}

}  // namespace rockcal::reports::sections
