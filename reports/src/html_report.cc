#include "rockcal/reports/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "rockcal/core/format.h"
#include "rockcal/core/material.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/statistics.h"
#include "rockcal/reports/html_page.h"
#include "rockcal/reports/reach_report.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/reports/svg.h"

namespace rockcal::reports {
namespace {

using core::FormatNumber;
using core::kFoot;

using svg::Escape;
using svg::Label;
using svg::Px;

using html::Exact;
using html::Figure;
using html::kFtTon;
using html::Kv;
using html::Length;
using html::Percent;
using html::Ref;
using html::RefCell;
using html::RefSpan;
using html::Show;
using html::Td;
using html::Th;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Passage density classes: share of the rocks whose centre passed over a cell.
constexpr double kDensityBreaks[] = {0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5};
constexpr const char* kDensityColours[] = {"#ffffb2", "#fed976", "#feb24c", "#fd8d3c",
                                           "#fc4e2a", "#e31a1c", "#b10026"};
constexpr int kDensityClasses = 7;
constexpr const char* kPartitionColour = "#6a3d9a";
constexpr const char* kReleaseColour = "#009E73";
constexpr const char* kStopColour = "#0072B2";
constexpr const char* kTimeoutColour = "#CC79A7";
constexpr const char* kFenceColour = "#d62728";

std::string Int(long v) { return std::to_string(v); }

const char* KindName(core::Partition::Kind kind) {
  return kind == core::Partition::Kind::kX ? "X" : "Z";
}

std::string PartitionWhere(const core::Partition& p) {
  if (p.kind == core::Partition::Kind::kX)
    return "X partition: the vertical plane x = " + Length(p.value);
  return "Z partition: where the ground is at elevation " + Length(p.value);
}

std::string Capitalised(std::string s) {
  if (!s.empty() && s[0] >= 'a' && s[0] <= 'z') s[0] = static_cast<char>(s[0] - 'a' + 'A');
  return s;
}

// ---------------------------------------------------------------------------

struct Context {
  const ReportInput& in;
  const core::Scene& scene;
  const core::SimulationResult& result;
  core::ResultStats stats;
  bool one_cell_wide = false;  // a 2D profile: no plan view
  bool several_shapes = false;
  int stopped = 0, left = 0, timeout = 0;
  double zmin = kInf, zmax = -kInf;  // terrain elevation range (valid nodes)
};

int Rocks(const Context& c) { return static_cast<int>(c.result.rocks.size()); }

// Bilinear ground elevation of the grid at (x, y); NaN over a hole or outside.
double GroundAt(const core::HeightGrid& g, double x, double y) {
  if (g.nx < 2 || g.ny < 2) return std::nan("");
  const double fx = (x - g.x0) / g.spacing, fy = (y - g.y0) / g.spacing;
  if (fx < 0 || fy < 0 || fx > g.nx - 1 || fy > g.ny - 1) return std::nan("");
  const int i = std::min(static_cast<int>(fx), g.nx - 2),
            j = std::min(static_cast<int>(fy), g.ny - 2);
  const double u = fx - i, v = fy - j;
  const double z00 = g.z[g.index(i, j)], z10 = g.z[g.index(i + 1, j)];
  const double z01 = g.z[g.index(i, j + 1)], z11 = g.z[g.index(i + 1, j + 1)];
  return (1 - u) * (1 - v) * z00 + u * (1 - v) * z10 + (1 - u) * v * z01 + u * v * z11;
}

// ---- plan view -------------------------------------------------------------

// A window of the grid: cells i0 <= i < i1, j0 <= j < j1 (nodes i0..i1, j0..j1).
struct View {
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
};

View WholeGrid(const core::HeightGrid& g) { return {0, g.nx - 1, 0, g.ny - 1}; }

struct Segment {
  double x0, y0, x1, y1;  // m
};

// Marching squares: the contour of the grid at `level` within `view`, as
// segments in metres.
std::vector<Segment> Contour(const core::HeightGrid& g, const View& view, double level) {
  std::vector<Segment> out;
  for (int j = view.j0; j < view.j1; ++j) {
    for (int i = view.i0; i < view.i1; ++i) {
      const double z[4] = {g.z[g.index(i, j)], g.z[g.index(i + 1, j)], g.z[g.index(i + 1, j + 1)],
                           g.z[g.index(i, j + 1)]};  // counter-clockwise from (i, j)
      if (!std::isfinite(z[0]) || !std::isfinite(z[1]) || !std::isfinite(z[2]) ||
          !std::isfinite(z[3]))
        continue;
      const double cx[4] = {g.x(i), g.x(i + 1), g.x(i + 1), g.x(i)};
      const double cy[4] = {g.y(j), g.y(j), g.y(j + 1), g.y(j + 1)};
      // Crossing points on the edges bottom (0-1), right (1-2), top (2-3), left (3-0).
      double px[4] = {0, 0, 0, 0}, py[4] = {0, 0, 0, 0};
      bool has[4];
      int n = 0;
      for (int e = 0; e < 4; ++e) {
        const int a = e, b = (e + 1) % 4;
        has[e] = (z[a] >= level) != (z[b] >= level);
        if (has[e]) {
          const double t = (level - z[a]) / (z[b] - z[a]);
          px[e] = cx[a] + t * (cx[b] - cx[a]);
          py[e] = cy[a] + t * (cy[b] - cy[a]);
          ++n;
        }
      }
      if (n == 2) {
        int e0 = -1, e1 = -1;
        for (int e = 0; e < 4; ++e)
          if (has[e]) (e0 < 0 ? e0 : e1) = e;
        out.push_back({px[e0], py[e0], px[e1], py[e1]});
      } else if (n == 4) {
        const double centre = 0.25 * (z[0] + z[1] + z[2] + z[3]);
        if ((z[0] >= level) == (centre >= level)) {  // corners 1 and 3 cut off
          out.push_back({px[0], py[0], px[1], py[1]});
          out.push_back({px[2], py[2], px[3], py[3]});
        } else {  // corners 0 and 2 cut off
          out.push_back({px[3], py[3], px[0], py[0]});
          out.push_back({px[1], py[1], px[2], py[2]});
        }
      }
    }
  }
  return out;
}

// The SVG path data of contour segments.
std::string SegmentsPath(const svg::Plot& plot, const std::vector<Segment>& segments) {
  std::string d;
  for (const Segment& s : segments)
    d += "M" + Px(plot.X(s.x0)) + " " + Px(plot.Y(s.y0)) + "L" + Px(plot.X(s.x1)) + " " +
         Px(plot.Y(s.y1));
  return d;
}

// Runs of equal class along each row, drawn as one rectangle each and grouped
// by class: class_of(i, j) for i0 <= i < i1, j0 <= j < j1, -1 for nothing;
// column i covers x in x_range(i), row j covers y in y_range(j).
template <typename ClassFn, typename XFn, typename YFn>
std::map<int, std::string> Runs(const svg::Plot& plot, int i0, int i1, int j0, int j1,
                                const ClassFn& class_of, const XFn& x_range, const YFn& y_range) {
  std::map<int, std::string> rects;
  for (int j = j0; j < j1; ++j) {
    double ylo, yhi;
    y_range(j, &ylo, &yhi);
    const std::string y = Px(plot.Y(yhi)), h = Px(plot.Y(ylo) - plot.Y(yhi));
    int i = i0;
    while (i < i1) {
      const int c = class_of(i, j);
      int k = i + 1;
      while (k < i1 && class_of(k, j) == c) ++k;
      if (c >= 0) {
        double xlo, xhi, unused;
        x_range(i, &xlo, &unused);
        x_range(k - 1, &unused, &xhi);
        rects[c] += "<rect x=\"" + Px(plot.X(xlo)) + "\" y=\"" + y + "\" width=\"" +
                    Px(plot.X(xhi) - plot.X(xlo)) + "\" height=\"" + h + "\"/>";
      }
      i = k;
    }
  }
  return rects;
}

std::string Swatch(const std::string& colour, const std::string& kind = "bar") {
  std::string s =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"18\" height=\"12\" viewBox=\"0 0 18 12\">";
  if (kind == "line")
    s +=
        "<line x1=\"1\" y1=\"6\" x2=\"17\" y2=\"6\" stroke=\"" + colour + "\" stroke-width=\"2\"/>";
  else if (kind == "dash")
    s += "<line x1=\"1\" y1=\"6\" x2=\"17\" y2=\"6\" stroke=\"" + colour +
         "\" stroke-width=\"2\" stroke-dasharray=\"4 2\"/>";
  else if (kind == "point")
    s += "<circle cx=\"9\" cy=\"6\" r=\"3\" fill=\"" + colour + "\"/>";
  else if (kind == "ring")
    s += "<circle cx=\"9\" cy=\"6\" r=\"4\" fill=\"none\" stroke=\"" + colour +
         "\" stroke-width=\"1.5\"/>";
  else if (kind == "cross")
    s += "<path d=\"M5 2L13 10M13 2L5 10\" stroke=\"" + colour + "\" stroke-width=\"1.5\"/>";
  else if (kind == "zone")
    s += "<rect x=\"1\" y=\"1\" width=\"16\" height=\"10\" fill=\"" + colour +
         "\" fill-opacity=\"0.3\" stroke=\"" + colour + "\" stroke-width=\"1.5\"/>";
  else
    s += "<rect x=\"1\" y=\"1\" width=\"16\" height=\"10\" fill=\"" + colour +
         "\" stroke=\"#999\" stroke-width=\"0.5\"/>";
  return s + "</svg>";
}

std::string LegendItem(const std::string& swatch, const std::string& label) {
  return "<li>" + swatch + " " + Escape(label) + "</li>";
}

// Pastel fill of material k on the zone map.
const char* MaterialFill(int k) {
  static const char* const kFills[] = {"#cfd8dc", "#f6d7a7", "#c8e6c9", "#d1c4e9",
                                       "#ffccbc", "#b3e5fc", "#f0f4c3", "#f8bbd0"};
  return kFills[k % 8];
}

// A plot of the plan within `view`, at equal scale in x and y.
svg::Plot PlanPlot(const Context& c, const View& view, double max_width, double max_height,
                   const std::string& title) {
  const core::HeightGrid& g = c.scene.grid;
  const double xlo = g.x(view.i0), xhi = g.x(view.i1), ylo = g.y(view.j0), yhi = g.y(view.j1);
  const double k = std::min(max_width / (xhi - xlo), max_height / (yhi - ylo));
  const bool us = c.in.units == sites::Units::kUS;
  svg::Plot::Options o;
  o.left = 58, o.bottom = 44, o.top = us ? 40 : 14, o.right = us ? 58 : 16;
  o.width = o.left + o.right + (xhi - xlo) * k;
  o.height = o.top + o.bottom + (yhi - ylo) * k;
  o.title = title;
  svg::Plot plot(xlo, xhi, ylo, yhi, o);
  plot.Axes("x [m]", "y [m]");
  if (us) {
    plot.TopAxis(1.0 / kFoot, "x [ft]");
    plot.RightAxis(1.0 / kFoot, "y [ft]");
  }
  return plot;
}

// Contour lines every `step` within `view`, labelled near the view's middle row.
std::string ContourLines(const Context& c, const View& view, const svg::Plot& plot, double step,
                         const char* colour) {
  const core::HeightGrid& g = c.scene.grid;
  std::string out = "<g fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"0.6\">";
  std::string labels = "<g class=\"halo small\" text-anchor=\"middle\">";
  const double ymid = 0.5 * (g.y(view.j0) + g.y(view.j1));
  std::vector<double> placed;  // label x positions, px
  for (double level = std::ceil(c.zmin / step) * step; level < c.zmax; level += step) {
    const std::vector<Segment> segs = Contour(g, view, level);
    if (segs.empty()) continue;
    out += "<path d=\"" + SegmentsPath(plot, segs) + "\"/>";
    const Segment* best = nullptr;
    double best_d = kInf;
    for (const Segment& s : segs) {
      const double d = std::fabs(0.5 * (s.y0 + s.y1) - ymid);
      if (d < best_d) best_d = d, best = &s;
    }
    const double lx = plot.X(0.5 * (best->x0 + best->x1)), ly = plot.Y(0.5 * (best->y0 + best->y1));
    bool crowded = false;
    for (double x : placed) crowded = crowded || std::fabs(lx - x) < 34.0;
    if (!crowded) {
      labels +=
          "<text x=\"" + Px(lx) + "\" y=\"" + Px(ly + 3) + "\">" + Escape(Label(level)) + "</text>";
      placed.push_back(lx);
    }
  }
  return out + "</g>" + labels + "</g>";
}

// Partitions (X lines, Z contours) with labels.
std::string PartitionMarks(const Context& c, const View& view, const svg::Plot& plot) {
  std::string out = "<g fill=\"none\" stroke=\"" + std::string(kPartitionColour) +
                    "\" stroke-width=\"2\" stroke-dasharray=\"7 4\">";
  std::string labels =
      "<g class=\"halo\" fill=\"" + std::string(kPartitionColour) + "\" font-weight=\"bold\">";
  for (const core::Partition& p : c.scene.partitions) {
    if (p.kind == core::Partition::Kind::kX) {
      if (p.value < plot.xlo() || p.value > plot.xhi()) continue;
      const std::string x = Px(plot.X(p.value));
      out += "<line x1=\"" + x + "\" y1=\"" + Px(plot.top()) + "\" x2=\"" + x + "\" y2=\"" +
             Px(plot.bottom()) + "\"/>";
      labels += "<text x=\"" + Px(plot.X(p.value) + 4) + "\" y=\"" + Px(plot.top() + 13) + "\">" +
                Escape(p.id) + "</text>";
    } else {
      const std::vector<Segment> segs = Contour(c.scene.grid, view, p.value);
      if (segs.empty()) continue;
      out += "<path d=\"" + SegmentsPath(plot, segs) + "\"/>";
      const Segment* top = &segs[0];
      for (const Segment& s : segs)
        if (std::max(s.y0, s.y1) > std::max(top->y0, top->y1)) top = &s;
      labels += "<text x=\"" + Px(plot.X(top->x0) + 4) + "\" y=\"" +
                Px(plot.Y(std::max(top->y0, top->y1)) + 13) + "\">" + Escape(p.id) + "</text>";
    }
  }
  return out + "</g>" + labels + "</g>";
}

// Release zones (polygons) and points (triangles), each drawn once.
std::string ReleaseMarks(const Context& c, const svg::Plot& plot) {
  std::string out = "<g fill=\"" + std::string(kReleaseColour) +
                    "\" fill-opacity=\"0.3\" stroke=\"" + kReleaseColour +
                    "\" stroke-width=\"1.5\">";
  std::set<std::string> drawn;
  for (const core::RockGroup& grp : c.scene.groups) {
    std::string shape;
    if (!grp.release.zone.empty()) {
      std::string pts;
      for (const Eigen::Vector2d& v : grp.release.zone)
        pts += (pts.empty() ? "" : " ") + Px(plot.X(v.x())) + "," + Px(plot.Y(v.y()));
      shape = "<polygon points=\"" + pts + "\"/>";
    } else {
      const double x = plot.X(grp.release.point.x()), y = plot.Y(grp.release.point.y());
      shape = "<path d=\"M" + Px(x) + " " + Px(y - 6) + "L" + Px(x + 5) + " " + Px(y + 3) + "L" +
              Px(x - 5) + " " + Px(y + 3) + "Z\" fill-opacity=\"0.8\"/>";
    }
    if (drawn.insert(shape).second) out += shape;
  }
  return out + "</g>";
}

// Grey elevation bands (cells) every `step`, from `lightest` (low) to
// `darkest` (high) grey level.
std::string ElevationBands(const Context& c, const View& view, const svg::Plot& plot, double step,
                           int lightest, int darkest) {
  const core::HeightGrid& g = c.scene.grid;
  const int bands = std::max(1, static_cast<int>(std::ceil((c.zmax - c.zmin) / step)));
  auto cls = [&](int i, int j) {
    const double z = 0.25 * (g.z[g.index(i, j)] + g.z[g.index(i + 1, j)] + g.z[g.index(i, j + 1)] +
                             g.z[g.index(i + 1, j + 1)]);
    if (!std::isfinite(z)) return -1;
    return std::clamp(static_cast<int>((z - c.zmin) / step), 0, bands - 1);
  };
  auto xr = [&](int i, double* lo, double* hi) { *lo = g.x(i), *hi = g.x(i + 1); };
  auto yr = [&](int j, double* lo, double* hi) { *lo = g.y(j), *hi = g.y(j + 1); };
  const auto runs = Runs(plot, view.i0, view.i1, view.j0, view.j1, cls, xr, yr);
  std::string out = "<g shape-rendering=\"crispEdges\">";
  for (const auto& [band, rects] : runs) {
    const int v = bands > 1 ? lightest + (darkest - lightest) * band / (bands - 1) : lightest;
    char colour[16];
    std::snprintf(colour, sizeof colour, "#%02x%02x%02x", v, v, v);
    out += "<g fill=\"" + std::string(colour) + "\">" + rects + "</g>";
  }
  return out + "</g>";
}

bool HasHoles(const core::HeightGrid& g) {
  for (double z : g.z)
    if (!std::isfinite(z)) return true;
  return false;
}

std::string PlanZones(const Context& c, double step, std::string* legend, double* width) {
  const core::HeightGrid& g = c.scene.grid;
  const View view = WholeGrid(g);
  svg::Plot plot = PlanPlot(
      c, view, 780.0, 620.0,
      "Plan of the slope: material zones, elevation contours, partitions and release zones");
  // Materials per node: the square of half a spacing around each node.
  auto cls = [&](int i, int j) {
    return std::isfinite(g.z[g.index(i, j)]) ? g.material[g.index(i, j)] : -1;
  };
  const double h = 0.5 * g.spacing;
  auto xr = [&](int i, double* lo, double* hi) {
    *lo = std::max(g.x(i) - h, plot.xlo()), *hi = std::min(g.x(i) + h, plot.xhi());
  };
  auto yr = [&](int j, double* lo, double* hi) {
    *lo = std::max(g.y(j) - h, plot.ylo()), *hi = std::min(g.y(j) + h, plot.yhi());
  };
  const auto runs = Runs(plot, 0, g.nx, 0, g.ny, cls, xr, yr);
  std::string m = "<g shape-rendering=\"crispEdges\">";
  for (const auto& [k, rects] : runs)
    m += "<g fill=\"" + std::string(MaterialFill(k)) + "\">" + rects + "</g>";
  plot.Raw(m + "</g>");
  plot.Raw(ContourLines(c, view, plot, step, "#555"));
  plot.Raw(ReleaseMarks(c, plot));
  plot.Raw(PartitionMarks(c, view, plot));
  *legend = "<ul class=\"legend\">";
  std::vector<int> used(c.scene.materials.size(), 0);
  for (std::size_t n = 0; n < g.z.size(); ++n)
    if (std::isfinite(g.z[n])) used[static_cast<std::size_t>(g.material[n])] = 1;
  for (std::size_t k = 0; k < c.scene.materials.size(); ++k)
    if (used[k])
      *legend += LegendItem(Swatch(MaterialFill(static_cast<int>(k))), c.scene.materials[k].id);
  if (HasHoles(g)) *legend += LegendItem(Swatch("#ffffff"), "no terrain data");
  *legend += LegendItem(Swatch("#555", "line"), "contour every " + Length(step));
  *legend += LegendItem(Swatch(kReleaseColour, "zone"), "release zone");
  if (!c.scene.partitions.empty())
    *legend += LegendItem(Swatch(kPartitionColour, "dash"), "partition");
  *legend += "</ul>";
  *width = plot.right() + (c.in.units == sites::Units::kUS ? 58 : 16);
  return plot.Svg();
}

// The part of the grid where rocks went: release zones, passages, stop
// points and observed stop points, with a margin; the whole grid when that
// is most of it.
View ActiveView(const Context& c) {
  const core::HeightGrid& g = c.scene.grid;
  double xlo = kInf, xhi = -kInf, ylo = kInf, yhi = -kInf;
  auto add = [&](double x, double y) {
    xlo = std::min(xlo, x), xhi = std::max(xhi, x), ylo = std::min(ylo, y), yhi = std::max(yhi, y);
  };
  for (const core::RockGroup& grp : c.scene.groups) {
    if (grp.release.zone.empty()) add(grp.release.point.x(), grp.release.point.y());
    for (const Eigen::Vector2d& v : grp.release.zone) add(v.x(), v.y());
  }
  for (const core::RockRecord& r : c.result.rocks) add(r.stop.x(), r.stop.y());
  if (c.in.observations && c.in.observations->runout)
    for (const Eigen::Vector2d& p : c.in.observations->runout->stop_points) add(p.x(), p.y());
  const std::vector<int>& pass = c.result.passages;
  if (pass.size() == static_cast<std::size_t>((g.nx - 1) * (g.ny - 1))) {
    for (int j = 0; j + 1 < g.ny; ++j)
      for (int i = 0; i + 1 < g.nx; ++i)
        if (pass[static_cast<std::size_t>(j * (g.nx - 1) + i)] > 0)
          add(g.x(i), g.y(j)), add(g.x(i + 1), g.y(j + 1));
  }
  const View whole = WholeGrid(g);
  if (!(xhi >= xlo) || !(yhi >= ylo)) return whole;
  const double margin = std::max(0.06 * std::max(xhi - xlo, yhi - ylo), 2.0 * g.spacing);
  View v;
  v.i0 = std::clamp(static_cast<int>(std::floor((xlo - margin - g.x0) / g.spacing)), 0, g.nx - 2);
  v.i1 = std::clamp(static_cast<int>(std::ceil((xhi + margin - g.x0) / g.spacing)), v.i0 + 1,
                    g.nx - 1);
  v.j0 = std::clamp(static_cast<int>(std::floor((ylo - margin - g.y0) / g.spacing)), 0, g.ny - 2);
  v.j1 = std::clamp(static_cast<int>(std::ceil((yhi + margin - g.y0) / g.spacing)), v.j0 + 1,
                    g.ny - 1);
  const double share = static_cast<double>(v.i1 - v.i0) * (v.j1 - v.j0) /
                       (static_cast<double>(g.nx - 1) * (g.ny - 1));
  return share > 0.7 ? whole : v;
}

std::string PlanPaths(const Context& c, double step, const View& view, std::string* legend,
                      int* drawn_stops, double* width) {
  const core::HeightGrid& g = c.scene.grid;
  svg::Plot plot = PlanPlot(
      c, view, 780.0, 620.0,
      "Plan of the rock paths: passage density, stop points, partitions and release zones");
  plot.Raw(ElevationBands(c, view, plot, step, 0xf4, 0xb8));
  const std::vector<int>& pass = c.result.passages;
  const int rocks = std::max(Rocks(c), 1);
  const bool have_passages = pass.size() == static_cast<std::size_t>((g.nx - 1) * (g.ny - 1));
  if (have_passages) {
    auto cls = [&](int i, int j) {
      const int n = pass[static_cast<std::size_t>(j * (g.nx - 1) + i)];
      if (n <= 0) return -1;
      const double share = static_cast<double>(n) / rocks;
      int k = 0;
      while (k + 1 < kDensityClasses && share >= kDensityBreaks[k + 1]) ++k;
      return k;
    };
    auto xr = [&](int i, double* lo, double* hi) { *lo = g.x(i), *hi = g.x(i + 1); };
    auto yr = [&](int j, double* lo, double* hi) { *lo = g.y(j), *hi = g.y(j + 1); };
    const auto runs = Runs(plot, view.i0, view.i1, view.j0, view.j1, cls, xr, yr);
    std::string d = "<g shape-rendering=\"crispEdges\" fill-opacity=\"0.85\">";
    for (const auto& [k, rects] : runs)
      d += "<g fill=\"" + std::string(kDensityColours[k]) + "\">" + rects + "</g>";
    plot.Raw(d + "</g>");
  }
  plot.Raw(ContourLines(c, view, plot, step, "#8a8a8a"));
  plot.Raw(ReleaseMarks(c, plot));
  plot.Raw(PartitionMarks(c, view, plot));
  // Stop points by outcome (at most max_stop_points, in rock order).
  std::string stops =
      "<g fill=\"" + std::string(kStopColour) + "\" stroke=\"#fff\" stroke-width=\"0.8\">";
  std::string timeouts =
      "<g fill=\"" + std::string(kTimeoutColour) + "\" stroke=\"#fff\" stroke-width=\"0.8\">";
  std::string lefts = "<g stroke=\"#333\" stroke-width=\"1.2\" fill=\"none\">";
  int n = 0;
  for (const core::RockRecord& r : c.result.rocks) {
    if (n >= c.in.options.max_stop_points) break;
    const double x = plot.X(std::clamp(r.stop.x(), plot.xlo(), plot.xhi()));
    const double y = plot.Y(std::clamp(r.stop.y(), plot.ylo(), plot.yhi()));
    ++n;
    if (r.outcome == core::Outcome::kLeft) {
      lefts += "<path d=\"M" + Px(x - 3) + " " + Px(y - 3) + "L" + Px(x + 3) + " " + Px(y + 3) +
               "M" + Px(x + 3) + " " + Px(y - 3) + "L" + Px(x - 3) + " " + Px(y + 3) + "\"/>";
    } else {
      (r.outcome == core::Outcome::kStopped ? stops : timeouts) +=
          "<circle cx=\"" + Px(x) + "\" cy=\"" + Px(y) + "\" r=\"3.2\"/>";
    }
  }
  *drawn_stops = n;
  plot.Raw(stops + "</g>" + timeouts + "</g>" + lefts + "</g>");
  const observations::Observations* obs = c.in.observations;
  const bool observed = obs && obs->runout && !obs->runout->stop_points.empty();
  if (observed) {
    std::string rings = "<g fill=\"none\" stroke=\"#000\" stroke-width=\"1.3\">";
    for (const Eigen::Vector2d& p : obs->runout->stop_points)
      rings +=
          "<circle cx=\"" + Px(plot.X(p.x())) + "\" cy=\"" + Px(plot.Y(p.y())) + "\" r=\"4\"/>";
    plot.Raw(rings + "</g>");
  }
  *legend = "<ul class=\"legend\">";
  if (have_passages) {
    for (int k = 0; k < kDensityClasses; ++k) {
      const std::string range = k + 1 < kDensityClasses
                                    ? (k == 0 ? "under " + Label(100 * kDensityBreaks[1]) + " %"
                                              : Label(100 * kDensityBreaks[k]) + "-" +
                                                    Label(100 * kDensityBreaks[k + 1]) + " %")
                                    : Label(100 * kDensityBreaks[k]) + " % or more";
      *legend += LegendItem(Swatch(kDensityColours[k]), range);
    }
  }
  *legend += LegendItem(Swatch(kStopColour, "point"), "stopped rock");
  if (c.timeout > 0)
    *legend += LegendItem(Swatch(kTimeoutColour, "point"), "rock still moving at the time limit");
  if (c.left > 0) *legend += LegendItem(Swatch("#333", "cross"), "rock left the slope here");
  if (observed) *legend += LegendItem(Swatch("#000", "ring"), "observed stop point");
  *legend += LegendItem(Swatch(kReleaseColour, "zone"), "release zone");
  if (!c.scene.partitions.empty())
    *legend += LegendItem(Swatch(kPartitionColour, "dash"), "partition");
  *legend += "</ul>";
  *width = plot.right() + (c.in.units == sites::Units::kUS ? 58 : 16);
  return plot.Svg();
}

std::string PlanSection(const Context& c) {
  const core::HeightGrid& g = c.scene.grid;
  const double step = svg::NiceStep(c.zmax - c.zmin, 12);
  const View view = ActiveView(c);
  const bool zoomed = view.i0 != 0 || view.j0 != 0 || view.i1 != g.nx - 1 || view.j1 != g.ny - 1;
  std::string zones_legend, paths_legend;
  int drawn = 0;
  double zones_width = 0, paths_width = 0;
  const std::string zones = PlanZones(c, step, &zones_legend, &zones_width);
  const std::string paths = PlanPaths(c, step, view, &paths_legend, &drawn, &paths_width);
  std::string s =
      "<p>x and y in metres" +
      std::string(c.in.units == sites::Units::kUS ? " (feet on the top and right axes)" : "") +
      "; contour labels are elevations in metres.</p><div class=\"figs\">";
  s += Figure(zones,
              "<b>Slope and zones.</b> Material zones (each grid node coloured by its material), "
              "elevation contours "
              "every " +
                  Escape(Length(step)) + ", release zones and partitions." + zones_legend,
              zones_width);
  std::string cap = "<b>Rock paths.</b> Passage density: the share of the " + Int(Rocks(c)) +
                    " rocks whose centre passed over each grid cell (the preferred paths)";
  if (c.result.passages.empty()) cap += " was not recorded for this run";
  cap += "; where each rock ended";
  if (drawn < Rocks(c)) cap += " (the first " + Int(drawn) + " rocks)";
  cap += ". Grey shading: elevation bands every " + Escape(Length(step)) + ", darker is higher.";
  if (zoomed) cap += " Zoomed to where the rocks went.";
  s += Figure(paths, cap + paths_legend, paths_width);
  return s + "</div>";
}

// ---- profile view ----------------------------------------------------------

std::string ProfileSection(const Context& c) {
  const core::HeightGrid& g = c.scene.grid;
  const double xlo = g.x0, xhi = g.x(g.nx - 1);
  const double yc = c.scene.groups.empty()
                        ? 0.5 * (g.y0 + g.y(g.ny - 1))
                        : observations::ReleaseCentroid(c.scene.groups[0].release).y();
  // Ground along y = yc and the range of ground elevation across the slope per column.
  std::vector<double> xs, line, lo, hi;
  for (int i = 0; i < g.nx; ++i) {
    double a = kInf, b = -kInf;
    for (int j = 0; j < g.ny; ++j) {
      const double z = g.z[g.index(i, j)];
      if (std::isfinite(z)) a = std::min(a, z), b = std::max(b, z);
    }
    xs.push_back(g.x(i));
    line.push_back(GroundAt(g, g.x(i), std::clamp(yc, g.y0, g.y(g.ny - 1))));
    lo.push_back(std::isfinite(a) ? a : std::nan(""));
    hi.push_back(std::isfinite(b) ? b : std::nan(""));
  }
  // Trajectories to draw.
  std::vector<const core::RockRecord*> paths;
  for (const core::RockRecord& r : c.result.rocks)
    if (!r.trajectory.empty() && static_cast<int>(paths.size()) < c.in.options.max_trajectories)
      paths.push_back(&r);
  double zlo = c.zmin, zhi = c.zmax;
  for (const auto* r : paths)
    for (const auto& s : r->trajectory) zlo = std::min(zlo, s.x.z()), zhi = std::max(zhi, s.x.z());
  const double pad = 0.04 * (zhi - zlo);
  zlo -= pad, zhi += pad;
  // Scale: true scale when it fits; otherwise exaggerate the vertical.
  const double xext = xhi - xlo, zext = zhi - zlo;
  double kx = 780.0 / xext, kz = kx;
  if (zext * kz > 440.0) kx = kz = 440.0 / zext;
  double exaggeration = 1.0;
  if (zext * kz < 180.0) {
    exaggeration = 180.0 / (zext * kz);
    kz *= exaggeration;
  }
  svg::Plot::Options o;
  const bool us = c.in.units == sites::Units::kUS;
  o.left = 58, o.bottom = 44, o.top = us ? 40 : 14, o.right = us ? 58 : 16;
  o.width = o.left + o.right + xext * kx;
  o.height = o.top + o.bottom + zext * kz;
  o.title = "Profile: ground elevation against x with sampled rock trajectories";
  svg::Plot plot(xlo, xhi, zlo, zhi, o);
  plot.Axes("x [m]", "elevation [m]");
  if (us) {
    plot.TopAxis(1.0 / kFoot, "x [ft]");
    plot.RightAxis(1.0 / kFoot, "elevation [ft]");
  }
  const bool is3d = !c.one_cell_wide;
  if (is3d) {
    std::string pts;
    for (std::size_t k = 0; k < xs.size(); ++k)
      if (std::isfinite(hi[k]))
        pts += (pts.empty() ? "" : " ") + Px(plot.X(xs[k])) + "," + Px(plot.Y(hi[k]));
    for (std::size_t k = xs.size(); k-- > 0;)
      if (std::isfinite(lo[k])) pts += " " + Px(plot.X(xs[k])) + "," + Px(plot.Y(lo[k]));
    plot.Raw("<polygon fill=\"#e3e3e3\" stroke=\"none\" points=\"" + pts + "\"/>");
  }
  plot.Polyline(xs, line, "stroke=\"#444\" stroke-width=\"1.8\"");
  for (const core::Partition& p : c.scene.partitions) {
    if (p.kind == core::Partition::Kind::kX)
      plot.VLine(p.value,
                 "stroke=\"" + std::string(kPartitionColour) +
                     "\" stroke-width=\"1.5\" stroke-dasharray=\"7 4\"",
                 p.id);
    else
      plot.HLine(p.value,
                 "stroke=\"" + std::string(kPartitionColour) +
                     "\" stroke-width=\"1.5\" stroke-dasharray=\"7 4\"",
                 p.id + " (z = " + Label(p.value) + " m)");
  }
  std::set<int> groups_drawn;
  for (const auto* r : paths) {
    std::vector<double> px, pz;
    for (const auto& s : r->trajectory) px.push_back(s.x.x()), pz.push_back(s.x.z());
    plot.Polyline(px, pz,
                  "stroke=\"" + std::string(svg::Colour(r->group)) +
                      "\" stroke-width=\"1\" stroke-opacity=\"0.75\"");
    groups_drawn.insert(r->group);
  }
  // Where the rocks ended (all of them, up to the cap).
  std::vector<double> sx, sz;
  for (const core::RockRecord& r : c.result.rocks) {
    if (static_cast<int>(sx.size()) >= c.in.options.max_stop_points) break;
    if (r.outcome != core::Outcome::kStopped) continue;
    sx.push_back(r.stop.x()), sz.push_back(r.stop.z());
  }
  plot.Points(sx, sz, 2.0, "fill=\"" + std::string(kStopColour) + "\" fill-opacity=\"0.6\"");
  std::vector<svg::Plot::LegendEntry> legend;
  legend.push_back({"#444", is3d ? "ground at y = " + Label(yc) + " m" : "ground", "line"});
  if (is3d) legend.push_back({"#d0d0d0", "ground range across the slope", "bar"});
  for (int grp : groups_drawn)
    legend.push_back({svg::Colour(grp),
                      "group " + std::to_string(grp + 1) + " (" +
                          core::ShapeName(c.scene.groups[static_cast<std::size_t>(grp)].shape) +
                          ") trajectory",
                      "line"});
  if (!sx.empty()) legend.push_back({kStopColour, "stop point", "point"});
  // Put the legend where the ground is low (the downslope side if it falls with x).
  const bool falls = line.front() > line.back() || !std::isfinite(line.back());
  plot.Legend(legend, falls);
  std::string cap = "<b>Profile.</b> Rock centre elevation against x";
  if (paths.empty())
    cap += "; no trajectories were recorded for this run";
  else
    cap += " for " + Int(static_cast<long>(paths.size())) +
           " sampled rocks (the first rocks of the run), sampled every " +
           Escape(Label(c.scene.options.record.sample_seconds)) + " s";
  cap += ", and the stop points of all stopped rocks.";
  if (is3d)
    cap += " The dark line is the ground along y = " + Escape(Length(yc)) +
           " (through the centre of the first release zone); rocks away from that line travel over "
           "other "
           "ground, whose range across the slope is shaded.";
  cap += exaggeration > 1.05
             ? " Vertical exaggeration " + Escape(FormatNumber(exaggeration, "%.1f")) + "x."
             : " True scale (no vertical exaggeration).";
  return Figure(plot.Svg(), cap, o.width);
}

// ---- histograms --------------------------------------------------------------

// A histogram of `values` (display units); `top_scale` converts to the
// secondary units on top; a dashed line marks `mark` when finite.
std::string Histogram(const std::vector<double>& values, const std::string& x_label,
                      double top_scale, const std::string& top_label, double mark,
                      const std::string& mark_label, const std::string& title,
                      double xmin_hint = 0.0) {
  if (values.empty()) return "";
  double lo = std::min(xmin_hint, *std::min_element(values.begin(), values.end()));
  double hi = *std::max_element(values.begin(), values.end());
  if (std::isfinite(mark) && mark > hi && mark < 2.0 * hi + 1e-12) hi = mark;
  if (!(hi > lo)) hi = lo + (lo != 0 ? std::fabs(lo) * 0.1 : 1.0);
  const int bins = std::clamp(
      static_cast<int>(std::ceil(std::sqrt(static_cast<double>(values.size())) * 1.5)), 6, 24);
  const double step = svg::NiceStep(hi - lo, bins);
  const double start = std::floor(lo / step) * step;
  int n = static_cast<int>(std::ceil((hi - start) / step - 1e-9));
  n = std::max(n, 1);
  if (start + n * step <= hi) ++n;
  std::vector<double> edges, counts(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k <= n; ++k) edges.push_back(start + k * step);
  for (double v : values) {
    const int k = std::clamp(static_cast<int>(std::floor((v - start) / step)), 0, n - 1);
    counts[static_cast<std::size_t>(k)] += 1.0;
  }
  const double cmax = *std::max_element(counts.begin(), counts.end());
  svg::Plot::Options o;
  o.width = 300, o.height = 220, o.left = 48, o.right = 12, o.top = 40, o.bottom = 42;
  o.title = title;
  svg::Plot plot(edges.front(), edges.back(), 0.0, cmax * 1.12, o);
  plot.Axes(x_label, "rocks");
  plot.TopAxis(top_scale, top_label);
  plot.Bars(edges, counts, "#6b8fb3");
  if (std::isfinite(mark) && mark <= edges.back()) {
    plot.VLine(mark,
               "stroke=\"" + std::string(kFenceColour) +
                   "\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"",
               mark_label);
  } else if (std::isfinite(mark)) {
    plot.Text(plot.right() - 4, plot.top() + 12, mark_label + " beyond the axis \u2192",
              "text-anchor=\"end\" fill=\"" + std::string(kFenceColour) + "\" class=\"halo\"");
  }
  return plot.Svg();
}

// ---- sections ----------------------------------------------------------------

std::string SiteSection(const Context& c) {
  html::PartitionPassage passage;
  for (const auto& ps : c.stats.partitions) passage.passed.push_back(ps.passed);
  passage.rocks = Rocks(c);
  std::string s = html::SiteTables(c.scene, c.in.site_file, c.in.units, &passage);

  // The run.
  const core::SimulationOptions& opt = c.scene.options;
  const core::SimulationResult& r = c.result;
  s += "<h3>Simulation</h3><table class=\"kv\">";
  s += Kv("Random seed", RefSpan(Ref("summary.json", "/seed"), static_cast<double>(opt.seed),
                                 std::to_string(opt.seed)));
  s += Kv("Rocks",
          RefSpan(Ref("summary.json", "/rocks"), Rocks(c), Int(Rocks(c))) + ": " +
              RefSpan(Ref("summary.json", "/outcomes/stopped"), c.stopped, Int(c.stopped)) +
              " stopped, " + RefSpan(Ref("summary.json", "/outcomes/left"), c.left, Int(c.left)) +
              " left the slope, " +
              RefSpan(Ref("summary.json", "/outcomes/timeout"), c.timeout, Int(c.timeout)) +
              " still moving at the time limit");
  s += Kv("Stopping rule",
          Escape("speed below " + Label(opt.stop_speed) + " m/s for " + Label(opt.stop_duration) +
                 " s; time limit " + Label(opt.max_time) + " s per rock"));
  s += Kv("Contact time step",
          RefSpan(Ref("summary.json", "/dt_seconds"), r.dt_min, Label(r.dt_min, 3)) +
              (r.dt_max > r.dt_min ? " to " + Escape(Label(r.dt_max, 3)) : std::string()) +
              " s (at most t_c/" + Int(opt.steps_per_contact) + ", " + Escape(Label(opt.safety)) +
              " of the critical step); free flight advanced exactly");
  s += Kv("Work",
          RefSpan(Ref("summary.json", "/steps"), static_cast<double>(r.steps), Int(r.steps)) +
              " contact steps and " + Escape(Int(r.flights)) + " free flights");
  s += Kv(
      "Wall time",
      RefSpan(Ref("summary.json", "/wall_seconds"), r.wall_seconds, Show(r.wall_seconds)) + " s");
  s += Kv("Energy check",
          "largest rise of mechanical energy " +
              RefSpan(Ref("summary.json", "/energy_check/max_relative_gain"),
                      r.max_relative_energy_gain, Label(r.max_relative_energy_gain, 3)) +
              " of the rock's largest kinetic energy (see the diagnostics)");
  s += "</table>";
  s += html::SiteNotes(c.in.notes);
  return s;
}

std::string StatsRow(const std::string& name, const std::string& key, int p,
                     const core::PartitionStats& ps) {
  auto pick = [&](const core::Stats& st) {
    if (key == "mean") return st.mean;
    if (key == "p50") return st.p50;
    if (key == "p90") return st.p90;
    if (key == "p95") return st.p95;
    return st.max;
  };
  const std::string base = "/partitions/" + Int(p) + "/";
  const double h = pick(ps.height), v = pick(ps.velocity), e = pick(ps.energy) * 1e-3;
  return "<tr><th>" + Escape(name) + "</th>" +
         RefCell(Ref("summary.json", base + "height_m/" + key), h, Show(h)) +
         Td(Show(h / kFoot), true) +
         RefCell(Ref("summary.json", base + "velocity_mps/" + key), v, Show(v)) +
         Td(Show(v / kFoot), true) +
         RefCell(Ref("summary.json", base + "energy_kj/" + key), e, Show(e)) +
         Td(Show(e * 1e3 / kFtTon), true) + "</tr>";
}

std::string PartitionSection(const Context& c, int p) {
  const core::Partition& part = c.scene.partitions[static_cast<std::size_t>(p)];
  const core::PartitionStats& ps = c.stats.partitions[static_cast<std::size_t>(p)];
  std::string s =
      "<p>" + Escape(Capitalised(PartitionWhere(part))) + ". " +
      RefSpan(Ref("summary.json", "/partitions/" + Int(p) + "/passed"), ps.passed, Int(ps.passed)) +
      " of " + Int(Rocks(c)) + " released rocks passed it (" +
      Percent(Rocks(c) ? static_cast<double>(ps.passed) / Rocks(c) : 0.0) +
      "). Values when a rock's centre first crossed it: bounce height (rock centre above the "
      "ground "
      "below it), translational speed and kinetic energy (translational plus rotational).</p>";
  s += "<table class=\"stats\"><thead><tr><th rowspan=\"2\"></th><th colspan=\"2\">bounce "
       "height</th>"
       "<th colspan=\"2\">speed</th><th colspan=\"2\">kinetic energy</th></tr><tr>" +
       Th("m") + Th("ft") + Th("m/s") + Th("ft/s") + Th("kJ") + Th("ft-tons") +
       "</tr></thead><tbody>";
  s += StatsRow("mean", "mean", p, ps) + StatsRow("median (p50)", "p50", p, ps) +
       StatsRow("90th percentile", "p90", p, ps) + StatsRow("95th percentile", "p95", p, ps) +
       StatsRow("maximum", "max", p, ps);
  s += "</tbody></table>";
  if (ps.passed == 0) return s + "<p>No rock crossed this partition: no histograms.</p>";
  std::vector<double> h, v, e;
  for (const core::RockRecord& r : c.result.rocks) {
    if (static_cast<std::size_t>(p) < r.crossings.size() &&
        r.crossings[static_cast<std::size_t>(p)].crossed) {
      const core::Crossing& cr = r.crossings[static_cast<std::size_t>(p)];
      h.push_back(cr.height), v.push_back(cr.speed), e.push_back(cr.energy * 1e-3);
    }
  }
  const double fh = c.in.options.barrier_height_m, fe = c.in.options.barrier_energy_j * 1e-3;
  s += "<div class=\"figs\">";
  const std::string n = Int(ps.passed) + " rocks at " + Escape(part.id);
  s += Figure(Histogram(h, "bounce height [m]", 1.0 / kFoot, "bounce height [ft]", fh,
                        "fence " + Label(fh, 3) + " m", "Histogram of bounce height at " + part.id,
                        std::min(0.0, *std::min_element(h.begin(), h.end()))),
              "<b>Bounce height</b>, " + n + "; dashed: the fence height.", 300);
  s += Figure(Histogram(v, "speed [m/s]", 1.0 / kFoot, "speed [ft/s]", std::nan(""), "",
                        "Histogram of speed at " + part.id),
              "<b>Speed</b>, " + n + ".", 300);
  s += Figure(
      Histogram(e, "kinetic energy [kJ]", 1e3 / kFtTon, "kinetic energy [ft-tons]", fe,
                "fence " + Label(fe, 3) + " kJ", "Histogram of kinetic energy at " + part.id),
      "<b>Kinetic energy</b>, " + n + "; dashed: the fence capacity.", 300);
  s += "</div>";
  return s;
}

std::string BarrierSection(const Context& c) {
  const double fh = c.in.options.barrier_height_m, fe = c.in.options.barrier_energy_j;
  std::string s =
      "<p>A fence <b>" + Escape(Length(fh)) + "</b> high with a capacity of <b>" +
      Escape(Show(fe * 1e-3)) + " kJ (" + Escape(Show(fe / kFtTon)) +
      " ft-tons)</b>, checked at each partition: the share of the passing rocks that would fly "
      "over it "
      "(bounce height above the fence) or break through it (kinetic energy above the capacity). "
      "Bounce height is that of the rock centre; add half the rock size for its top. The 95th "
      "percentiles are the usual design values.</p>";
  s += "<table><thead><tr>" + Th("partition") + Th("passed") + Th("height above fence") +
       Th("energy above capacity") + Th("either (fence defeated)") + Th("of all released rocks") +
       Th("p95 bounce height") + Th("p95 energy") + "</tr></thead><tbody>";
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    const core::PartitionStats& ps = c.stats.partitions[p];
    int over_h = 0, over_e = 0, either = 0;
    for (const core::RockRecord& r : c.result.rocks) {
      if (p >= r.crossings.size() || !r.crossings[p].crossed) continue;
      const bool a = r.crossings[p].height > fh, b = r.crossings[p].energy > fe;
      over_h += a, over_e += b, either += (a || b);
    }
    auto share = [&](int n) {
      return ps.passed ? Int(n) + " (" + Percent(static_cast<double>(n) / ps.passed) + ")"
                       : std::string("-");
    };
    s += "<tr><td><a href=\"#" + Escape(PartitionSectionId(c.scene.partitions[p].id)) + "\">" +
         Escape(c.scene.partitions[p].id) + "</a></td>" + Td(Int(ps.passed), true) +
         Td(share(over_h), true) + Td(share(over_e), true) + Td(share(either), true) +
         Td(Percent(Rocks(c) ? static_cast<double>(either) / Rocks(c) : 0.0), true) +
         Td(ps.passed ? Length(ps.height.p95) : "-", true) +
         Td(ps.passed
                ? Show(ps.energy.p95 * 1e-3) + " kJ (" + Show(ps.energy.p95 / kFtTon) + " ft-tons)"
                : "-",
            true) +
         "</tr>";
  }
  return s + "</tbody></table>";
}

// Where a rock that left the slope crossed out: the nearest grid edge, or a hole.
std::string ExitEdge(const core::HeightGrid& g, const Eigen::Vector3d& p) {
  const double s = g.spacing;
  const double d[4] = {p.x() - g.x0, g.x(g.nx - 1) - p.x(), p.y() - g.y0, g.y(g.ny - 1) - p.y()};
  const char* names[4] = {"the x-min edge", "the x-max edge", "the y-min edge", "the y-max edge"};
  int k = static_cast<int>(std::min_element(d, d + 4) - d);
  if (d[k] > s) return "a hole in the terrain data";
  return names[k];
}

std::string RunoutSection(const Context& c) {
  const core::Stats& rx = c.stats.runout_x;
  std::vector<double> xs, ys;
  for (const core::RockRecord& r : c.result.rocks)
    if (r.outcome == core::Outcome::kStopped) xs.push_back(r.stop.x()), ys.push_back(r.stop.y());
  std::string s = "<p>" + Int(c.stopped) + " of " + Int(Rocks(c)) + " rocks stopped on the slope";
  if (c.left > 0) {
    std::map<std::string, int> edges;
    for (const core::RockRecord& r : c.result.rocks)
      if (r.outcome == core::Outcome::kLeft) ++edges[ExitEdge(c.scene.grid, r.stop)];
    s += "; " + Int(c.left) + " left it (";
    bool first = true;
    for (const auto& [edge, n] : edges)
      s += (first ? "" : ", ") + Int(n) + " over " + edge, first = false;
    s += ")";
  }
  if (c.timeout > 0) s += "; " + Int(c.timeout) + " were still moving at the time limit";
  s += ". Stop positions of the stopped rocks:</p>";
  const core::Stats ry = core::Summarize(ys);
  s += "<table class=\"stats\"><thead><tr><th></th><th colspan=\"2\">stop x</th>";
  const bool lateral = !c.one_cell_wide;
  if (lateral) s += "<th colspan=\"2\">stop y</th>";
  s += "</tr><tr><th></th>" + Th("m") + Th("ft") + (lateral ? Th("m") + Th("ft") : std::string()) +
       "</tr></thead><tbody>";
  const std::vector<double> sorted_y = [&] {
    auto v = ys;
    std::sort(v.begin(), v.end());
    return v;
  }();
  const std::vector<double> sorted_x = [&] {
    auto v = xs;
    std::sort(v.begin(), v.end());
    return v;
  }();
  struct Row {
    const char* name;
    const char* key;
    double x, y;
  };
  const Row rows[] = {
      {"minimum", nullptr, sorted_x.front(), sorted_y.front()},
      {"10th percentile", nullptr, core::Quantile(sorted_x, 0.1), core::Quantile(sorted_y, 0.1)},
      {"mean", "mean", rx.mean, ry.mean},
      {"median (p50)", "p50", rx.p50, ry.p50},
      {"90th percentile", "p90", rx.p90, ry.p90},
      {"95th percentile", "p95", rx.p95, ry.p95},
      {"maximum", "max", rx.max, ry.max}};
  for (const Row& row : rows) {
    s += "<tr><th>" + std::string(row.name) + "</th>" +
         (row.key ? RefCell(Ref("summary.json", std::string("/runout/x_m/") + row.key), row.x,
                            Show(row.x))
                  : Td(Show(row.x), true)) +
         Td(Show(row.x / kFoot), true);
    if (lateral) s += Td(Show(row.y), true) + Td(Show(row.y / kFoot), true);
    s += "</tr>";
  }
  s += "</tbody></table>";
  // Histogram and exceedance curve of stop x.
  s += "<div class=\"figs\">";
  s += Figure(Histogram(xs, "stop x [m]", 1.0 / kFoot, "stop x [ft]", std::nan(""), "",
                        "Histogram of stop x", sorted_x.front()),
              "<b>Stop x</b> of the " + Int(c.stopped) + " stopped rocks.", 300);
  svg::Plot::Options o;
  o.width = 380, o.height = 220, o.left = 48, o.right = 12, o.top = 40, o.bottom = 42;
  o.title = "Share of the released rocks that stopped beyond x";
  svg::Plot plot(sorted_x.front(), sorted_x.back(), 0.0, 100.0, o);
  plot.Axes("x [m]", "rocks beyond x [%]");
  plot.TopAxis(1.0 / kFoot, "x [ft]");
  std::vector<double> px, py;
  const double n = Rocks(c);
  for (std::size_t k = 0; k < sorted_x.size(); ++k) {
    px.push_back(sorted_x[k]), py.push_back(100.0 * (sorted_x.size() - k) / n);
    px.push_back(sorted_x[k]), py.push_back(100.0 * (sorted_x.size() - k - 1) / n);
  }
  plot.Polyline(px, py, "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1.8\"");
  s += Figure(
      plot.Svg(),
      "<b>Runout exceedance:</b> the share of all " + Int(Rocks(c)) +
          " released rocks that stopped beyond x" +
          (c.left + c.timeout > 0 ? " (rocks that left the slope or timed out are not counted)."
                                  : "."),
      380);
  s += "</div>";
  return s;
}

std::string ShapesSection(const Context& c) {
  std::map<core::Shape, std::vector<const core::RockRecord*>> by_shape;
  for (const core::RockRecord& r : c.result.rocks) by_shape[r.shape].push_back(&r);
  // One column per shape, one row per quantity.
  std::vector<std::pair<std::string, std::vector<std::string>>> rows;
  auto row = [&](const std::string& name) -> std::vector<std::string>& {
    for (auto& r : rows)
      if (r.first == name) return r.second;
    rows.push_back({name, {}});
    return rows.back().second;
  };
  std::string head = "<tr><th></th>";
  for (const auto& [shape, rocks] : by_shape) {
    head += Th(core::ShapeName(shape));
    int st = 0, le = 0, to = 0;
    std::vector<double> xs;
    for (const auto* r : rocks) {
      if (r->outcome == core::Outcome::kStopped) ++st, xs.push_back(r->stop.x());
      if (r->outcome == core::Outcome::kLeft) ++le;
      if (r->outcome == core::Outcome::kTimeout) ++to;
    }
    const double n = static_cast<double>(rocks.size());
    const core::Stats sx = core::Summarize(xs);
    row("rocks").push_back(Int(static_cast<long>(rocks.size())));
    row("stopped").push_back(Int(st) + " (" + Percent(st / n) + ")");
    row("left the slope").push_back(Int(le) + " (" + Percent(le / n) + ")");
    if (c.timeout > 0) row("still moving at the time limit").push_back(Int(to));
    row("median stop x").push_back(xs.empty() ? "-" : Length(sx.p50));
    row("95th percentile stop x").push_back(xs.empty() ? "-" : Length(sx.p95));
    for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
      const std::string& id = c.scene.partitions[p].id;
      std::vector<double> h, e;
      for (const auto* r : rocks)
        if (p < r->crossings.size() && r->crossings[p].crossed)
          h.push_back(r->crossings[p].height), e.push_back(r->crossings[p].energy);
      const core::Stats sh = core::Summarize(h), se = core::Summarize(e);
      row(id + ": passed")
          .push_back(Int(static_cast<long>(h.size())) + " (" + Percent(h.size() / n) + ")");
      row(id + ": 95th percentile bounce height").push_back(h.empty() ? "-" : Length(sh.p95));
      row(id + ": 95th percentile energy")
          .push_back(e.empty()
                         ? "-"
                         : Show(se.p95 * 1e-3) + " kJ (" + Show(se.p95 / kFtTon) + " ft-tons)");
    }
  }
  std::string s = "<p>The main results for each rock shape.</p><table class=\"stats\"><thead>" +
                  head + "</tr></thead><tbody>";
  for (const auto& [name, cells] : rows) {
    s += "<tr><th>" + Escape(name) + "</th>";
    for (const std::string& cell : cells) s += Td(cell, true);
    s += "</tr>";
  }
  return s + "</tbody></table>";
}

