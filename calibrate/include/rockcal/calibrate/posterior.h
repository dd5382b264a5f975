// The posterior of the calibrated values, p(theta | observations), under a
// uniform prior on the calibration box: the misfit is a Gaussian
// log-likelihood in units of sigma (half the sum of the squared residuals,
// each scaled by the observation's error and the simulation's Monte Carlo
// error), so p(theta | obs) ~ exp(-misfit(theta)); with
// PosteriorOptions::sigma_log_term, exp(-misfit(theta) - log_scale(theta)),
// the sigmas' log term (Misfit::log_scale) that moves with theta too.
// Each simulation is expensive and noisy, so the residuals are emulated
// (emulator.h) over the evaluations already made, a space-filling design
// and points added where the posterior mass is; the posterior is sampled on
// the emulator by adaptive Metropolis, the emulator's variance added to
// each residual's (Kennedy & O'Hagan 2001). See docs/posterior.md.
#ifndef ROCKCAL_CALIBRATE_POSTERIOR_H_
#define ROCKCAL_CALIBRATE_POSTERIOR_H_

#include <Eigen/Dense>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/calibrate/emulator.h"
#include "rockcal/calibrate/mcmc.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/posterior_draws.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// ---- The posterior of a calibration --------------------------------------------

// Options of SamplePosterior. Defaults in brackets.
struct PosteriorOptions {
  // Emulated points the first emulator needs, evaluations reused included:
  // a maximin Latin hypercube tops them up to this many; 0: 6 (d + 1) [0].
  int design_points = 0;
  // Refining rounds, at most: each samples the emulator, then simulates the
  // posterior samples where the emulator is least sure, and refits; they
  // end sooner once settled (settled_variance) [8], >= 0.
  int rounds = 8;
  // Points simulated per refining round; 0: 2 (d + 1) [0], >= 0.
  int round_points = 0;
  // A round adds no points when the emulator's variance, averaged over the
  // residuals, is below this (in sigma^2) at every posterior sample [0.02].
  double settled_variance = 0.02;
  // The emulated residuals r are warped, r' = c asinh(r / c), so that the
  // far misfits of a box-wide design do not swamp the region that matters;
  // c in sigmas [4], > 0.
  double warp = 4.0;
  // The likelihood carries the sigmas' log term, exp(-misfit - log_scale)
  // (observations::Misfit::log_scale, emulated as one more output): the
  // Gaussian likelihood whole, where a sigma moves with the values [false].
  // Off, exp(-misfit): the squared residuals alone, which favour values
  // that widen a simulated spread (docs/posterior.md, Limits).
  bool sigma_log_term = false;
  McmcOptions mcmc;  // the final sampling; the rounds use half its steps
  EmulatorOptions emulator;
  // The residuals are correlated: the quantiles of one distribution share
  // their values, and the statistics of different distributions are of the
  // same rocks. With this set the likelihood takes their correlation R
  // (residual_correlation.h) by whitening the residual vector before it is
  // emulated (|W r|^2 = r^T R^-1 r). Off: every residual independent, as in
  // the misfit [on].
  bool correlated_quantiles = true;
  // R from this many bootstrap resamples of the rocks simulated at the
  // design's best point (ObjectiveFunction::ResidualCorrelation: every pair
  // of residuals, shrunk towards the quantiles' asymptotic correlation);
  // 0, or an objective that cannot tell: the quantiles' asymptotic
  // correlation alone (QuantileCorrelation of `layout`) [200], >= 0.
  int bootstrap_replicates = 200;
  // A parameter is "not determined by the data" when its 5-95 % interval is
  // wider than this share of the prior's (90 % of the range) [0.75], (0, 1].
  double undetermined_share = 0.75;
  // The predictive bands from this many posterior draws, each simulated at
  // its own seed with the final stage's rocks (PredictiveBands); 0: none
  // [20], >= 0.
  int predictive_draws = 20;

  bool IsValid(std::string* error) const;
  int DesignPoints(int parameters) const;
  int RoundPoints(int parameters) const;
};

