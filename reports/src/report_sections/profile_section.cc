// The profile view of report.html: ground elevation against x with sampled
// trajectories and stop points.
#include <algorithm>
#include <cmath>
#include <set>

#include "rockcal/core/rock_shape.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

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

// The ground along y = yc and its range across the slope, per grid column.
struct GroundProfile {
  double yc = 0.0;                       // m, through the first release zone's centre
  std::vector<double> xs, line, lo, hi;  // m; NaN where a column has no data
};

GroundProfile Ground(const Context& c) {
  const core::HeightGrid& g = c.scene.grid;
  GroundProfile p;
  p.yc = c.scene.groups.empty() ? 0.5 * (g.y0 + g.y(g.ny - 1))
                                : observations::ReleaseCentroid(c.scene.groups[0].release).y();
  for (int i = 0; i < g.nx; ++i) {
    double a = kInf, b = -kInf;
    for (int j = 0; j < g.ny; ++j) {
      const double z = g.z[g.index(i, j)];
      if (std::isfinite(z)) a = std::min(a, z), b = std::max(b, z);
    }
    p.xs.push_back(g.x(i));
    p.line.push_back(GroundAt(g, g.x(i), std::clamp(p.yc, g.y0, g.y(g.ny - 1))));
    p.lo.push_back(std::isfinite(a) ? a : std::nan(""));
    p.hi.push_back(std::isfinite(b) ? b : std::nan(""));
  }
  return p;
}

// The recorded trajectories to draw: at most max_trajectories, spread over
// every group.
std::vector<const core::RockRecord*> SampledPaths(const Context& c) {
  std::vector<const core::RockRecord*> paths;
  for (const core::RockRecord& r : c.result.rocks)
    if (!r.trajectory.empty()) paths.push_back(&r);
  return SpreadSample(paths, c.in.options.max_trajectories);
}

// The frame of the profile: true scale when it fits, otherwise with the
// vertical exaggerated (returned in *exaggeration); *width is the picture's.
svg::Plot ProfilePlot(const Context& c, const std::vector<const core::RockRecord*>& paths,
                      double* exaggeration, double* width) {
  const core::HeightGrid& g = c.scene.grid;
  const double xlo = g.x0, xhi = g.x(g.nx - 1);
  double zlo = c.zmin, zhi = c.zmax;
  for (const auto* r : paths)
    for (const auto& s : r->trajectory) zlo = std::min(zlo, s.x.z()), zhi = std::max(zhi, s.x.z());
  const double pad = 0.04 * (zhi - zlo);
  zlo -= pad, zhi += pad;
  const double xext = xhi - xlo, zext = zhi - zlo;
  double kx = 780.0 / xext, kz = kx;
  if (zext * kz > 440.0) kx = kz = 440.0 / zext;
  *exaggeration = 1.0;
  if (zext * kz < 180.0) {
    *exaggeration = 180.0 / (zext * kz);
    kz *= *exaggeration;
  }
  svg::Plot::Options o;
  const bool us = c.in.units == sites::Units::kUS;
  o.left = 58, o.bottom = 44, o.top = us ? 40 : 14, o.right = us ? 58 : 16;
  o.width = o.left + o.right + xext * kx;
  o.height = o.top + o.bottom + zext * kz;
  o.title = "Profile: ground elevation against x with sampled rock trajectories";
  *width = o.width;
  svg::Plot plot(xlo, xhi, zlo, zhi, o);
  plot.Axes("x [m]", "elevation [m]");
  if (us) {
    plot.TopAxis(1.0 / kFoot, "x [ft]");
    plot.RightAxis(1.0 / kFoot, "elevation [ft]");
  }
  return plot;
}

// The ground line, and in 3D the shaded range of the ground across the slope.
void DrawGround(const GroundProfile& ground, bool is3d, svg::Plot* plot) {
  if (is3d) {
    std::string pts;
    for (std::size_t k = 0; k < ground.xs.size(); ++k)
      if (std::isfinite(ground.hi[k]))
        pts +=
            (pts.empty() ? "" : " ") + Px(plot->X(ground.xs[k])) + "," + Px(plot->Y(ground.hi[k]));
    for (std::size_t k = ground.xs.size(); k-- > 0;)
      if (std::isfinite(ground.lo[k]))
        pts += " " + Px(plot->X(ground.xs[k])) + "," + Px(plot->Y(ground.lo[k]));
    plot->Raw("<polygon fill=\"#e3e3e3\" stroke=\"none\" points=\"" + pts + "\"/>");
  }
  plot->Polyline(ground.xs, ground.line, "stroke=\"#444\" stroke-width=\"1.8\"");
}