std::string DiagnosticsSection(const Context& c) {
  const nlohmann::json d = DiagnosticsJson(c.scene, c.result);
  struct Row {
    const char* key;
    const char* what;
    int verdict;  // 0: information, 1: must be 0, 2: small is good (below limit)
    double limit;
  };
  const Row rows[] = {
      {"dt_min_seconds", "smallest contact time step [s]", 0, 0},
      {"dt_max_seconds", "largest contact time step [s]", 0, 0},
      {"steps_per_contact", "steps per contact duration (N_c)", 0, 0},
      {"rocks_with_step_shrunk_for_stability",
       "rocks whose step was cut below t_c/N_c for stability", 0, 0},
      {"gentle_steps_per_contact", "steps per contact duration in gentle contact (N_g; 0: off)", 0,
       0},
      {"contact_steps", "contact steps", 0, 0},
      {"gentle_steps", "of which at the gentle-contact step", 0, 0},
      {"retried_steps", "gentle steps taken back and redone short (an impact began)", 0, 0},
      {"flights", "exact free flights", 0, 0},
      {"max_penetration_over_radius",
       "deepest overlap / element radius (about impact speed x t_c / pi)", 2, 0.5},
      {"max_relative_energy_gain",
       "largest rise of mechanical energy / largest kinetic energy of the rock", 2, 1e-3},
      {"non_finite_rocks", "rocks whose state became non-finite", 1, 0},
      {"tunneled_rocks", "rocks that fell through the terrain", 1, 0},
  };
  std::string s =
      "<p>The numerical health of the run (diagnostics.json): the engine picks its own stable step "
      "and "
      "reports where it had to work hard.</p><table><thead><tr>" +
      Th("quantity") + Th("value") + Th("check") + "</tr></thead><tbody>";
  for (const Row& row : rows) {
    if (!d.contains(row.key)) continue;
    const double v = d[row.key].get<double>();
    std::string verdict = "";
    if (row.verdict == 1) verdict = v == 0 ? "OK" : "FAILED: must be 0";
    if (row.verdict == 2)
      verdict = v <= row.limit ? "OK (below " + Label(row.limit) + ")"
                               : "check: above " + Label(row.limit);
    const bool integer = d[row.key].is_number_integer();
    s += "<tr>" + Td(row.what) +
         RefCell(Ref("diagnostics.json", std::string("/") + row.key), v,
                 integer ? Int(static_cast<long>(v)) : Label(v, 3)) +
         "<td class=\"" +
         (verdict.rfind("OK", 0) == 0 ? "ok"
          : verdict.empty()           ? ""
                                      : "bad") +
         "\">" + Escape(verdict) + "</td></tr>";
  }
  s += "</tbody></table>";
  if (c.timeout > 0)
    s += "<p class=\"warn\">" + Int(c.timeout) + " rocks were still moving at the time limit of " +
         Label(c.scene.options.max_time) + " s; a longer limit may move their stop points.</p>";
  return s;
}