// One calibrated value's posterior, SI.
struct ParameterPosterior {
  double median = 0.0, p05 = 0.0, p95 = 0.0, mean = 0.0, sd = 0.0;
  // (p95 - p05) over the uniform prior's 5-95 % width (0.9 of the range).
  double width_share = 0.0;
  bool undetermined = false;  // width_share > PosteriorOptions::undetermined_share
  double rhat = 0.0;
  double ess = 0.0;  // effective sample size of the chains (unthinned)
};

// One compared statistic's posterior predictive band (PredictiveBands).
struct PredictiveBand {
  observations::ResidualId id;                // the residual's: its observation and quantity
  double observed = 0.0;                      // SI
  double p05 = 0.0, median = 0.0, p95 = 0.0;  // of the simulated value over the draws, SI
  // The 5-95 % band of a new observation, SI: the draws' mixture of the
  // misfit's own likelihood, the observed value normal about each draw's
  // simulated one with that residual's sigma (observation error, the
  // observed statistic's sampling error and the simulated one's Monte Carlo
  // error). The observed value is checked against it: under the model it
  // falls inside 90 % of the time.
  double new_p05 = 0.0, new_p95 = 0.0;
  bool inside() const { return observed >= new_p05 && observed <= new_p95; }
};

struct PosteriorResult {
  ParameterSpace space;
  std::vector<std::vector<double>> samples;  // physical values, chain after chain
  int chains = 0;                            // the samples' chains, of equal length
  std::vector<ParameterPosterior> parameters;
  std::vector<std::vector<double>> correlation;  // d x d, of the samples
  double max_rhat = 0.0;
  double min_ess = 0.0;  // the smallest effective sample size over the parameters
  double acceptance = 0.0;
  int reused = 0;     // evaluations of the calibration emulated (the reach design's)
  int evaluated = 0;  // points of the posterior stage (design and rounds)
  int simulated = 0;  // of them, simulated now (the rest replayed from the log)
  int emulated = 0;   // points of the final emulator
  int rounds = 0;     // refining rounds that added points
  // The emulator's variance at the posterior samples, averaged over the
  // residuals, in sigma^2: its median (how much it widened the posterior).
  double emulator_variance = 0.0;
  // Where the residuals' correlation came from: "bootstrap", "quantiles"
  // (their asymptotic correlation) or "independent"; and how many
  // independent residuals' information it leaves, (tr R)^2 / tr(R^2).
  std::string correlation_source;
  bool sigma_log_term = false;  // PosteriorOptions::sigma_log_term, as used
  double effective_residuals = 0.0;
  int left_out = 0;                   // residuals the likelihood leaves out (LikelihoodResiduals)
  std::vector<double> length_scales;  // unit box
  double nugget = 0.0;
  double wall_seconds = 0.0;
  // The posterior predictive bands (PredictiveBands), when made: of the
  // compared statistics, and (a site's draws) of the runout quantiles and
  // every partition's passing share, heights, velocity and energies
  // (DrawStatistics, as rockcal simulate --parameters gives them).
  std::vector<PredictiveBand> bands;
  std::vector<DrawBand> statistic_bands;
  int band_draws = 0;
  int band_rocks = 0;
  std::string message;  // warnings (R-hat, emulator), empty when none

  // How many of `bands` hold their observed value (PredictiveBand::inside).
  int BandsInside() const {
    int n = 0;
    for (const PredictiveBand& b : bands) n += b.inside();
    return n;
  }
};

// One value's posterior from its values at the samples (`chains` chains of
// equal length, one after the other): mean, sd, median and 5-95 %
// interval; R-hat and the effective sample size of those chains (NaN for
// fewer than 2); width_share, the interval over `prior_width` (the
// prior's 5-95 % width), and undetermined beyond `undetermined_share`.
ParameterPosterior SummariseValues(std::vector<double> values, int chains, double prior_width,
                                   double undetermined_share);
// result->parameters, correlation, max_rhat and min_ess from its samples,
// space (a uniform prior on the bounds) and chains (SummariseValues); R-hat
// and ESS from `traces` (the unthinned chains) when given.
void SummariseSamples(double undetermined_share, const McmcResult* traces, PosteriorResult* result);
// The posterior of other values, `map` of the physical values, with the
// bounds of `space`: each of from's samples mapped, summarised
// (SummariseSamples); no bands. A campaign's site values are its joint
// values mapped.
PosteriorResult MapPosterior(
    const PosteriorResult& from, ParameterSpace space,
    const std::function<std::vector<double>(const std::vector<double>&)>& map,
    double undetermined_share);

