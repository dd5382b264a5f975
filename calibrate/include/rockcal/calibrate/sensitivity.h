// Global sensitivity analysis (`rockcal sensitivity`): which calibrated
// parameters move which simulated quantities, and by more than the Monte
// Carlo noise of one run?
//  - Generic estimators over a vector-valued model on the unit box [0, 1]^k:
//    Morris elementary effects (mu, mu*, sigma) and Sobol first-order and
//    total indices by Saltelli sampling, with bootstrap intervals. They know
//    nothing of rockfall and are tested against functions with exact answers.
//  - The site wrapper: the parameters are the site's "calibrate" bounds, the
//    outputs a list of named scalars of a simulation (bounce-height quantiles
//    and passing fraction per partition, runout quantiles, the share of rocks
//    stopped, the calibration misfit), every run with the same seed; and the
//    Monte Carlo noise of each output at the site's current parameters, so
//    each effect can be read against it.
// The result is a struct, read from and written to its JSON by to_json /
// from_json; the console report is written here; the files (JSON, CSV, the
// bar charts and report.html) by rockcal/reports/study_report.h. See
// calibrate/STUDIES.md for the formulas.
#ifndef ROCKCAL_CALIBRATE_SENSITIVITY_H_
#define ROCKCAL_CALIBRATE_SENSITIVITY_H_

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// A model on the unit box: k inputs in [0, 1], m outputs (always m values;
// NaN where an output has no value at that point, e.g. a quantile of no rocks).
using SensitivityModel = std::function<std::vector<double>(const std::vector<double>& unit_x)>;
// Called after each model run with (runs done, runs in all).
using SensitivityProgressFn = std::function<void(int done, int total)>;

enum class SensitivityMethod { kMorris, kSobol };
const char* SensitivityMethodToString(SensitivityMethod method);  // "morris", "sobol"
std::string SensitivityMethodNames();                          // "morris, sobol"
// Sets *method from its name; false for an unknown name.
bool StringToSensitivityMethod(const std::string& name, SensitivityMethod* method);

// ---- Morris elementary effects ------------------------------------------------

struct MorrisOptions {
  // r, the number of trajectories (one-at-a-time paths through the box); the
  // cost is r (k + 1) model runs. >= 2 (sigma needs two effects).
  int trajectories = 10;
  // p, the levels of the grid {0, 1/(p-1), ..., 1}; the step is
  // Delta = p / (2 (p - 1)) (2/3 for the default 4). Even, in [2, 100].
  int levels = 4;
  std::uint64_t seed = 1;          // of the trajectories' starts, directions and orders
  SensitivityProgressFn progress;  // may be empty

  // Checks each field; on failure sets *error naming the field, its value and
  // the rule, and returns false.
  bool IsValid(std::string* error) const;
};

// The elementary effects of one parameter on one output. An effect is
// (f(x + d Delta e_i) - f(x)) / (d Delta), d = +1 or -1: output units per
// full range of the parameter.
struct MorrisIndex {
  double mu = 0.0;       // mean effect (signed; NaN when no effect was finite)
  double mu_star = 0.0;  // mean |effect| (Campolongo et al. 2007)
  double sigma = 0.0;    // standard deviation of the effects (n - 1); NaN below 2
  int effects = 0;       // finite effects averaged (r when every output was finite)
};

struct MorrisResult {
  int parameters = 0, outputs = 0;
  int trajectories = 0, levels = 0;
  double delta = 0.0;
  int evaluations = 0;                          // r (k + 1)
  std::vector<std::vector<MorrisIndex>> index;  // [output][parameter]
};

// Runs the r trajectories of `options` through `model` (k inputs, m outputs),
// one run at a time in a fixed order, so the result depends on the seed
// only. Throws std::invalid_argument when the options are not valid, k < 1,
// m < 1, or the model returns other than m values.
MorrisResult RunMorris(int parameters, int outputs, const SensitivityModel& model,
                       const MorrisOptions& options);

// ---- Sobol indices (Saltelli sampling) ------------------------------------------

struct SobolOptions {
  // N, the rows of each of the sample matrices A and B; the cost is
  // N (k + 2) model runs. >= 4.
  int samples = 64;
  int bootstrap = 200;       // resamples of the N rows for the intervals; >= 20
  double confidence = 0.95;  // level of the bootstrap percentile intervals; in (0.5, 1)
  // Seed of A and B (pseudo-random, xoshiro256**) and of the bootstrap.
  std::uint64_t seed = 1;
  SensitivityProgressFn progress;  // may be empty

  bool IsValid(std::string* error) const;
};

struct SobolIndex {
  // First-order index S_i (Saltelli et al. 2010) and total index ST_i
  // (Jansen 1999), with the bootstrap percentile interval of each. NaN when
  // the output has no variance or fewer than 2 usable rows.
  double first = 0.0, first_low = 0.0, first_high = 0.0;
  double total = 0.0, total_low = 0.0, total_high = 0.0;
};

// How RunSobol draws the matrices A and B, in words (sensitivity.json's
// design.sampling).
constexpr const char* kSobolSampling = "pseudo-random (xoshiro256**), seeded";

struct SobolResult {
  int parameters = 0, outputs = 0;
  int samples = 0, bootstrap = 0;
  double confidence = 0.0;
  int evaluations = 0;                         // N (k + 2)
  std::vector<double> variance;                // [output] of the 2N values of f(A) and f(B)
  std::vector<int> rows;                       // [output] rows whose k + 2 values were all finite
  std::vector<std::vector<SobolIndex>> index;  // [output][parameter]
};