// ---- calibration -------------------------------------------------------------

// A parameter value in SI with US units beside it (as everywhere in the report).
std::string ParameterValue(const calibrate::Parameter& p, double v) {
  switch (p.kind) {
    case calibrate::ParameterKind::kHardness:
      return FormatNumber(v, "%.3f");
    case calibrate::ParameterKind::kRoughness:
      return Length(v);
    case calibrate::ParameterKind::kContactTime:
      return Show(v) + " s (" + Show(v * 1e3) + " ms)";
    case calibrate::ParameterKind::kRollingResistance:
      return FormatNumber(v, "%.3f");
  }
  return Show(v);
}

// Where v lies within [lo, hi]: a small bar with a marker.
std::string BoundsBar(double v, double lo, double hi) {
  const double f = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
  const std::string x = Px(4 + 92 * f);
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"12\" viewBox=\"0 0 100 "
         "12\">"
         "<line x1=\"4\" y1=\"6\" x2=\"96\" y2=\"6\" stroke=\"#999\" stroke-width=\"2\"/>"
         "<line x1=\"4\" y1=\"2\" x2=\"4\" y2=\"10\" stroke=\"#999\"/><line x1=\"96\" y1=\"2\" "
         "x2=\"96\" y2=\"10\" "
         "stroke=\"#999\"/><circle cx=\"" +
         x + "\" cy=\"6\" r=\"4\" fill=\"" + kStopColour + "\"/></svg>";
}

