// The measured impacts section of report.html: the verdict on the rebounds,
// each impact's observed rebound against the distribution of its replays,
// and the rebound ratios against the impact angle (docs/field-campaigns.md,
// section 7).
#include <algorithm>
#include <cmath>

#include "rockcal/reports/impact_outputs.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

constexpr const char* kNormalColour = "#0072B2";
constexpr const char* kTangentialColour = "#D55E00";

// Each impact's observed rebound speed against the median speed of its
// replays, one robust spread above and below, on a 1:1 line.
std::string SpeedPlot(const observations::Misfit& fit) {
  std::vector<double> ox, sy;
  double lo = kInf, hi = -kInf;
  for (const observations::ImpactFit& f : fit.impacts) {
    const double o = f.observed.norm(), s = f.simulated.norm();
    ox.push_back(o), sy.push_back(s);
    lo = std::min({lo, o, s - f.speed_sd});
    hi = std::max({hi, o, s + f.speed_sd});
  }
  lo = std::max(0.0, lo);
  const double pad = 0.05 * (hi - lo > 0 ? hi - lo : 1.0);
  lo = std::max(0.0, lo - pad), hi += pad;
  svg::Plot::Options o;
  o.width = 360, o.height = 320, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
  o.title = "Impacts: observed rebound speed against the replays";
  svg::Plot plot(lo, hi, lo, hi, o);
  plot.Axes("observed rebound speed [m/s]", "replays' median [m/s]");
  plot.Polyline({lo, hi}, {lo, hi}, "stroke=\"#999\" stroke-dasharray=\"4 3\"");
  for (std::size_t k = 0; k < fit.impacts.size(); ++k)
    plot.Polyline({ox[k], ox[k]},
                  {sy[k] - fit.impacts[k].speed_sd, sy[k] + fit.impacts[k].speed_sd},
                  "stroke=\"" + std::string(kStopColour) + "\" stroke-width=\"1\"");
  plot.Points(ox, sy, 3.0, "fill=\"" + std::string(kStopColour) + "\"");
  return Figure(plot.Svg(),
                "Each impact's observed rebound speed against the median speed of its replays, "
                "with their robust spread above and below; a reproduced rebound lies on the 1:1 "
                "line within its bar.",
                360);
}

// The normal and tangential rebound ratios against the impact angle:
// observed (filled) and the replays' median with its spread (open, barred).
std::string RatioPlot(const observations::Misfit& fit) {
  double hi = 1.0, lo = 0.0;
  std::vector<double> angle, rn, rt, sn, st;
  for (const observations::ImpactFit& f : fit.impacts) {
    angle.push_back(f.incidence_deg);
    rn.push_back(f.normal_observed), sn.push_back(f.normal_simulated);
    const bool t = std::isfinite(f.tangential_observed) && f.tangential_sigma > 0;
    rt.push_back(t ? f.tangential_observed : std::nan(""));
    st.push_back(t ? f.tangential_simulated : std::nan(""));
    for (double v :
         {f.normal_observed, f.normal_simulated + f.normal_spread, t ? f.tangential_observed : 0.0,
          t ? f.tangential_simulated + f.tangential_spread : 0.0})
      hi = std::max(hi, v);
    for (double v :
         {f.normal_observed, f.normal_simulated - f.normal_spread, t ? f.tangential_observed : 0.0,
          t ? f.tangential_simulated - f.tangential_spread : 0.0})
      lo = std::min(lo, v);
  }
  svg::Plot::Options o;
  o.width = 420, o.height = 320, o.left = 58, o.right = 14, o.top = 14, o.bottom = 42;
  o.title = "Rebound ratios against the impact angle";
  svg::Plot plot(0.0, 90.0, lo, hi * 1.05, o);
  plot.Axes("impact angle from the ground's normal [deg]", "rebound ratio");
  for (std::size_t k = 0; k < fit.impacts.size(); ++k) {
    const observations::ImpactFit& f = fit.impacts[k];
    plot.Polyline({angle[k], angle[k]}, {sn[k] - f.normal_spread, sn[k] + f.normal_spread},
                  "stroke=\"" + std::string(kNormalColour) + "\" stroke-width=\"1\"");
    if (std::isfinite(st[k]))
      plot.Polyline({angle[k], angle[k]},
                    {st[k] - f.tangential_spread, st[k] + f.tangential_spread},
                    "stroke=\"" + std::string(kTangentialColour) + "\" stroke-width=\"1\"");
  }
  plot.Points(angle, sn, 3.5,
              "fill=\"white\" stroke=\"" + std::string(kNormalColour) + "\" stroke-width=\"1.2\"");
  plot.Points(
      angle, st, 3.5,
      "fill=\"white\" stroke=\"" + std::string(kTangentialColour) + "\" stroke-width=\"1.2\"");
  plot.Points(angle, rn, 3.0, "fill=\"" + std::string(kNormalColour) + "\"");
  plot.Points(angle, rt, 3.0, "fill=\"" + std::string(kTangentialColour) + "\"");
  plot.Legend(
      {{kNormalColour, "normal R_n", "point"}, {kTangentialColour, "tangential R_t", "point"}},
      true);
  return Figure(plot.Svg(),
                "Normal (R<sub>n</sub> = &#8722;v<sub>n,out</sub> / v<sub>n,in</sub>) and "
                "tangential (R<sub>t</sub> = v<sub>t,out</sub> / v<sub>t,in</sub>) rebound ratios "
                "about the ground's normal, against the impact angle: observed (filled) and the "
                "replays' median with its robust spread (open, barred).",
                420);
}

}  // namespace

