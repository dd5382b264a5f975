// The section of a simulation that drew its parameters from a calibration's
// posterior (rockcal simulate --parameters of a posterior): the draws, and
// the predictive bands of the runout and of each partition's statistics.
#include "sections.h"

namespace rockcal::reports::sections {

std::string PosteriorDrawsSection(const Context& c) {
  const calibrate::PosteriorRun& run = *c.in.posterior_run;
  const int draws = static_cast<int>(run.draws.size());
  int lo = draws ? run.draws.front().rocks : 0, hi = lo;
  for (const auto& d : run.draws) {
    lo = std::min(lo, d.rocks);
    hi = std::max(hi, d.rocks);
  }
  std::string s =
      run.class_draws
          ? "<p>The class values are not one set of values: " + Int(draws) +
                " parameter sets were drawn, each value uniformly within its class's interval "
                "(section <i>Values from the class table</i>), and rock <i>i</i> was simulated "
                "with set <i>i</i> mod " + Int(draws) +
                ", so every figure of this report carries the table's spread and the Monte Carlo "
                "variation together. draws.csv lists the sets. The bands below are the 5 % and "
                "95 % quantiles over the draws of each draw's statistic, each draw of " +
                (lo == hi ? Int(lo) : Int(lo) + " to " + Int(hi)) +
                " rocks (0 for a partition a draw's rocks did not reach)."
          : "<p>The parameters are not one set of values: " + Int(draws) +
      " parameter sets were drawn from the " + Int(run.samples) + " posterior samples of " +
      Escape(run.parameters.samples_file) + " (" + Escape(run.parameters.file) +
      "), and rock <i>i</i> was simulated with set <i>i</i> mod " + Int(draws) +
      ", so every figure of this report is of the posterior predictive: the calibration's "
      "uncertainty and the Monte Carlo variation together. draws.csv lists the sets. "
      "The bands below are the 5 % and 95 % quantiles over the draws of each draw's statistic, "
      "each draw of " + (lo == hi ? Int(lo) : Int(lo) + " to " + Int(hi)) +
      " rocks (0 for a partition a draw's rocks did not reach).";
  if (lo < 30)
    s += " <b>With fewer than 30 rocks per draw the bands are mostly the Monte Carlo variation "
         "of so few rocks</b>: give more rocks (--rocks) for bands of the parameters' "
         "uncertainty.";
  s += run.class_draws ? " The medians alone: --class-values median.</p>"
                       : " The point values alone: --point-values.</p>";
  s += DrawBandsTable(run.bands);
  if (!run.raster_bands.empty())
    s += "<p>The maps (rasters.tif, rasters/*.asc with --rasters) add the bands " +
         Escape("reach_probability_q05/_q95, energy_p95_q05/_q95, height_p95_q05/_q95") +
         ": per cell, the 5 % and 95 % quantiles over the draws of each draw's map.</p>";
  return s;
}

}  // namespace rockcal::reports::sections