std::string CalibrationSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const calibrate::MethodResult& best = rec.methods[static_cast<std::size_t>(rec.best)];
  const std::string cj = "calibration.json";
  std::string s = "<table class=\"kv\">";
  s += Kv("Method", "<code>" + Escape(best.method) + "</code>" +
                        (rec.methods.size() > 1
                             ? " (the best of " + Int(static_cast<long>(rec.methods.size())) +
                                   " methods, compared below)"
                             : std::string()));
  s += Kv("Stopped because", "<span data-json=\"" + Ref(cj, "/termination") + "\" data-value=\"" +
                                 Escape(best.termination.message) + "\">" + Escape(best.termination.message) +
                                 "</span>");
  s += Kv("Evaluations", RefSpan(Ref(cj, "/evaluations"), best.evaluations, Int(best.evaluations)) +
                             " (" + Int(best.simulated) +
                             " simulated, the rest replayed from the log) in " +
                             Escape(Show(best.wall_seconds)) + " s");
  s += Kv("Misfit",
          "at the start " +
              RefSpan(Ref(cj, "/misfit_before"), rec.misfit_before.value,
                      Label(rec.misfit_before.value, 4)) +
              ", at the calibrated values " +
              RefSpan(Ref(cj, "/methods/" + Int(rec.best) + "/misfit"), best.best_misfit,
                      Label(best.best_misfit, 4)) +
              ", lowest evaluated " +
              RefSpan(Ref(cj, "/methods/" + Int(rec.best) + "/lowest_misfit"), best.lowest_misfit,
                      Label(best.lowest_misfit, 4)) +
              ", this report's simulation " +
              RefSpan(Ref(cj, "/misfit_after"), rec.misfit_after.value,
                      Label(rec.misfit_after.value, 4)) +
              " (half the sum of the squared residuals, each in units of its uncertainty)");
  s += Kv("Calibrated values",
          best.smoothed.used
              ? "the smoothed estimate: " + Escape(best.smoothed.message) +
                    ", at its Gauss-Newton minimum (the lowest evaluation sits in a dip of the "
                    "Monte Carlo noise)"
              : "the lowest evaluation" +
                    (best.smoothed.message.empty()
                         ? std::string()
                         : " (smoothed estimate " + Escape(best.smoothed.message) + ")"));
  s += Kv("Each evaluation", Escape(Int(rec.rocks) + " rocks, seed " + std::to_string(rec.seed) +
                                    " (the same random numbers at every evaluation)"));
  s += Kv(
      "Whole calibration",
      RefSpan(Ref(cj, "/wall_seconds"), rec.wall_seconds, Show(rec.wall_seconds)) + " s wall time");
  s += "</table>";
  if (rec.misfit_after.penalised || rec.misfit_before.penalised)
    s += "<p class=\"warn\">" +
         Escape(rec.misfit_after.message.empty() ? rec.misfit_before.message
                                                 : rec.misfit_after.message) +
         "</p>";

  // Parameter table.
  const auto& ps = rec.space.parameters();
  const calibrate::Uncertainty& u = best.uncertainty;
  const bool have_se = u.computed && !u.rank_deficient;
  s += "<h3>Calibrated parameters</h3><table><thead><tr>" + Th("material") + Th("parameter") +
       Th("calibrated") + Th("std. error") + Th("start") + Th("lower bound") + Th("upper bound") +
       Th("within bounds") + "</tr></thead><tbody>";
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const double v = k < best.best.size() ? best.best[k] : std::nan("");
    const double range = ps[k].upper - ps[k].lower;
    const bool at_bound =
        std::fabs(v - ps[k].lower) < 0.01 * range || std::fabs(ps[k].upper - v) < 0.01 * range;
    s += "<tr>" + Td(ps[k].material) + Td(ps[k].name()) + "<td class=\"n\" data-json=\"" +
         Ref(cj, "/calibrated/" + Int(static_cast<long>(k))) + "\" data-value=\"" + Exact(v) +
         "\">" + Escape(ParameterValue(ps[k], v)) + (at_bound ? " <b>at a bound</b>" : "") +
         "</td>" +
         Td(have_se && k < u.std_error.size() ? ParameterValue(ps[k], u.std_error[k]) : "-", true) +
         Td(k < rec.start.size() ? ParameterValue(ps[k], rec.start[k]) : "-", true) +
         Td(ParameterValue(ps[k], ps[k].lower), true) +
         Td(ParameterValue(ps[k], ps[k].upper), true) + "<td>" +
         BoundsBar(v, ps[k].lower, ps[k].upper) + "</td></tr>";
  }
  s += "</tbody></table>";
  if (u.computed && u.rank_deficient)
    s += "<p class=\"note\">Standard errors not available: " + Escape(u.message) + ".</p>";
  else if (!u.computed)
    s += "<p class=\"note\">Standard errors are computed by the <code>ceres</code> method only; "
         "\"-\" means not "
         "computed.</p>";
  else
    s += "<p class=\"note\">Standard errors are linearised from the Jacobian of the residuals and "
         "are a lower "
         "bound.</p>";
  if (have_se && u.correlation.size() == ps.size() && ps.size() > 1) {
    s += "<h3>Correlation of the parameters</h3><table><thead><tr><th></th>";
    for (const auto& p : ps) s += Th(p.label());
    s += "</tr></thead><tbody>";
    for (std::size_t a = 0; a < ps.size(); ++a) {
      s += "<tr><th>" + Escape(ps[a].label()) + "</th>";
      for (std::size_t b = 0; b < ps.size(); ++b)
        s += Td(FormatNumber(u.correlation[a][b], "%.2f"), true);
      s += "</tr>";
    }
    s += "</tbody></table>";
  }
  if (rec.methods.size() > 1) {
    const double best_all = LowestMisfitOfAll(rec);
    s += "<h3>Methods compared</h3><table><thead><tr>" + Th("method") + Th("misfit") +
         Th("lowest evaluated") + Th("evaluations") + Th("simulated") + Th("wall s") +
         Th("s to within 10 % of the lowest") + Th("stopped because") + "</tr></thead><tbody>";
    for (std::size_t m = 0; m < rec.methods.size(); ++m) {
      const auto& mr = rec.methods[m];
      const double reach = calibrate::TimeToReach(mr, best_all, 0.1);
      s += "<tr" + std::string(static_cast<int>(m) == rec.best ? " class=\"best\"" : "") +
           "><td><code>" + Escape(mr.method) + "</code></td>" +
           RefCell(Ref(cj, "/methods/" + Int(static_cast<long>(m)) + "/misfit"), mr.best_misfit,
                   Label(mr.best_misfit, 4)) +
           RefCell(Ref(cj, "/methods/" + Int(static_cast<long>(m)) + "/lowest_misfit"),
                   mr.lowest_misfit, Label(mr.lowest_misfit, 4)) +
           Td(Int(mr.evaluations), true) + Td(Int(mr.simulated), true) +
           Td(Show(mr.wall_seconds), true) + Td(reach >= 0 ? Show(reach) : "never", true) +
           Td(mr.termination.message) + "</tr>";
    }
    s += "</tbody></table>";
  }
  return s;
}