// Runs A, B and the k matrices A_B^(i) (A with column i from B) through
// `model`, one run at a time in a fixed order. A row with a non-finite value
// of an output is left out of that output's indices. Throws
// std::invalid_argument as RunMorris does.
SobolResult RunSobol(int parameters, int outputs, const SensitivityModel& model,
                     const SobolOptions& options);

// ---- A site -----------------------------------------------------------------------

// One named scalar of a simulation.
struct SiteOutput {
  std::string name;         // "BP-1.height.p90", "runout.p50", "stopped", "misfit"
  std::string unit;         // "m", "fraction", "" (the misfit)
  std::string description;  // one sentence
  std::function<double(const core::Scene&, const core::SimulationResult&)> compute;
};

// The outputs of a site: per partition the bounce-height p50 and p90 (rock
// centre above the ground, crossing rocks) and the passing fraction (of the
// released rocks); the runout p50 and p90 of the stopped rocks (along the
// observations' runout direction from their origin when `observations` gives
// a runout, else the stop x as in summary.json); the share of rocks stopped;
// and with `observations` the calibration misfit (observations::ComputeMisfit
// with `misfit`, as calibrate::Objective computes it).
std::vector<SiteOutput> SiteOutputs(const core::Scene& scene,
                                    const observations::Observations* observations,
                                    const observations::MisfitOptions& misfit = {});

struct SensitivityOptions {
  SensitivityMethod method = SensitivityMethod::kMorris;
  // Morris trajectories r or Sobol rows N; 0: the method's default (10 or 64).
  // When set: >= 2 for Morris, >= 4 for Sobol, <= 100000.
  int samples = 0;
  int levels = 4;            // Morris grid levels (see MorrisOptions)
  int bootstrap = 200;       // resamples for the Sobol intervals and for the noise; >= 20
  double confidence = 0.95;  // of the Sobol intervals; in (0.5, 1)
  // Seed of every simulation (common random numbers: each run releases the
  // same rocks the same way) and of the sampling; empty: the site's seed.
  std::optional<std::uint64_t> seed;
  int threads = 0;           // of each simulation; 0: OpenMP default; >= 0
  StudyProgressFn progress;  // after each simulation (may be empty)

  // The sample count in effect (samples, or the method's default).
  int EffectiveSamples() const;
  bool IsValid(std::string* error) const;
};

// An output as the study measured it at the site's current parameters.
struct SensitivityOutputInfo {
  std::string name, unit, description;
  double value = 0.0;  // at the site's current parameters (NaN: no value)
  // Monte Carlo noise: the bootstrap standard error of the output over the
  // run's rocks (resampled with replacement), output units; NaN: unknown.
  double noise = 0.0;
};

// One parameter against one output, for the table and the CSV.
struct SensitivityEntry {
  int parameter = 0, output = 0;
  MorrisIndex morris;  // Morris only
  SobolIndex sobol;    // Sobol only
  // Morris: mu* over the noise of one elementary effect, sqrt(2) noise / Delta
  // (two runs a step Delta apart); pure noise gives about 0.8.
  // Sobol: the standard deviation of the output the parameter causes alone,
  // sqrt(S_i V), over the noise. NaN when unknown.
  double effect_over_noise = 0.0;
};

// An effect stands out of the Monte Carlo noise when its effect_over_noise
// is at least this (sensitivity.json's "resolved_ratio").
constexpr double kResolvedEffectOverNoise = 2.0;

struct SensitivityResult {
  std::string site;  // the scene's name
  SensitivityMethod method = SensitivityMethod::kMorris;
  int samples = 0;  // r or N
  std::uint64_t seed = 0;
  int rocks = 0, threads = 0;
  std::vector<Parameter> parameters;
  std::vector<double> current;  // physical values at the site (clamped into the bounds)
  std::vector<SensitivityOutputInfo> outputs;
  MorrisResult morris;                    // method morris
  SobolResult sobol;                      // method sobol
  std::vector<SensitivityEntry> entries;  // parameter-major: [p * outputs + o]
  int simulations = 0;                    // the design's runs + 1 at the current parameters
  double wall_seconds = 0.0;              // the whole study
  double simulation_seconds = 0.0;        // inside the simulations
  int non_finite_runs = 0;                // runs with a rock in a non-finite state
  std::vector<std::string> notes;
  std::string summary;  // one sentence: what ran, how long, what stands out of the noise

  const SensitivityEntry& at(int parameter, int output) const {
    return entries[static_cast<std::size_t>(parameter) * outputs.size() +
                   static_cast<std::size_t>(output)];
  }
  // Morris: the noise of one elementary effect of `output`, sqrt(2) noise /
  // Delta (two runs a step Delta apart).
  double EffectNoise(std::size_t output) const;
  double SimulationsPerSecond() const;  // simulations / wall_seconds
};

// Runs the study on `site` (its scene with the run's rock count; the
// parameters are its "calibrate" bounds) with the outputs of SiteOutputs.
// Throws InputError when the site has no calibrate bounds, and
// std::invalid_argument when the options are not valid.
SensitivityResult RunSensitivity(const sites::Site& site,
                                 const observations::Observations* observations,
                                 const SensitivityOptions& options);

// sensitivity.json (calibrate/src/sensitivity_json.cc; reports/ writes the file
// and its CSV).
void to_json(nlohmann::json& j, const SensitivityResult& result);
void from_json(const nlohmann::json& j, SensitivityResult& result);
// A human table (one line per parameter and output, then the summary).
std::string SensitivityReport(const SensitivityResult& result);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_SENSITIVITY_H_
