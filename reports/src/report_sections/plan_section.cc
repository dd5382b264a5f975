// The plan view of report.html: the slope with its material zones, and the
// rock paths (passage density and stop points), zoomed to where rocks went.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// Passage density classes: share of the rocks whose centre passed over a cell.
constexpr double kDensityBreaks[] = {0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5};
constexpr const char* kDensityColours[] = {"#ffffb2", "#fed976", "#feb24c", "#fd8d3c",
                                           "#fc4e2a", "#e31a1c", "#b10026"};
constexpr int kDensityClasses = 7;

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
      labels += "<text x=\"" + Px(lx) + "\" y=\"" + Px(ly + 3) + "\">" +
                Escape(CoordinateNumber(level)) + "</text>";
      placed.push_back(lx);
    }
  }
  return out + "</g>" + labels + "</g>";
}

// Clips the segment a-b to the box [lo, hi] (Liang-Barsky); false when
// nothing of it is inside.
bool ClipSegment(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, Eigen::Vector2d* a,
                 Eigen::Vector2d* b) {
  const Eigen::Vector2d d = *b - *a;
  double t0 = 0.0, t1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    for (const auto& [p, q] :
         {std::pair(-d[axis], (*a)[axis] - lo[axis]), std::pair(d[axis], hi[axis] - (*a)[axis])}) {
      if (p == 0.0) {
        if (q < 0.0) return false;  // parallel to this side, outside it
        continue;
      }
      const double t = q / p;
      if (p < 0.0) {
        t0 = std::max(t0, t);
      } else {
        t1 = std::min(t1, t);
      }
    }
  }
  if (t0 > t1) return false;
  const Eigen::Vector2d start = *a;
  *a = start + t0 * d;
  *b = start + t1 * d;
  return true;
}

// The legend's partitions (dashed) and barriers (solid), each when there are some.
std::string PartitionLegend(const Context& c) {
  bool planes = false, lines = false;
  for (const core::Partition& p : c.scene.partitions)
    (p.kind == core::Partition::Kind::kLine ? lines : planes) = true;
  return (planes ? LegendItem(Swatch(kPartitionColour, "dash"), "partition") : std::string()) +
         (lines ? LegendItem(Swatch(kPartitionColour, "line"), "barrier") : std::string());
}