std::string TracePlot(const CalibrationSummary& rec, bool by_time) {
  double xmax = 0.0, ymin = kInf, ymax = 0.0;
  const double start = rec.misfit_before.penalised ? std::nan("") : rec.misfit_before.value;
  if (start > 0) ymin = ymax = start;
  for (const auto& m : rec.methods)
    for (const auto& e : m.trace) {
      if (e.penalised) continue;
      xmax = std::max(xmax, by_time ? e.elapsed : static_cast<double>(e.index));
      if (e.misfit > 0) ymin = std::min(ymin, e.misfit);
      ymax = std::max(ymax, e.misfit);
    }
  if (!std::isfinite(ymin)) ymin = 1e-3;
  if (!(ymax > 0)) ymax = 1.0;
  const bool log_y = ymax / ymin > 20.0;
  svg::Plot::Options o;
  o.width = 420, o.height = 290, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
  o.log_y = log_y;
  o.title = by_time ? "Misfit against wall time" : "Misfit against evaluations";
  svg::Plot plot(0.0, std::max(xmax, by_time ? 1e-3 : 1.0), log_y ? ymin / 1.5 : 0.0,
                 ymax * (log_y ? 1.5 : 1.08), o);
  plot.Axes(by_time ? "wall time [s]" : "evaluation", log_y ? "misfit (log scale)" : "misfit");
  if (std::isfinite(start))
    plot.HLine(start, "stroke=\"#777\" stroke-dasharray=\"3 3\"", "at the start");
  for (std::size_t m = 0; m < rec.methods.size(); ++m) {
    const auto& mr = rec.methods[m];
    std::vector<double> xs, ys, bx, by;
    double best = kInf;
    for (const auto& e : mr.trace) {
      const double x = by_time ? e.elapsed : e.index;
      if (!e.penalised) xs.push_back(x), ys.push_back(e.misfit);
      if (e.misfit < best) {
        best = e.misfit;
        bx.push_back(x), by.push_back(best);
      }
    }
    if (!bx.empty())
      bx.push_back(by_time ? std::max(mr.wall_seconds, bx.back()) : mr.trace.back().index),
          by.push_back(best);
    const std::string colour = svg::Colour(static_cast<int>(m));
    plot.Points(xs, ys, 2.4, "fill=\"" + colour + "\" fill-opacity=\"0.5\"");
    plot.Steps(bx, by, "stroke=\"" + colour + "\" stroke-width=\"2\"");
  }
  return plot.Svg();
}

