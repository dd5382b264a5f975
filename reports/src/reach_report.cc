#include "rockcal/reports/reach_report.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rockcal/reports/html_page.h"
#include "rockcal/reports/svg.h"

namespace rockcal::reports {
namespace {

using html::Show;
using svg::Escape;
using svg::Px;

constexpr const char* kInReach = "#1a7f37";
constexpr const char* kOutOfReach = "#b00020";
constexpr const char* kAtEdge = "#c07000";
constexpr double kClip = 10.0;  // sigmas: the plot's half-width at most

// (value - observed) / sigma of statistic s.
double Sigmas(const calibrate::ReachStatistic& s, double value) {
  return (value - s.observed) / s.sigma;
}

std::string Pointer(std::size_t index, const char* field) {
  return "/statistics/" + std::to_string(index) + "/" + field;
}

}  // namespace

std::string ReachSvg(const calibrate::ReachResult& result) {
  const std::size_t n = result.statistics.size();
  double half = 3.0;
  for (const calibrate::ReachStatistic& s : result.statistics) {
    if (s.points_with_value == 0 || !(s.sigma > 0.0)) continue;
    half = std::max({half, std::abs(Sigmas(s, s.min)), std::abs(Sigmas(s, s.max))});
  }
  half = std::min(half * 1.05, kClip);
  svg::Plot::Options o;
  o.left = 210.0;
  o.right = 70.0;
  o.top = 12.0;
  o.bottom = 44.0;
  o.width = 640.0;
  const double row = 18.0;
  o.height = o.top + o.bottom + row * static_cast<double>(std::max<std::size_t>(n, 1));
  o.title = "Reached range of each statistic in sigmas from the observed value";
  svg::Plot plot(-half, half, 0.0, static_cast<double>(std::max<std::size_t>(n, 1)), o);
  // Axes of our own: the y axis carries names, not numbers.
  std::string g = "<g class=\"axes\">";
  g += "<rect x=\"" + Px(plot.X(-1.0)) + "\" y=\"" + Px(plot.top()) + "\" width=\"" +
       Px(plot.X(1.0) - plot.X(-1.0)) + "\" height=\"" + Px(plot.bottom() - plot.top()) +
       "\" fill=\"#e8eef5\"/>";
  for (double t : svg::Ticks(-half, half, 8)) {
    const std::string x = Px(plot.X(t));
    g += "<line x1=\"" + x + "\" y1=\"" + Px(plot.top()) + "\" x2=\"" + x + "\" y2=\"" +
         Px(plot.bottom()) + "\" stroke=\"#ddd\"/>";
    g += "<text x=\"" + x + "\" y=\"" + Px(plot.bottom() + 15) + "\" text-anchor=\"middle\">" +
         Escape(svg::Label(t)) + "</text>";
  }
  g += "<rect x=\"" + Px(plot.left()) + "\" y=\"" + Px(plot.top()) + "\" width=\"" +
       Px(plot.right() - plot.left()) + "\" height=\"" + Px(plot.bottom() - plot.top()) +
       "\" fill=\"none\" stroke=\"#333\"/>";
  g += "<text x=\"" + Px((plot.left() + plot.right()) / 2) + "\" y=\"" + Px(o.height - 8) +
       "\" text-anchor=\"middle\">(simulated - observed) / sigma</text>";
  g += "</g>";
  plot.Raw(g);
  for (std::size_t k = 0; k < n; ++k) {
    const calibrate::ReachStatistic& s = result.statistics[k];
    const double yc = plot.top() + row * (static_cast<double>(k) + 0.5);
    const char* colour = s.at_edge() ? kAtEdge : s.in_reach() ? kInReach : kOutOfReach;
    plot.Text(plot.left() - 6, yc + 4, s.name(),
              std::string("text-anchor=\"end\" fill=\"") + colour + "\"");
    if (s.points_with_value > 0 && s.sigma > 0.0) {
      const double lo = Sigmas(s, s.min), hi = Sigmas(s, s.max);
      const double a = std::clamp(lo, -half, half), b = std::clamp(hi, -half, half);
      const double x0 = plot.X(a), x1 = std::max(plot.X(b), x0 + 2.0);
      plot.Raw("<rect x=\"" + Px(x0) + "\" y=\"" + Px(yc - 5) + "\" width=\"" + Px(x1 - x0) +
               "\" height=\"10\" fill=\"" + colour + "\" fill-opacity=\"0.55\"><title>" +
               Escape(s.name() + ": reached " + Show(s.min) + " to " + Show(s.max) + ", observed " +
                      Show(s.observed) + " +- " + Show(s.sigma)) +
               "</title></rect>");
      if (hi > half)
        plot.Text(plot.right() + 4, yc + 4, "to " + svg::Label(hi, 3), "fill=\"#555\"");
      else if (lo < -half)
        plot.Text(plot.right() + 4, yc + 4, "from " + svg::Label(lo, 3), "fill=\"#555\"");
    } else {
      plot.Text(plot.X(0.0) + 8, yc + 4, "no value", std::string("fill=\"") + kOutOfReach + "\"");
    }
    plot.Raw("<circle cx=\"" + Px(plot.X(0.0)) + "\" cy=\"" + Px(yc) +
             "\" r=\"3.5\" fill=\"#000\"/>");
  }
  return plot.Svg();
}

std::string ReachSection(const calibrate::ReachResult& r, const std::string& json_file) {
  auto ref = [&json_file](const std::string& pointer) { return html::Ref(json_file, pointer); };
  const int out = r.out_of_reach();
  const std::size_t n = r.statistics.size();
  std::string s = "<p class=\"verdict " + std::string(out == 0 ? "ok" : "bad") + "\">" +
                  std::to_string(n - static_cast<std::size_t>(out)) + " of " + std::to_string(n) +
                  " statistics in reach";
  int edge = 0;
  for (const calibrate::ReachStatistic& st : r.statistics) edge += st.at_edge() ? 1 : 0;
  if (edge > 0) s += " (" + std::to_string(edge) + " at the edge)";
  if (out > 0) {
    std::string names;
    for (const calibrate::ReachStatistic& st : r.statistics)
      if (!st.in_reach()) names += (names.empty() ? "" : ", ") + Escape(st.name());
    s += "; out of reach: " + names;
  }
  s += "</p>";
  s += "<p>Before fitting: " + std::to_string(r.points.size()) +
       " points of the calibration box (" +
       (r.design == calibrate::DesignKind::kHalton
            ? std::string("a shifted Halton sequence")
            : "a maximin Latin hypercube, best of " + std::to_string(r.candidates)) +
       ", seed " + std::to_string(r.design_seed) + "), each simulated with the same " +
       std::to_string(r.rocks) + " rocks (seed " + std::to_string(r.simulation_seed) +
       "). The statistics are the residuals of the misfit. A statistic is <em>in reach</em> "
       "when its observed value lies within [min &#8722; &#963;, max + &#963;] of the values "
       "the design reached, &#963; being the median of its residual's sigma over the points "
       "(measurement error, Monte Carlo error of the simulated value, sampling error of the "
       "observed one); <em>at the edge</em> when only that allowance puts it in reach. Out of "
       "reach means the model produces it nowhere in the box: widen the "
       "box, change the model (release, shapes, contact parameters) or question the "
       "observation. A calibration then gives a best compromise, not a fit.</p>";
  s += "<table><thead><tr>" + html::Th("statistic") + html::Th("observed") + html::Th("± sigma") +
       html::Th("reached min") + html::Th("reached max") + html::Th("closest (sigmas)") +
       html::Th("points") + html::Th("verdict") + "</tr></thead><tbody>";
  for (std::size_t k = 0; k < n; ++k) {
    const calibrate::ReachStatistic& st = r.statistics[k];
    auto cell = [&](const char* field, double v) {
      return std::isfinite(v) ? html::RefCell(ref(Pointer(k, field)), v, Show(v))
                              : html::Td("-", true);
    };
    s += "<tr>" + html::Td(st.name()) + cell("observed", st.observed) + cell("sigma", st.sigma) +
         cell("min", st.min) + cell("max", st.max) + cell("closest_sigmas", st.closest_sigmas) +
         html::Td(std::to_string(st.points_with_value), true) + "<td class=\"" +
         (st.at_edge()    ? "warn"
          : st.in_reach() ? "ok"
                          : "bad") +
         "\">" + Escape(calibrate::ReachVerdictText(st.verdict)) +
         (st.at_edge() ? " (at the edge)" : "") + "</td></tr>";
  }
  s += "</tbody></table>";
  s += html::Figure(ReachSvg(r),
                    "Per statistic, the range of values the design reached, in sigmas from the "
                    "observed value (the dot); the shaded band is &#177;1 &#963;, the tolerance "
                    "of the verdict. Green: in reach; orange: at the edge (in reach by that "
                    "band only); red: out of reach.",
                    640.0);
  if (r.best_point >= 0) {
    const calibrate::ReachPoint& b = r.points[static_cast<std::size_t>(r.best_point)];
    s += "<h3>Best design point</h3><table class=\"kv\">";
    s += html::Kv("Point", std::to_string(r.best_point) + " of " + std::to_string(r.points.size()));
    s +=
        html::Kv("Misfit", html::RefSpan(ref("/points/" + std::to_string(r.best_point) + "/misfit"),
                                         b.misfit, Show(b.misfit)));
    for (std::size_t p = 0; p < r.parameters.size(); ++p)
      s += html::Kv(r.parameters[p].label(),
                    html::RefSpan(ref("/points/" + std::to_string(r.best_point) + "/physical/" +
                                      std::to_string(p)),
                                  b.physical[p], Show(b.physical[p])) +
                        " (box " + Escape(Show(r.parameters[p].lower)) + " to " +
                        Escape(Show(r.parameters[p].upper)) + ")");
    s += "</table>";
  }
  return s;
}

std::string ReachHtmlReport(const StudyReportInput& in, const calibrate::ReachResult& result) {
  if (!in.scene) throw std::invalid_argument("ReachHtmlReport: the scene is required");
  html::Page page;
  page.title = "rockcal reach check: " + in.scene->name;
  page.heading_html = "Reach check: " + Escape(in.scene->name);
  page.lead_html = "Can the calibration box produce what was observed? " +
                   std::to_string(result.points.size()) + " design points of " +
                   std::to_string(result.rocks) + " rocks in " + Escape(Show(result.wall_seconds)) +
                   " s; " + std::to_string(result.out_of_reach()) + " of " +
                   std::to_string(result.statistics.size()) + " statistics out of reach.";
  page.note_html =
      "SI units (m, or a fraction). The machine-readable record is reach.json and reach.csv.";
  page.sections = {
      {"site", "Site", "",
       html::SiteTables(*in.scene, in.site_file, in.units) + html::SiteNotes(in.notes)},
      {"reach", "Reach", "", ReachSection(result)}};
  page.footer_html =
      "Generated by rockcal <code>rockcal study reach</code>, a rockfall simulator after CRSP-3D "
      "(FHWA-CFL/TD-12-007, 2012). Design seed " +
      std::to_string(result.design_seed) + ", simulation seed " +
      std::to_string(result.simulation_seed) +
      ". This file is self-contained: no scripts, no "
      "network.";
  return html::PageHtml(page);
}

}  // namespace rockcal::reports
