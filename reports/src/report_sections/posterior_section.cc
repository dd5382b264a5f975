// The posterior section of report.html (rockcal calibrate --posterior): the
// intervals of the calibrated values, the pairwise plot of the posterior
// samples, and the posterior predictive bands of the compared statistics.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "rockcal/reports/calibration_outputs.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

using calibrate::PosteriorResult;

std::string Num(double v) { return FormatNumber(v, "%.4g"); }

// The pairwise plot: marginal histograms on the diagonal, the samples'
// scatter below it and their correlation above it, in the unit box of each
// parameter's bounds (the prior); the calibrated values as a red cross.
std::string PairwisePlot(const PosteriorResult& post, const std::vector<double>& calibrated) {
  const auto& ps = post.space.parameters();
  const int d = static_cast<int>(ps.size());
  const double cell = d <= 3 ? 130.0 : d <= 5 ? 105.0 : 80.0;
  const double margin = 26.0, gap = 6.0;
  const double size = margin + d * cell + 4.0;
  const double height = d * cell + 20.0;
  char buf[256];
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Px(size) + "\" height=\"" +
                  Px(height) + "\" viewBox=\"0 0 " + Px(size) + " " + Px(height) +
                  "\" role=\"img\"><title>Pairwise plot of the posterior samples</title>";
  // At most 800 points per panel, evenly through the samples.
  const std::size_t n = post.samples.size();
  const std::size_t stride = std::max<std::size_t>(1, n / 800);
  auto unit = [&](std::size_t sample, int k) {
    const auto& p = ps[static_cast<std::size_t>(k)];
    return (post.samples[sample][static_cast<std::size_t>(k)] - p.lower) / (p.upper - p.lower);
  };
  for (int row = 0; row < d; ++row)
    for (int col = 0; col < d; ++col) {
      const double x0 = margin + col * cell + gap / 2, y0 = row * cell + gap / 2;
      const double w = cell - gap;
      std::snprintf(buf, sizeof buf,
                    "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#fafafa\" "
                    "stroke=\"#bbb\" stroke-width=\"0.8\"/>",
                    x0, y0, w, w);
      s += buf;
      if (row == col) {
        const int bins = 20;
        std::vector<double> counts(bins, 0.0);
        for (std::size_t i = 0; i < n; ++i)
          counts[static_cast<std::size_t>(std::clamp(static_cast<int>(unit(i, col) * bins), 0, bins - 1))] += 1;
        const double top = *std::max_element(counts.begin(), counts.end());
        for (int b = 0; b < bins; ++b) {
          const double h = top > 0 ? counts[static_cast<std::size_t>(b)] / top * (w - 4) : 0.0;
          std::snprintf(buf, sizeof buf,
                        "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" "
                        "fill=\"#6b8fb3\"/>",
                        x0 + b * w / bins, y0 + w - h, w / bins, h);
          s += buf;
        }
        const auto& q = post.parameters[static_cast<std::size_t>(col)];
        const auto& p = ps[static_cast<std::size_t>(col)];
        for (double v : {q.p05, q.p95}) {
          const double x = x0 + (v - p.lower) / (p.upper - p.lower) * w;
          std::snprintf(buf, sizeof buf,
                        "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#333\" "
                        "stroke-dasharray=\"3 2\"/>",
                        x, y0, x, y0 + w);
          s += buf;
        }
      } else if (row > col) {
        for (std::size_t i = 0; i < n; i += stride) {
          std::snprintf(buf, sizeof buf,
                        "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"1.1\" fill=\"%s\" fill-opacity=\"0.35\"/>",
                        x0 + unit(i, col) * w, y0 + (1.0 - unit(i, row)) * w, kStopColour);
          s += buf;
        }
      } else {
        const double c = post.correlation[static_cast<std::size_t>(row)][static_cast<std::size_t>(col)];
        std::snprintf(buf, sizeof buf,
                      "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"%d\" "
                      "fill=\"%s\">%+.2f</text>",
                      x0 + w / 2, y0 + w / 2 + 5, std::abs(c) >= 0.7 ? 16 : 12,
                      std::abs(c) >= 0.7 ? "#b2182b" : "#555", c);
        s += buf;
      }
      if (row != col && calibrated.size() == ps.size()) {
        const auto& pc = ps[static_cast<std::size_t>(col)];
        const auto& pr = ps[static_cast<std::size_t>(row)];
        if (row > col) {
          const double cx = x0 + (calibrated[static_cast<std::size_t>(col)] - pc.lower) / (pc.upper - pc.lower) * w;
          const double cy = y0 + (1.0 - (calibrated[static_cast<std::size_t>(row)] - pr.lower) / (pr.upper - pr.lower)) * w;
          std::snprintf(buf, sizeof buf,
                        "<path d=\"M%.1f %.1fl8 8m0 -8l-8 8\" stroke=\"%s\" stroke-width=\"1.8\"/>",
                        cx - 4, cy - 4, kFenceColour);
          s += buf;
        }
      }
    }
  // Labels: each parameter under its column and beside its row.
  const int font = d > 5 ? 7 : 10;  // the labels fit their cells
  for (int k = 0; k < d; ++k) {
    std::snprintf(buf, sizeof buf, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"%d\">",
                  margin + k * cell + cell / 2, d * cell + 14.0, font);
    s += buf + Escape(ps[static_cast<std::size_t>(k)].label()) + "</text>";
    std::snprintf(buf, sizeof buf,
                  "<text x=\"14\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"%d\" "
                  "transform=\"rotate(-90 14 %.1f)\">",
                  k * cell + cell / 2, font, k * cell + cell / 2);
    s += buf + Escape(ps[static_cast<std::size_t>(k)].label()) + "</text>";
  }
  return s + "</svg>";
}