std::string TraceSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  int penalised = 0;
  for (const auto& m : rec.methods)
    for (const auto& e : m.trace) penalised += e.penalised ? 1 : 0;
  std::string s =
      "<p><b>Error against run time.</b> The misfit of every evaluation (dots) and the best so far "
      "(line) for each method, against wall time since the method started and against the number "
      "of "
      "evaluations.";
  if (penalised > 0)
    s += " " + Int(penalised) + " penalised evaluations (failed comparisons) are not drawn.";
  s += "</p><ul class=\"legend\">";
  for (std::size_t m = 0; m < rec.methods.size(); ++m) {
    const std::string colour = svg::Colour(static_cast<int>(m));
    s += LegendItem(Swatch(colour, "line"), rec.methods[m].method + ": best so far");
    s += LegendItem(Swatch(colour, "point"), rec.methods[m].method + ": each evaluation");
  }
  s += "</ul><div class=\"figs\">";
  s += Figure(TracePlot(rec, true), "<b>Misfit against wall time</b> since each method started.",
              420);
  s += Figure(TracePlot(rec, false), "<b>Misfit against evaluations.</b>", 420);
  s += "</div>";
  return s;
}

std::string FitSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const auto& after = rec.misfit_after.residuals;
  // Observation labels in order, and the "before" residual of each (label, quantity).
  std::vector<std::string> labels;
  for (const auto& r : after)
    if (std::find(labels.begin(), labels.end(), r.observation) == labels.end())
      labels.push_back(r.observation);
  std::map<std::pair<std::string, std::string>, const observations::Residual*> before;
  for (const auto& r : rec.misfit_before.residuals) before[{r.observation, r.quantity}] = &r;
  std::string s =
      "<p>Each observed quantile against its simulated counterpart, at the start (rings) and at "
      "the "
      "calibrated values (dots, with one uncertainty above and below). A perfect fit lies on the "
      "1:1 "
      "line.</p><ul class=\"legend\">" +
      LegendItem(Swatch("#888", "ring"), "at the start") +
      LegendItem(Swatch(kStopColour, "point"), "calibrated, with its uncertainty") +
      LegendItem(Swatch("#999", "dash"), "1:1") + "</ul><div class=\"figs\">";
  for (const std::string& label : labels) {
    std::vector<double> ox, sy, bx, by;
    double lo = kInf, hi = -kInf;
    std::string bars;
    for (const auto& r : after) {
      if (r.observation != label) continue;
      ox.push_back(r.observed), sy.push_back(r.simulated);
      lo = std::min({lo, r.observed, r.simulated - r.sigma}),
      hi = std::max({hi, r.observed, r.simulated + r.sigma});
      const auto it = before.find({r.observation, r.quantity});
      if (it != before.end()) {
        bx.push_back(it->second->observed), by.push_back(it->second->simulated);
        lo = std::min(lo, it->second->simulated), hi = std::max(hi, it->second->simulated);
      }
    }
    const bool fraction = after.empty() ? false : [&] {
      for (const auto& r : after)
        if (r.observation == label) return r.quantity == "fraction";
      return false;
    }();
    const double pad = 0.05 * (hi - lo > 0 ? hi - lo : 1.0);
    lo -= pad, hi += pad;
    svg::Plot::Options o;
    o.width = 330, o.height = 290, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
    o.title = "Observed against simulated quantiles: " + label;
    svg::Plot plot(lo, hi, lo, hi, o);
    const std::string unit = fraction ? "" : " [m]";
    plot.Axes("observed" + unit, "simulated" + unit);
    plot.Polyline({lo, hi}, {lo, hi}, "stroke=\"#999\" stroke-dasharray=\"4 3\"");
    for (const auto& r : after) {
      if (r.observation != label) continue;
      plot.Polyline({r.observed, r.observed}, {r.simulated - r.sigma, r.simulated + r.sigma},
                    "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1\"");
    }
    plot.Points(bx, by, 3.5, "fill=\"none\" stroke=\"#888\" stroke-width=\"1.2\"");
    plot.Points(ox, sy, 3.0, "fill=\"" + std::string(kStopColour) + "\"");
    s += Figure(plot.Svg(),
                "<b>" + Escape(label) + "</b>" +
                    (fraction ? "" : " (quantiles p10 to p90 and the maximum)"),
                330);
  }
  s += "</div>";
  // Residual table.
  const bool us = rec.units == sites::Units::kUS;
  s += "<h3>Residuals</h3><table><thead><tr>" + Th("observation") + Th("quantity") +
       Th("observed") + Th("simulated at the start") + Th("simulated, calibrated") +
       Th("uncertainty") + Th("residual") + "</tr></thead><tbody>";
  for (std::size_t k = 0; k < after.size(); ++k) {
    const auto& r = after[k];
    const bool fraction = r.quantity == "fraction";
    auto value = [&](double v) {
      if (fraction) return FormatNumber(v, "%.3f");
      return us ? Show(v) + " m (" + Show(v / kFoot) + " ft)" : Show(v) + " m";
    };
    const auto it = before.find({r.observation, r.quantity});
    const std::string base = "/fit/" + Int(static_cast<long>(k)) + "/";
    s += "<tr>" + Td(r.observation) + Td(r.quantity) +
         RefCell(Ref("calibration.json", base + "observed"), r.observed, value(r.observed)) +
         Td(it != before.end() ? value(it->second->simulated) : "-", true) +
         RefCell(Ref("calibration.json", base + "simulated"), r.simulated, value(r.simulated)) +
         Td(value(r.sigma), true) +
         RefCell(Ref("calibration.json", base + "residual"), r.value, Show(r.value)) + "</tr>";
  }
  s += "</tbody></table>";
  return s;
}