std::string ImpactsSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const observations::Misfit& fit = rec.misfit_after;
  const std::string verdict = observations::ImpactVerdict(fit);
  const bool poor = verdict.rfind("rebounds NOT", 0) == 0;
  std::string s =
      "<p>" + Int(static_cast<long>(fit.impacts.size())) + " measured impacts, each replayed " +
      Int(fit.impacts.empty() ? 0 : fit.impacts.front().draws) +
      " times on the slope at the calibrated values (its rock set just clear of "
      "the ground on its incoming path, at its incoming velocity, in drawn "
      "orientations). " +
      (poor ? "<b>" : "") + Escape(Capitalised(verdict)) + (poor ? "</b>" : "") +
      ". Every impact's rebound, observed and replayed: " + "<code>impacts.csv</code>" + ".</p>";
  s += SpeedPlot(fit) + RatioPlot(fit);
  s += "<table><thead><tr>" + Th("impact") + Th("group") + Th("angle [deg]") +
       Th("observed speed") + Th("replays' median") + Th("spread") + Th("R_n observed") +
       Th("R_n replays") + Th("R_t observed") + Th("R_t replays") + Th("left the ground") +
       "</tr></thead><tbody>";
  for (std::size_t k = 0; k < fit.impacts.size(); ++k) {
    const observations::ImpactFit& f = fit.impacts[k];
    const std::string base = "/impacts/per_impact/" + Int(static_cast<long>(k)) + "/";
    const bool t = std::isfinite(f.tangential_observed) && f.tangential_sigma > 0;
    auto ratio = [](double v, double spread) {
      return FormatNumber(v, "%.3g") + " &#177; " + FormatNumber(spread, "%.2g");
    };
    s += "<tr>" + Td(f.id) + Td(c.scene.groups[static_cast<std::size_t>(f.group)].id) +
         RefCell(Ref("calibration.json", base + "incidence_deg"), f.incidence_deg,
                 FormatNumber(f.incidence_deg, "%.1f")) +
         Td(Speed(f.observed.norm(), rec.units), true) +
         Td(Speed(f.simulated.norm(), rec.units), true) + Td(Speed(f.speed_sd, rec.units), true) +
         RefCell(Ref("calibration.json", base + "normal_ratio/observed"), f.normal_observed,
                 FormatNumber(f.normal_observed, "%.3g")) +
         "<td class=\"n\">" + ratio(f.normal_simulated, f.normal_spread) + "</td>" +
         Td(t ? FormatNumber(f.tangential_observed, "%.3g") : std::string("-"), true) +
         (t ? "<td class=\"n\">" + ratio(f.tangential_simulated, f.tangential_spread) + "</td>"
            : Td("-", true)) +
         Td(Int(f.left) + " of " + Int(f.draws), true) + "</tr>";
  }
  s += "</tbody></table>";
  return s;
}

}  // namespace rockcal::reports::sections