// One observation's predictive bands: per quantity the 5-95 % band of a new
// observation (thin), of the simulated statistic (thick), its median and the
// observed value.
std::string BandPlot(const std::string& label, const std::vector<const calibrate::PredictiveBand*>& bands) {
  double lo = kInf, hi = -kInf;
  for (const auto* b : bands)
    lo = std::min({lo, b->new_p05, b->p05, b->observed}),
    hi = std::max({hi, b->new_p95, b->p95, b->observed});
  const double pad = 0.06 * (hi - lo > 0 ? hi - lo : 1.0);
  svg::Plot::Options o;
  o.width = 360, o.height = 240, o.left = 58, o.right = 12, o.top = 14, o.bottom = 42;
  o.title = "Posterior predictive bands: " + label;
  for (std::size_t k = 0; k < bands.size(); ++k)
    o.x_ticks.push_back({static_cast<double>(k), bands[k]->id.quantity()});
  svg::Plot plot(-0.6, static_cast<double>(bands.size()) - 0.4, lo - pad, hi + pad, o);
  const bool fraction =
      !bands.empty() && (bands[0]->id.statistic == observations::Statistic::kFraction ||
                         bands[0]->id.statistic == observations::Statistic::kShare);
  plot.Axes("quantity", fraction ? "value" : "value [m]");
  std::vector<double> xs, med, obs_in, x_in, obs_out, x_out;
  for (std::size_t k = 0; k < bands.size(); ++k) {
    const double x = static_cast<double>(k);
    plot.Polyline({x, x}, {bands[k]->new_p05, bands[k]->new_p95},
                  "stroke=\"#969696\" stroke-width=\"2\"");
    plot.Polyline({x, x}, {bands[k]->p05, bands[k]->p95},
                  "stroke=\"#9ecae1\" stroke-width=\"9\"");
    xs.push_back(x), med.push_back(bands[k]->median);
    (bands[k]->inside() ? x_in : x_out).push_back(x);
    (bands[k]->inside() ? obs_in : obs_out).push_back(bands[k]->observed);
  }
  plot.Points(xs, med, 2.0, "fill=\"#2171b5\"");
  plot.Points(x_in, obs_in, 3.5, "fill=\"none\" stroke=\"#000\" stroke-width=\"1.5\"");
  plot.Points(x_out, obs_out, 3.5, "fill=\"none\" stroke=\"" + std::string(kFenceColour) + "\" stroke-width=\"2\"");
  return plot.Svg();
}

}  // namespace