// ---- the outline ---------------------------------------------------------------

struct SectionInfo {
  std::string id, title;
  int partition = -1;
};

Context MakeContext(const ReportInput& in) {
  if (!in.scene || !in.result)
    throw std::invalid_argument("HtmlReport: scene and result are required");
  std::string error;
  if (!in.options.IsValid(&error)) throw std::invalid_argument("HtmlReport: " + error);
  Context c{in, *in.scene, *in.result, core::ComputeStats(*in.scene, *in.result)};
  const core::HeightGrid& g = c.scene.grid;
  c.one_cell_wide = g.nx <= 2 || g.ny <= 2;
  std::set<core::Shape> shapes;
  for (const auto& grp : c.scene.groups) shapes.insert(grp.shape);
  c.several_shapes = shapes.size() > 1;
  c.stopped = c.result.count(core::Outcome::kStopped);
  c.left = c.result.count(core::Outcome::kLeft);
  c.timeout = c.result.count(core::Outcome::kTimeout);
  for (double z : g.z)
    if (std::isfinite(z)) c.zmin = std::min(c.zmin, z), c.zmax = std::max(c.zmax, z);
  if (!(c.zmax >= c.zmin)) c.zmin = 0.0, c.zmax = 1.0;
  if (c.zmax == c.zmin) c.zmax = c.zmin + 1.0;
  return c;
}