// Which of the misfit's residuals (named as in `layout`) the posterior's
// likelihood takes: all but, for each site whose tracked runs are compared
// both by the pooled quantiles ("runout distance") and one by one ("run
// <id>"), the per-run residuals. The same stops would count twice, and a
// run's sigma is mostly its simulated spread, which the misfit alone
// rewards widening (docs/posterior.md, "Tracked runs"). With the sigmas'
// log term (`sigma_log_term`) every residual is taken: the log term is
// summed over all of them.
std::vector<bool> LikelihoodResiduals(const std::vector<observations::Residual>& layout,
                                      bool sigma_log_term);

// A warning for a posterior of `scene` when some of its rock groups start
// at an exact point (a release "point" without "position_spread"): every
// rock of such a group meets the same ground first, so the simulated
// statistics can jump with the values (a resonance of the first bounces),
// which the posterior's emulator smooths over and its intervals then miss
// (docs/posterior.md, "Tracked runs"). Empty when every group starts in a
// zone or a disc.
std::string PointReleaseWarning(const core::Scene& scene);

// Progress of SamplePosterior: (what, done, total).
using PosteriorProgress = std::function<void(const std::string& stage, int done, int total)>;

// Samples the posterior of `objective`'s parameters: the unpenalised
// `reused` evaluations (of this objective: same rocks and seed) and a
// space-filling design emulated, refined, then sampled (PosteriorOptions).
// New evaluations are appended to `log` as method "posterior" (and
// replayed from it on a resume). The seed of the design, the rounds and the
// chains is options.mcmc.seed. Throws InputError for invalid options;
// std::runtime_error when too few unpenalised evaluations exist to emulate.
// `layout`: the residuals of one evaluation (their observation and quantity
// name each residual; the values are not used), for the quantiles'
// correlation when the objective gives none (PosteriorOptions::
// bootstrap_replicates) and for the residuals the likelihood takes
// (LikelihoodResiduals); empty or of another length: then every residual,
// each independent.
PosteriorResult SamplePosterior(const ObjectiveFunction& objective,
                                const std::vector<Evaluation>& reused,
                                const PosteriorOptions& options, EvaluationLog* log,
                                const PosteriorProgress& progress = nullptr,
                                const std::vector<observations::Residual>& layout = {});

// One posterior predictive draw: the compared statistics' residuals at the
// physical values `physical`, simulated anew at `seed` (the posterior's
// objective at another seed), and the simulation's other statistics
// (DrawStatistics; empty when not made).
struct PredictiveOutcome {
  observations::Misfit misfit;
  std::vector<DrawValue> statistics;
};
using PredictiveDraw =
    std::function<PredictiveOutcome(const std::vector<double>& physical, std::uint64_t seed)>;

// The PredictiveDraw of one site: its scene with `rocks` rocks at the
// draw's seed (RunScene, `threads`), `space` applied, recording what the
// observations need and every partition; a simulation that fails gives
// no residuals and no statistics. Keeps references to `site` and
// `observations`.
PredictiveDraw SiteDraw(const sites::Site& site, const observations::Observations& observations,
                        const observations::MisfitOptions& misfit, const ParameterSpace& space,
                        int rocks, int threads);

// The posterior predictive bands of the compared statistics: `draws`
// posterior samples (evenly spaced through result.samples) each simulated
// by `draw` at its own seed (seed + 1000 + k, none of the calibration's)
// with `rocks` rocks in all, so that the bands hold the parameters'
// uncertainty and the Monte Carlo variation together; the simulated
// values' 5 %, 50 % and 95 % quantiles per residual (by observation and
// quantity), and of the draws' other statistics (BandsOverDraws). Fills
// result->bands and statistic_bands; spread over the ranks under mpirun.
void PredictiveBands(const PredictiveDraw& draw, std::uint64_t seed, int rocks, int draws,
                     PosteriorResult* result, const PosteriorProgress& progress = nullptr);

// The posterior as JSON: per parameter its summary, the correlations, the
// diagnostics and the bands.
nlohmann::json PosteriorJson(const PosteriorResult& result);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_POSTERIOR_H_