std::string PosteriorSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  const PosteriorResult& post = *rec.posterior;
  const auto& ps = rec.space.parameters();
  const std::vector<double>& calibrated = rec.best_method().best;
  std::string s =
      "<p>The posterior of the calibrated values under a uniform prior on their bounds: the "
      "misfit is a Gaussian log-likelihood in units of each residual's uncertainty "
      "(observation and Monte Carlo error together), sampled on a Gaussian-process emulator of "
      "the residuals (" +
      Int(post.emulated) + " evaluations, " + Int(post.reused) +
      " of them the reach design's) by adaptive Metropolis (" +
      Int(static_cast<long>(post.samples.size())) + " samples, max R-hat " +
      FormatNumber(post.max_rhat, "%.3f") +
      "). posterior.csv holds the samples. A value whose interval is about as wide as its "
      "bounds is not determined by these observations.</p>";
  // The family's figures: docs/posterior.md, "How honest the intervals are"
  // (measured 2026-12-07; bench/README.md holds each row).
  s += "<p>How honest such intervals are, measured on the project's scene family of twin "
       "experiments (truths drawn from the prior, fields simulated with their measurement "
       "errors, ten settings of observation kinds, counts, errors and materials: 1060 "
       "intervals): the 90 % intervals held the truth 89.0 % of the time (84-94 % per "
       "setting) and the truth's rank among the posterior's samples was uniform "
       "(simulation-based calibration); for truths in the outer tenth of a range 79-81 % (an "
       "exact posterior: about 84 %). The model's own error is not in them: the predictive "
       "bands below are the check (docs/posterior.md, \"How honest the intervals are\").</p>";
  if (post.left_out > 0)
    s += "<p>The likelihood leaves out the " + Int(post.left_out) +
         " per-run residuals: the pooled runout quantiles compare the same stops, which would "
         "otherwise count twice (docs/posterior.md, \"Tracked runs\").</p>";
  if (!post.message.empty()) s += "<p class=\"warn\"><b>Warning:</b> " + Escape(post.message) + "</p>";
  if (const std::string advice = PosteriorAdvice(rec); !advice.empty())
    s += "<p class=\"warn\">" + Escape(advice) + "</p>";
  s += "<table><thead><tr>" + Th("parameter") + Th("calibrated") + Th("posterior median") +
       Th("5 %") + Th("95 %") + Th("interval / prior") + Th("determined") + Th("R-hat") +
       "</tr></thead><tbody>";
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const auto& q = post.parameters[k];
    s += "<tr>" + Td(ps[k].label()) + Td(Num(calibrated[k]), true) + Td(Num(q.median), true) +
         Td(Num(q.p05), true) + Td(Num(q.p95), true) + Td(FormatNumber(q.width_share, "%.2f"), true) +
         Td(q.undetermined ? "no" : "yes") + Td(FormatNumber(q.rhat, "%.3f"), true) + "</tr>";
  }
  s += "</tbody></table>";
  s += "<h3>Pairwise plot</h3><p>Each panel spans the parameters' bounds. Diagonal: the marginal "
       "posterior of each value (dashed: its 5 % and 95 % quantiles). Below it: the samples of "
       "each pair (red cross: the calibrated values). Above it: their correlation (red when "
       "0.7 or more in size: the pair is determined only together).</p>";
  s += Figure(PairwisePlot(post, calibrated), "Posterior samples, pair by pair", 0);
  if (!post.bands.empty()) {
    const int inside = post.BandsInside();
    s += "<h3>Posterior predictive bands</h3><p>" + Int(post.band_draws) +
         " posterior draws, each simulated at its own seed with " + Int(post.band_rocks) +
         " rocks. Thick bars: the 5-95 % band of the simulated statistic (the parameters' "
         "uncertainty and the Monte Carlo variation together); dots: its median. Thin bars: the "
         "5-95 % band of a new observation (the same draws with each residual's observation, "
         "sampling and Monte Carlo error about them: the misfit's own likelihood), against which "
         "the observed values (rings) are read, red outside. Under the model 90 % or a little "
         "more (the draws fitted the same data) fall inside: " +
         Int(inside) + " of " + Int(static_cast<long>(post.bands.size())) +
         " observed statistics do.</p><ul class=\"legend\">" +
         LegendItem(Swatch("#9ecae1", "bar"), "5-95 % band of the simulated statistic") +
         LegendItem(Swatch("#969696", "bar"), "5-95 % band of a new observation") +
         LegendItem(Swatch("#2171b5", "point"), "median") +
         LegendItem(Swatch("#000", "ring"), "observed, inside") +
         LegendItem(Swatch(kFenceColour, "ring"), "observed, outside") +
         "</ul><div class=\"figs\">";
    std::vector<observations::ResidualId> observed;
    std::map<observations::ResidualId, std::vector<const calibrate::PredictiveBand*>> by;
    for (const auto& b : post.bands) {
      if (!by.count(b.id.observation_id())) observed.push_back(b.id.observation_id());
      by[b.id.observation_id()].push_back(&b);
    }
    for (const observations::ResidualId& of : observed)
      s += Figure(BandPlot(of.observation(), by[of]), "<b>" + Escape(of.observation()) + "</b>",
                  360);
    s += "</div><table><thead><tr>" + Th("observation") + Th("quantity") + Th("observed") +
         Th("5 %") + Th("median") + Th("95 %") + Th("new observation 5 %") +
         Th("new observation 95 %") + Th("inside") + "</tr></thead><tbody>";
    for (const auto& b : post.bands)
      s += "<tr>" + Td(b.id.observation()) + Td(b.id.quantity()) + Td(Num(b.observed), true) +
           Td(Num(b.p05), true) + Td(Num(b.median), true) + Td(Num(b.p95), true) +
           Td(Num(b.new_p05), true) + Td(Num(b.new_p95), true) + Td(b.inside() ? "yes" : "no") +
           "</tr>";
    s += "</tbody></table>";
  }
  if (!post.statistic_bands.empty())
    s += "<h3>Predictive bands of the runout and of every partition</h3><p>The same " +
         Int(post.band_draws) +
         " draws: per draw the runout quantiles of its stopped rocks and, at every partition, "
         "the share of its rocks that passed and their height, velocity and energy (0 where "
         "none passed); the 5 % and 95 % quantiles over the draws, as rockcal simulate "
         "--parameters of this folder gives them for a new release or slope.</p>" +
         DrawBandsTable(post.statistic_bands);
  return s;
}

}  // namespace rockcal::reports::sections