std::vector<SectionInfo> Outline(const Context& c) {
  std::vector<SectionInfo> out;
  out.push_back({"site", "Project and site"});
  if (!c.one_cell_wide && c.scene.grid.nx >= 2 && c.scene.grid.ny >= 2)
    out.push_back({"plan", "Plan view"});
  out.push_back({"profile", "Profile view"});
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    const core::Partition& part = c.scene.partitions[p];
    out.push_back({PartitionSectionId(part.id),
                   "Partition " + part.id + " (" + KindName(part.kind) + ")", static_cast<int>(p)});
  }
  if (!c.scene.partitions.empty()) out.push_back({"barrier", "Barrier check"});
  if (c.stopped > 0) out.push_back({"runout", "Runout"});
  if (c.several_shapes) out.push_back({"shapes", "Rock shapes"});
  if (c.in.calibration && !c.in.calibration->methods.empty()) {
    if (c.in.calibration->reach) out.push_back({"reach", "Reach before fit"});
    out.push_back({"calibration", "Calibration"});
    bool trace = false;
    for (const auto& m : c.in.calibration->methods) trace = trace || !m.trace.empty();
    if (trace) out.push_back({"trace", "Error against run time"});
    if (!c.in.calibration->misfit_after.residuals.empty())
      out.push_back({"fit", "Fit to the observations"});
  }
  out.push_back({"diagnostics", "Numerical diagnostics"});
  return out;
}

}  // namespace

bool ReportOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!(barrier_height_m > 0.0) || !std::isfinite(barrier_height_m))
    return fail("barrier_height_m = " + Label(barrier_height_m) + ": must be a finite number > 0");
  if (!(barrier_energy_j > 0.0) || !std::isfinite(barrier_energy_j))
    return fail("barrier_energy_j = " + Label(barrier_energy_j) + ": must be a finite number > 0");
  if (max_trajectories < 0)
    return fail("max_trajectories = " + Int(max_trajectories) + ": must be >= 0");
  if (max_stop_points < 1)
    return fail("max_stop_points = " + Int(max_stop_points) + ": must be >= 1");
  return true;
}

std::string PartitionSectionId(const std::string& partition_id) {
  std::string id = "partition-";
  for (char ch : partition_id) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '-' || ch == '_';
    id += ok ? ch : '_';
  }
  return id;
}

std::vector<std::string> ReportSections(const ReportInput& in) {
  const Context c = MakeContext(in);
  std::vector<std::string> ids;
  for (const SectionInfo& s : Outline(c)) ids.push_back(s.id);
  return ids;
}

std::string HtmlReport(const ReportInput& in) {
  const Context c = MakeContext(in);
  const bool calibrated = in.calibration && !in.calibration->methods.empty();
  html::Page page;
  page.title = "rockcal report: " + c.scene.name;
  page.heading_html =
      std::string(calibrated ? "Rockfall calibration report: " : "Rockfall simulation report: ") +
      html::RefText("summary.json#/site", c.scene.name);
  std::string& lead = page.lead_html;
  lead = Int(Rocks(c)) + " rocks: " + Int(c.stopped) + " stopped, " + Int(c.left) +
         " left the slope, " + Int(c.timeout) + " still moving at the time limit";
  for (std::size_t p = 0; p < c.scene.partitions.size(); ++p) {
    const auto& ps = c.stats.partitions[p];
    lead += "; " + Escape(ps.id) + " passed by " +
            Percent(Rocks(c) ? static_cast<double>(ps.passed) / Rocks(c) : 0.0);
  }
  lead += ". Simulated by rockcal (CRSP-3D method) in " + Escape(Show(c.result.wall_seconds)) +
          " s wall time.";
  if (calibrated) {
    const auto& rec = *in.calibration;
    const observations::FitVerdict verdict = observations::AssessFit(rec.misfit_after);
    lead +=
        std::string(verdict.poor ? " Calibration searched with " : " Parameters calibrated with ") +
        Escape(rec.methods[static_cast<std::size_t>(rec.best)].method) + ": misfit " +
        Escape(Label(rec.misfit_before.value, 3)) + " at the start, " +
        Escape(Label(rec.misfit_after.value, 3)) + " at the calibrated values. <b>Fit " +
        Escape(verdict.Sentence()) + ".</b>" +
        (verdict.poor ? " The calibrated values do not reproduce the observations: do not use "
                        "them as if they did (widen the box, change the model, or check the "
                        "observations)."
                      : "");
  }
  page.note_html =
      "SI units with US units beside them: 1 ft = 0.3048 m; 1 ft/s = 0.3048 m/s; "
      "1 ft-ton (foot times short ton-force, as CRSP reports kinetic energy) = 2.7116 kJ; "
      "1 lbf/ft&#179; = 0.15709 kN/m&#179;. The machine-readable record is summary.json and "
      "rocks.csv (SI).";
  for (const SectionInfo& s : Outline(c)) {
    html::Section section{s.id, s.title, "", ""};
    if (s.id == "site")
      section.body_html = SiteSection(c);
    else if (s.id == "plan")
      section.body_html = PlanSection(c);
    else if (s.id == "profile")
      section.body_html = ProfileSection(c);
    else if (s.partition >= 0)
      section.body_html = PartitionSection(c, s.partition);
    else if (s.id == "barrier")
      section.body_html = BarrierSection(c);
    else if (s.id == "runout")
      section.body_html = RunoutSection(c);
    else if (s.id == "shapes")
      section.body_html = ShapesSection(c);
    else if (s.id == "reach")
      section.body_html = ReachSection(*in.calibration->reach);
    else if (s.id == "calibration")
      section.body_html = CalibrationSection(c);
    else if (s.id == "trace")
      section.body_html = TraceSection(c);
    else if (s.id == "fit")
      section.body_html = FitSection(c);
    else if (s.id == "diagnostics")
      section.body_html = DiagnosticsSection(c);
    if (s.partition >= 0) {
      const core::Partition& part = c.scene.partitions[static_cast<std::size_t>(s.partition)];
      section.heading_html =
          "Partition " +
          html::RefText("summary.json#/partitions/" + Int(s.partition) + "/id", part.id) + " (" +
          KindName(part.kind) + " partition, " +
          (part.kind == core::Partition::Kind::kX ? "x = " : "z = ") + Escape(Length(part.value)) +
          ")";
    }
    page.sections.push_back(std::move(section));
  }
  page.footer_html =
      "Generated by rockcal, a rockfall simulator after CRSP-3D (FHWA-CFL/TD-12-007, 2012). "
      "Random seed " +
      std::to_string(c.scene.options.seed) + ", " + Int(Rocks(c)) +
      " rocks. This file is self-contained: no scripts, no network.";
  return html::PageHtml(page);
}

}  // namespace rockcal::reports