// Partitions: X as vertical lines, Z as horizontal lines at their elevation.
void DrawPartitions(const Context& c, svg::Plot* plot) {
  for (const core::Partition& p : c.scene.partitions) {
    if (p.kind == core::Partition::Kind::kLine) continue;  // drawn in plan only
    if (p.kind == core::Partition::Kind::kX)
      plot->VLine(p.value,
                  "stroke=\"" + std::string(kPartitionColour) +
                      "\" stroke-width=\"1.5\" stroke-dasharray=\"7 4\"",
                  p.id);
    else
      plot->HLine(p.value,
                  "stroke=\"" + std::string(kPartitionColour) +
                      "\" stroke-width=\"1.5\" stroke-dasharray=\"7 4\"",
                  p.id + " (z = " + CoordinateNumber(p.value) + " m)");
  }
}

// The trajectories, coloured by group; returns the groups drawn.
std::set<int> DrawPaths(const std::vector<const core::RockRecord*>& paths, svg::Plot* plot) {
  std::set<int> groups_drawn;
  for (const auto* r : paths) {
    std::vector<double> px, pz;
    for (const auto& s : r->trajectory) px.push_back(s.x.x()), pz.push_back(s.x.z());
    plot->Polyline(px, pz,
                   "stroke=\"" + std::string(svg::Colour(r->group)) +
                       "\" stroke-width=\"1\" stroke-opacity=\"0.75\"");
    groups_drawn.insert(r->group);
  }
  return groups_drawn;
}

// Where the stopped rocks ended (up to max_stop_points rocks); false when none.
bool DrawStops(const Context& c, svg::Plot* plot) {
  std::vector<const core::RockRecord*> stopped;
  for (const core::RockRecord& r : c.result.rocks)
    if (r.outcome == core::Outcome::kStopped) stopped.push_back(&r);
  std::vector<double> sx, sz;
  for (const core::RockRecord* r : SpreadSample(stopped, c.in.options.max_stop_points))
    sx.push_back(r->stop.x()), sz.push_back(r->stop.z());
  plot->Points(sx, sz, 2.0, "fill=\"" + std::string(kStopColour) + "\" fill-opacity=\"0.6\"");
  return !sx.empty();
}

std::vector<svg::Plot::LegendEntry> ProfileLegend(const Context& c, const GroundProfile& ground,
                                                  bool is3d, const std::set<int>& groups_drawn,
                                                  bool stops) {
  std::vector<svg::Plot::LegendEntry> legend;
  legend.push_back(
      {"#444", is3d ? "ground at y = " + CoordinateNumber(ground.yc) + " m" : "ground", "line"});
  if (is3d) legend.push_back({"#d0d0d0", "ground range across the slope", "bar"});
  for (int grp : groups_drawn)
    legend.push_back({svg::Colour(grp),
                      "group " + std::to_string(grp + 1) + " (" +
                          core::ShapeToString(c.scene.groups[static_cast<std::size_t>(grp)].shape) +
                          ") trajectory",
                      "line"});
  if (stops) legend.push_back({kStopColour, "stop point", "point"});
  return legend;
}

std::string ProfileCaption(const Context& c, const std::vector<const core::RockRecord*>& paths,
                           double yc, bool is3d, double exaggeration) {
  std::string cap = "<b>Profile.</b> Rock centre elevation against x";
  if (paths.empty())
    cap += "; no trajectories were recorded for this run";
  else
    cap += " for " + Int(static_cast<long>(paths.size())) + " sampled rocks (" +
           Escape(PerGroup(paths)) + "), each sampled every " +
           Escape(Label(c.scene.options.record.sample_seconds)) + " s";
  cap += c.stopped > c.in.options.max_stop_points
             ? ", and the stop points of " + Int(c.in.options.max_stop_points) + " of the " +
                   Int(c.stopped) + " stopped rocks, spread over every group."
             : ", and the stop points of all stopped rocks.";
  if (is3d)
    cap += " The dark line is the ground along y = " + Escape(Coordinate(yc, c.in.units)) +
           " (through the centre of the first release zone); rocks away from that line travel over "
           "other "
           "ground, whose range across the slope is shaded.";
  cap += exaggeration > 1.05
             ? " Vertical exaggeration " + Escape(FormatNumber(exaggeration, "%.1f")) + "x."
             : " True scale (no vertical exaggeration).";
  return cap;
}

}  // namespace

std::string ProfileSection(const Context& c) {
  const GroundProfile ground = Ground(c);
  const std::vector<const core::RockRecord*> paths = SampledPaths(c);
  double exaggeration = 1.0, width = 0.0;
  svg::Plot plot = ProfilePlot(c, paths, &exaggeration, &width);
  const bool is3d = !c.one_cell_wide;
  DrawGround(ground, is3d, &plot);
  DrawPartitions(c, &plot);
  const std::set<int> groups_drawn = DrawPaths(paths, &plot);
  const bool stops = DrawStops(c, &plot);
  // Put the legend where the ground is low (the downslope side if it falls with x).
  const bool falls = ground.line.front() > ground.line.back() || !std::isfinite(ground.line.back());
  plot.Legend(ProfileLegend(c, ground, is3d, groups_drawn, stops), falls);
  return Figure(plot.Svg(), ProfileCaption(c, paths, ground.yc, is3d, exaggeration), width);
}

}  // namespace rockcal::reports::sections
