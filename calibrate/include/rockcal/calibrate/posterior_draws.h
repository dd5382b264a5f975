// A simulation that carries a calibration's uncertainty: rockcal simulate
// --parameters of a calibration with a posterior (rockcal calibrate
// --posterior) simulates its rocks in D turns, rock i with the D posterior
// draws' (i mod D)-th parameter set, so that the run is one of the posterior
// predictive (every rock keeps its index and random stream: the releases
// are those of a run at the calibrated values, at the same seed). Each
// draw's rocks give its own statistics and maps; their 5 % and 95 %
// quantiles over the draws are the predictive bands, from the parameters'
// uncertainty and the Monte Carlo variation of R / D rocks together.
// See docs/posterior.md.
#ifndef ROCKCAL_CALIBRATE_POSTERIOR_DRAWS_H_
#define ROCKCAL_CALIBRATE_POSTERIOR_DRAWS_H_

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/default_table.h"
#include "rockcal/core/rasters.h"
#include "rockcal/core/simulate.h"

namespace rockcal::calibrate {

// Options of SimulatePosteriorDraws. Defaults in brackets.
struct PosteriorDrawOptions {
  // Parameter sets drawn from the posterior samples (without replacement),
  // each simulating every draws-th rock [20], in [1, 10000]; at most the
  // rocks simulated and the samples held.
  int draws = 20;
  // Draws the samples (the run's seed: the simulation's own) [1].
  std::uint64_t seed = 1;

  bool IsValid(std::string* error) const;
};

// `draws` distinct sample indices in [0, samples), from a random stream of
// `seed` (a partial Fisher-Yates shuffle): the same at any thread count.
std::vector<int> DrawSampleIndices(int samples, int draws, std::uint64_t seed);

// One posterior draw of a run.
struct PosteriorDraw {
  int sample = 0;              // its index among the samples (line sample + 2 of posterior.csv)
  std::vector<double> values;  // SI, in the order of the parameters
  int rocks = 0;               // rocks draw, draw + D, draw + 2 D, ... of the run
  core::ResultStats stats;     // of its rocks
};

// One statistic's band over the draws: the 5 %, 50 % and 95 % quantiles
// (type 7) of the draws' values.
struct DrawBand {
  std::string where;     // "runout" or a partition id
  std::string quantity;  // "x_m.p50", "passed_fraction", "height_m.p95", "energy_kj.max", ...
  std::string unit;      // "m", "1", "kJ", "m/s"
  double p05 = 0.0, median = 0.0, p95 = 0.0;
};

// One statistic of one draw (a DrawBand's where, quantity and unit) and its value.
struct DrawValue {
  std::string where, quantity, unit;
  double value = 0.0;
};

// The statistics the bands are of, from one draw's `stats` (core::ComputeStats
// of `scene`, its partitions) and its `rocks`: the runout quantiles (p50,
// p90, p95, max of the stopped rocks' x), and per partition the share of
// the rocks that passed and the height, velocity and energy (p50, p95, max;
// 0 where none passed).
std::vector<DrawValue> DrawStatistics(const core::Scene& scene, const core::ResultStats& stats,
                                      int rocks);
// Per statistic (by where and quantity, in the order first met) the band
// over the draws' values.
std::vector<DrawBand> BandsOverDraws(const std::vector<std::vector<DrawValue>>& draws);
// The bands as JSON: {"runout": {"x_m": {"p50": {"p05", "median", "p95"},
// ...}}, "partitions": [{"id", "passed_fraction": {...}, "height_m": {...},
// ...}]}.
nlohmann::json DrawBandsJson(const std::vector<DrawBand>& bands);

struct PosteriorRun {
  CalibratedSite parameters;  // the parameters file read (point values and posterior)
  // The sets were drawn from a class table's intervals (class_draws.h), not
  // from a posterior's samples: parameters.file names the table.
  bool class_draws = false;
  int samples = 0;            // in its samples' file
  std::vector<PosteriorDraw> draws;
  // Every rock of the run in rock order, rock i simulated with draw i mod D's values.
  core::SimulationResult pooled;
  // DrawStatistics of each draw's rocks, each as a band over the draws
  // (BandsOverDraws).
  std::vector<DrawBand> bands;
  // The maps' bands when the scene records passages (else empty): per
  // cell, the 5 % and 95 % quantiles over the draws of each draw's
  // reach_probability, energy_p95 and height_p95 (core::ComputeRasters of
  // the draw's rocks; a draw that sent no rock over a cell counts 0 there:
  // NaN only where no draw did or the terrain has a hole), named
  // <band>_q05 and <band>_q95.
  std::vector<core::RasterBand> raster_bands;
};

// The scene of one parameter set: the site with `values` applied (and
// whatever else the caller sets: rocks, seed, recording), the same rocks
// for every set.
using SceneForValues = std::function<core::Scene(const CalibratedSite& values)>;

// Draws options.draws parameter sets from `samples` (ReadPosteriorSamples
// of `parameters`) and simulates rock i of scene_for's scenes with set
// i mod D; fills the pooled result, each draw's statistics and the bands.
// Throws InputError (naming `what_draws`, e.g. "argument --draws") when
// there are fewer rocks or samples than draws.
PosteriorRun SimulatePosteriorDraws(const CalibratedSite& parameters,
                                    const std::vector<std::vector<double>>& samples,
                                    const PosteriorDrawOptions& options,
                                    const SceneForValues& scene_for, const std::string& what_draws,
                                    const core::ProgressFn& progress = nullptr);

// summary.json's "parameters" of a posterior run: the file, "use":
// "posterior draws", the samples, draws, rocks per draw, and the bands
// (DrawBandsJson).
nlohmann::json PosteriorRunJson(const PosteriorRun& run);
// draws.csv: draw, sample, rocks, then a column per parameter label (SI).
std::string DrawsCsv(const PosteriorRun& run);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_POSTERIOR_DRAWS_H_
