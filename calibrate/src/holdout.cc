// K-fold cross-validation of a calibration (calibration_run.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/observations.h"
#include "rockcal/parallel/parallel.h"

namespace rockcal::calibrate {

HoldoutSummary CrossValidate(const sites::Site& site, const observations::Observations& obs,
                             const CalibrationOptions& options, int folds,
                             const CalibrationCallbacks& callbacks) {
  CheckCalibration(site, options);
  HoldoutSummary out;
  out.folds = folds;
  out.seed = options.seed ? *options.seed : site.scene.options.seed;
  const std::vector<observations::Fold> split = observations::MakeFolds(obs, folds, out.seed);
  out.repeat_scatter = observations::RunRepeatScatter(obs, site.scene);
  std::vector<double> errors;
  for (const observations::Fold& fold : split) {
    FoldResult r;
    r.fold = fold.index + 1;
    for (const auto& s : fold.scars) r.held_out_values += static_cast<int>(s.size());
    r.held_out_values += static_cast<int>(fold.runout.size() + fold.impacts.size());
    CalibrationOptions o = options;
    o.posterior.reset();  // the folds check the point estimate only
    // Each fold searches as the full calibration does, reach check and race
    // included, on its own part of the observations: a fold that started
    // from the full run's values would have seen its held-out blocks.
    o.observations_subset = "fold " + std::to_string(r.fold) + " of " + std::to_string(folds) +
                            ", seed " + std::to_string(out.seed);
    if (!options.log_path.empty())
      o.log_path = (std::filesystem::path(options.log_path).parent_path() /
                    ("evaluations-fold-" + std::to_string(r.fold) + ".jsonl"))
                       .string();
    // A run stopped before this fold began left no log of it: start it afresh.
    o.resume = options.resume && !o.log_path.empty() && std::filesystem::exists(o.log_path);
    const CalibrationSummary cal =
        Calibrate(site, observations::Subset(obs, fold, false), o, callbacks);
    const ScoreSummary score =
        Score(cal.calibrated, observations::Subset(obs, fold, true), options.misfit);
    r.in_sample_misfit = cal.misfit_after.value;
    r.held_out_misfit = score.misfit.value;
    r.calibrated = cal.best_method().best;
    r.termination = cal.termination;
    std::vector<double> gaps;
    if (!score.misfit.runs.empty()) {
      // Tracked runs: the mean over the held-out runs of |median simulated
      // runout of the run's group - the run's runout|.
      r.runout_error_m = score.misfit.MeanRunError();
      errors.push_back(*r.runout_error_m);
    }
    for (const observations::Residual& res : score.misfit.residuals)
      if (score.misfit.runs.empty())
        if (res.id.kind == observations::ObservationKind::kRunoutDistance &&
            res.id.statistic != observations::Statistic::kMax)
          gaps.push_back(std::abs(res.simulated - res.observed));
    if (!gaps.empty()) {
      std::sort(gaps.begin(), gaps.end());
      const std::size_t m = gaps.size() / 2;
      r.runout_error_m = gaps.size() % 2 ? gaps[m] : 0.5 * (gaps[m - 1] + gaps[m]);
      errors.push_back(*r.runout_error_m);
    }
    out.mean_in_sample_misfit += r.in_sample_misfit / folds;
    out.mean_held_out_misfit += r.held_out_misfit / folds;
    out.results.push_back(std::move(r));
  }
  if (!errors.empty()) {
    double sum = 0.0;
    for (double e : errors) sum += e;
    out.mean_runout_error_m = sum / static_cast<double>(errors.size());
  }
  return out;
}

}  // namespace rockcal::calibrate