// Partitions (X lines, Z contours, barriers' lines) with labels.
std::string PartitionMarks(const Context& c, const View& view, const svg::Plot& plot) {
  std::string out = "<g fill=\"none\" stroke=\"" + std::string(kPartitionColour) +
                    "\" stroke-width=\"2\" stroke-dasharray=\"7 4\">";
  std::string labels =
      "<g class=\"halo\" fill=\"" + std::string(kPartitionColour) + "\" font-weight=\"bold\">";
  for (const core::Partition& p : c.scene.partitions) {
    if (p.kind == core::Partition::Kind::kLine) {  // a barrier: its line, solid, clipped
      const Eigen::Vector2d lo(plot.xlo(), plot.ylo()), hi(plot.xhi(), plot.yhi());
      bool labelled = false;
      for (std::size_t k = 0; k + 1 < p.line.size(); ++k) {
        Eigen::Vector2d a = p.line[k], b = p.line[k + 1];
        if (!ClipSegment(lo, hi, &a, &b)) continue;
        out += "<line stroke-dasharray=\"none\" stroke-width=\"3\" x1=\"" + Px(plot.X(a.x())) +
               "\" y1=\"" + Px(plot.Y(a.y())) + "\" x2=\"" + Px(plot.X(b.x())) + "\" y2=\"" +
               Px(plot.Y(b.y())) + "\"/>";
        if (!labelled)
          labels += "<text x=\"" + Px(plot.X(a.x()) + 4) + "\" y=\"" + Px(plot.Y(a.y()) - 4) +
                    "\">" + Escape(p.id) + "</text>";
        labelled = true;
      }
    } else if (p.kind == core::Partition::Kind::kX) {
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
  *legend += LegendItem(Swatch("#555", "line"), "contour every " + Length(step, c.in.units));
  *legend += LegendItem(Swatch(kReleaseColour, "zone"), "release zone");
  *legend += PartitionLegend(c);
  *legend += "</ul>";
  *width = plot.right() + (c.in.units == sites::Units::kUS ? 58 : 16);
  return plot.Svg();
}

// The bands of the run's maps that the plan draws (null when not recorded):
// cells centred on the grid nodes, as in rasters.tif.
const core::RasterBand* Passages(const Context& c) {
  return c.rasters ? c.rasters->Find("passages") : nullptr;
}
const core::RasterBand* Reach(const Context& c) {
  return c.rasters ? c.rasters->Find("reach_probability") : nullptr;
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
  if (const core::RasterBand* pass = Passages(c)) {
    const double h = 0.5 * g.spacing;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        if (pass->values[static_cast<std::size_t>(g.index(i, j))] > 0)
          add(g.x(i) - h, g.y(j) - h), add(g.x(i) + h, g.y(j) + h);
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
  // Passage density: the reach probability of each cell of the maps (centred
  // on a grid node, half cells at the edges of the view).
  const core::RasterBand* reach = Reach(c);
  const bool have_passages = reach != nullptr;
  if (have_passages) {
    auto cls = [&](int i, int j) {
      const double share = reach->values[static_cast<std::size_t>(g.index(i, j))];
      if (!(share > 0.0)) return -1;  // none, or no terrain (NaN)
      int k = 0;
      while (k + 1 < kDensityClasses && share >= kDensityBreaks[k + 1]) ++k;
      return k;
    };
    const double h = 0.5 * g.spacing;
    auto xr = [&](int i, double* lo, double* hi) {
      *lo = std::max(g.x(i) - h, plot.xlo()), *hi = std::min(g.x(i) + h, plot.xhi());
    };
    auto yr = [&](int j, double* lo, double* hi) {
      *lo = std::max(g.y(j) - h, plot.ylo()), *hi = std::min(g.y(j) + h, plot.yhi());
    };
    const auto runs = Runs(plot, view.i0, view.i1 + 1, view.j0, view.j1 + 1, cls, xr, yr);
    std::string d = "<g shape-rendering=\"crispEdges\" fill-opacity=\"0.85\">";
    for (const auto& [k, rects] : runs)
      d += "<g fill=\"" + std::string(kDensityColours[k]) + "\">" + rects + "</g>";
    plot.Raw(d + "</g>");
  }
  plot.Raw(ContourLines(c, view, plot, step, "#8a8a8a"));
  plot.Raw(ReleaseMarks(c, plot));
  plot.Raw(PartitionMarks(c, view, plot));
  // Stop points by outcome (at most max_stop_points, spread over every group).
  std::string stops =
      "<g fill=\"" + std::string(kStopColour) + "\" stroke=\"#fff\" stroke-width=\"0.8\">";
  std::string timeouts =
      "<g fill=\"" + std::string(kTimeoutColour) + "\" stroke=\"#fff\" stroke-width=\"0.8\">";
  std::string lefts = "<g stroke=\"#333\" stroke-width=\"1.2\" fill=\"none\">";
  std::vector<const core::RockRecord*> all;
  for (const core::RockRecord& rock : c.result.rocks) all.push_back(&rock);
  int n = 0;
  for (const core::RockRecord* drawn : SpreadSample(all, c.in.options.max_stop_points)) {
    const core::RockRecord& r = *drawn;
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
  *legend += PartitionLegend(c);
  *legend += "</ul>";
  *width = plot.right() + (c.in.units == sites::Units::kUS ? 58 : 16);
  return plot.Svg();
}

}  // namespace

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
                  Escape(Length(step, c.in.units)) + ", release zones and partitions." +
                  zones_legend,
              zones_width);
  std::string cap = "<b>Rock paths.</b> Passage density: the share of the " + Int(Rocks(c)) +
                    " rocks whose centre passed over each cell of the site grid, centred on a "
                    "grid node (the preferred paths; the reach_probability band of rasters.tif)";
  if (!c.rasters) cap += " was not recorded for this run";
  cap += "; where each rock ended";
  if (drawn < Rocks(c)) cap += " (" + Int(drawn) + " of the rocks, spread over every group)";
  cap += ". Grey shading: elevation bands every " + Escape(Length(step, c.in.units)) +
         ", darker is higher.";
  if (zoomed) cap += " Zoomed to where the rocks went.";
  s += Figure(paths, cap + paths_legend, paths_width);
  return s + "</div>";
}

}  // namespace rockcal::reports::sections
