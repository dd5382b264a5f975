// The tracks section of report.html: the tracked runs' jump heights, jump
// lengths and impact speeds against those of their groups' simulated rocks
// at the calibrated values, measured alike (docs/field-campaigns.md,
// section 6), and the verdict on them.
#include <algorithm>
#include <cmath>

#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// The share of values at or below each value: an empirical distribution
// function's steps.
void Cumulative(const std::vector<double>& sorted, std::vector<double>* xs,
                std::vector<double>* ys) {
  const double n = static_cast<double>(sorted.size());
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    xs->push_back(sorted[k]);
    ys->push_back(static_cast<double>(k) / n);
    xs->push_back(sorted[k]);
    ys->push_back(static_cast<double>(k + 1) / n);
  }
}

// The observed and simulated distributions of one quantity (ascending), as
// two distribution functions on one plot.
std::string DistributionPlot(const std::vector<double>& observed,
                             const std::vector<double>& simulated, const std::string& what,
                             const std::string& unit) {
  double lo = kInf, hi = -kInf;
  for (const std::vector<double>* v : {&observed, &simulated})
    if (!v->empty()) lo = std::min(lo, v->front()), hi = std::max(hi, v->back());
  if (!(hi >= lo)) return "";
  const double pad = 0.05 * (hi - lo > 0 ? hi - lo : 1.0);
  svg::Plot::Options o;
  o.width = 360, o.height = 250, o.left = 50, o.right = 14, o.top = 14, o.bottom = 42;
  o.title = "Tracks: " + what + ", observed and simulated";
  svg::Plot plot(std::max(0.0, lo - pad), hi + pad, 0.0, 1.0, o);
  plot.Axes(what + " [" + unit + "]", "share at or below");
  std::vector<double> sx, sy, ox, oy;
  Cumulative(simulated, &sx, &sy);
  Cumulative(observed, &ox, &oy);
  plot.Polyline(sx, sy, "stroke=\"" + std::string(svg::Colour(1)) + "\" stroke-width=\"1.6\"");
  plot.Polyline(ox, oy, "stroke=\"#000\" stroke-width=\"1.6\"");
  plot.Legend({{"#000", "observed (" + Int(static_cast<long>(observed.size())) + ")"},
               {svg::Colour(1), "simulated (" + Int(static_cast<long>(simulated.size())) + ")"}},
              true);
  return Figure(plot.Svg(),
                "The " + Escape(what) +
                    " of the tracks' flights (black) and of the simulated rocks' flights, measured "
                    "alike (orange): the share of values at or below each value.",
                360);
}

}  // namespace

std::string TracksSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const observations::Misfit& fit = rec.misfit_after;
  const observations::TrackFit& t = fit.tracks;
  const observations::FitVerdict v = observations::AssessTracks(fit);
  std::string s = "<p>" + Int(t.tracks) +
                  " tracked paths, their flights found where the path leaves its free-flight "
                  "parabola, against the flights of the " +
                  Int(t.rocks) +
                  " simulated rocks of the tracked runs' groups at the calibrated values, sampled "
                  "and measured alike. " +
                  (v.poor ? "<b>" + Escape(Capitalised(observations::TracksVerdictSentence(fit))) +
                                ".</b> The calibrated values do not reproduce the observed jumps."
                          : Escape(Capitalised(observations::TracksVerdictSentence(fit))) + ".") +
                  "</p>";
  s += "<table><thead><tr>" + Th("quantity") + Th("side") + Th("flights or impacts");
  for (const double level : observations::Tracks::Levels()) s += Th(observations::LevelName(level));
  s += "</tr></thead><tbody>";
  struct Row {
    const char* name;
    const char* key;
    const std::vector<double>* observed;
    const std::vector<double>* simulated;
    bool length;
  };
  const Row rows[] = {
      {"jump height", "jump_height_m", &t.observed_heights, &t.simulated_heights, true},
      {"jump length", "jump_length_m", &t.observed_lengths, &t.simulated_lengths, true},
      {"impact speed", "impact_speed_m_s", &t.observed_speeds, &t.simulated_speeds, false}};
  for (const Row& row : rows)
    for (const bool observed : {true, false}) {
      const std::vector<double>& values = observed ? *row.observed : *row.simulated;
      const std::string base =
          std::string("/tracks/") + row.key + (observed ? "/observed/" : "/simulated/");
      s += "<tr>" + Td(row.name) + Td(observed ? "observed" : "simulated") +
           RefCell(Ref("calibration.json", base + "n"), static_cast<double>(values.size()),
                   Int(static_cast<long>(values.size())));
      for (const double level : observations::Tracks::Levels()) {
        if (values.empty()) {
          s += Td("-", true);
          continue;
        }
        const double q = core::Quantile(values, level);
        s += RefCell(Ref("calibration.json", base + observations::LevelName(level)), q,
                     row.length ? SiteLength(q, rec.units) : Show(q) + " m/s");
      }
      s += "</tr>";
    }
  s += "</tbody></table>";
  s += DistributionPlot(t.observed_heights, t.simulated_heights, "jump height", "m");
  s += DistributionPlot(t.observed_lengths, t.simulated_lengths, "jump length", "m");
  return s;
}

}  // namespace rockcal::reports::sections
