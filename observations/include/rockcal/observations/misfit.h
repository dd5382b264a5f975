// The misfit between a simulation's rock records and field observations:
// quantiles of simulated against observed distributions, each difference
// scaled by its uncertainty. See observations/README.md for the formulas.
#ifndef ROCKCAL_OBSERVATIONS_MISFIT_H_
#define ROCKCAL_OBSERVATIONS_MISFIT_H_

#include <algorithm>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/observations.h"

namespace rockcal::observations {

// Which comparisons of tracked runs (Runout::has_runs) enter the misfit.
enum class RunTerms {
  kPooled,  // the runs' runouts pooled into one distribution, compared by quantiles
  kPerRun,  // one residual per run: its group's median runout against its stop
  kBoth,    // both (the default; docs/field-campaigns.md says why)
};
const char* RunTermsToString(RunTerms terms);  // "pooled", "per_run", "both"
// The value named `name` (RunTermsToString); false when unknown.
bool StringToRunTerms(const std::string& name, RunTerms* terms);

struct MisfitOptions {
  // 0.1, 0.2, ..., 0.9 (out of line: an initializer list here trips GCC 12's
  // -Wdangling-pointer in the inlined copy).
  static std::vector<double> DefaultLevels();
  // Quantile levels compared for every distribution (heights, runout distance
  // and lateral offset), each in [0, 1].
  std::vector<double> levels = DefaultLevels();  // 0.1, 0.2, ..., 0.9
  // Also compare the observed maximum with the simulated order statistic
  // that exceeds it with probability 1/2 under the model (MaxOrderPosition):
  // the simulated maximum when both sides have as many values.
  bool include_max = true;
  // Misfit of a result that cannot be compared (non-finite rock state), and
  // the contribution of each distribution with fewer than 2 simulated values.
  // Finite, > 0.
  double penalty = 1e6;
  // Floor of every sigma as a fraction of the measurement error of its kind
  // (an absolute floor of 1e-9 applies too), in (0, 1].
  double sigma_floor = 1e-3;
  // Tracked runs: the pooled quantiles, the per-run residuals or both.
  RunTerms run_terms = RunTerms::kBoth;
  // Tracked runs: the weight, in rocks' degrees of freedom, of the spread
  // pooled over all runs when a run's own predictive spread is estimated
  // (its n rocks give n - 1); finite, >= 0.
  double run_spread_prior = 4.0;

  // Checks each field; on failure sets *error (naming the field, its value
  // and the rule) and returns false.
  bool IsValid(std::string* error) const;
};

// What a residual compares: the kind of its observation. Each prints as the
// residuals' "observation" text (ResidualId::observation()).
enum class ObservationKind {
  kNone,             // none: a penalty spread over the residuals of a failed evaluation ("")
  kTreeScars,        // the heights of a tree-scar set: its label, "tree_scars[0] BP-1"
  kRunoutDistance,   // the runout distances: "runout distance"
  kRunoutMassClass,  // those of one mass class: "runout distance, mass 10-40 kg"
  kRunoutLateral,    // the lateral offsets: "runout lateral"
  kRunoutStopped,    // the share of rocks that stopped: "runout stopped"
  kRun,              // one tracked run's runout: "run <id>"
  kPassing,          // a passing fraction: its label, "passing[0] BP-2"
  kTracks,           // a distribution of the tracks: "tracks jump height" (its name)
  kPrior,            // a campaign's offset prior: "prior"
  kImpact,           // one measured impact's rebound: "impact <id>"
  // Every impact's normal rebound ratio, pooled: "impacts normal ratio".
  kImpactsNormal,
  // Every impact's tangential rebound ratio, pooled: "impacts tangential ratio".
  kImpactsTangential,
};

// Which number of an observation a residual compares. Each prints as the
// residuals' "quantity" text (ResidualId::quantity()).
enum class Statistic {
  kNone,      // none (ObservationKind::kNone): ""
  kQuantile,  // the quantile at ResidualId::level: "p10", "p2.5"
  kMax,       // the largest value: "max"
  kShare,     // a share of rocks with binomial errors on both sides: "share"
  kFraction,  // a passing fraction: "fraction"
  kRunout,    // a tracked run's median runout against its stop: "runout"
  kOffset,    // a site's offset of a shared parameter: "<site>:<class>.<parameter>_offset"
  // An impact's normal rebound ratio (its draws' median): "normal_ratio".
  kNormalRatio,
  // An impact's tangential rebound ratio (its draws' median): "tangential_ratio".
  kTangentialRatio,
};

// A residual's identity, typed: compare these fields, never the text.
struct ResidualId {
  ObservationKind kind = ObservationKind::kNone;
  // Which observation of its kind: the index into the observations'
  // tree_scars, passing or runs (Runout::run_ids), the mass class (0 the
  // lightest) or the campaign's offset; -1 for a kind there is one of.
  int index = -1;
  // Its name: the scar set's or passing's label, the run's id, the mass
  // class's range in kg ("< 10", "10-40", ">= 40"), the offset's
  // "<class>.<parameter>"; empty for a kind there is one of.
  std::string name;
  Statistic statistic = Statistic::kNone;
  double level = 0.0;  // Statistic::kQuantile: the quantile level, in [0, 1]
  // The campaign site the observation (or the offset) belongs to; empty for
  // one site's misfit.
  std::string site;

  // The identity of an observation (no statistic yet), and this one with
  // `statistic` at `level`: Of(ObservationKind::kRunoutDistance).With(
  // Statistic::kQuantile, 0.9) is "runout distance" "p90".
  static ResidualId Of(ObservationKind kind, int index = -1, std::string name = {});
  ResidualId With(Statistic statistic, double level = 0.0) const;

  // The observation's text: "runout distance", with "<site>: " before it in
  // a campaign (a prior's is "prior").
  std::string observation() const;
  // The quantity's text: "p10", "max", "share", "fraction", "runout", or an
  // offset's "<site>:<class>.<parameter>_offset".
  std::string quantity() const;
  // This identity without its statistic: the key of its observation.
  ResidualId observation_id() const;
  // The identity one site's misfit prints as `observation` and `quantity`
  // (reach.json and score.json hold them so), read back by the kind that
  // prints it. A campaign's site prefix, priors and offsets are not read; an
  // index the text does not carry (a mass class's, a run's) stays -1.
  // Throws std::invalid_argument naming a text no kind prints.
  static ResidualId Parse(const std::string& observation, const std::string& quantity);

  bool operator==(const ResidualId& other) const;
  bool operator!=(const ResidualId& other) const { return !(*this == other); }
  bool operator<(const ResidualId& other) const;  // any strict order, for maps
};

// One scaled difference between a simulated and an observed quantity.
struct Residual {
  ResidualId id;            // what it compares
  double simulated = 0.0;   // SI (m, or a fraction)
  double observed = 0.0;    // SI
  double sigma = 1.0;       // SI, > 0
  double value = 0.0;       // (simulated - observed) / sigma
  // The part of sigma that does not depend on the simulation (the
  // measurement error and the observed statistic's own error, floored),
  // 0 < fixed_sigma <= sigma; 0 when all of sigma is fixed (a prior, an
  // offset, a penalty). Misfit::log_scale sums log(sigma / fixed_sigma).
  double fixed_sigma = 0.0;
};

// How the simulations of one tracked run (Runout::has_runs) compare with it.
struct RunFit {
  std::string id;
  int group = 0;               // index into core::Scene::groups
  double observed = 0.0;       // m, the run's runout from its release
  // m, the median runout of its group's rocks (censored ones at the far
  // end; those that stopped when not every observed rock stopped)
  double simulated = 0.0;
  int rocks = 0;               // simulated rocks of its group
  int stopped = 0;             // of which stopped
  // Simulated rocks that stopped near their release while the run itself
  // ran on (StuckNearRelease).
  int stuck = 0;
  // The per-run residual's scale [m]: measurement error, predictive spread
  // and the median's Monte Carlo error (RunTerms kPerRun, kBoth; else 0).
  double sigma = 0.0;
  double spread = 0.0;  // m, the run's predictive spread (shrunk toward the pool)
  static constexpr double kStuckDistance = 1.0;  // m
  static constexpr double kStuckShare = 0.1;
  // A rock that moved `moved` m (in plan, centre to centre) stuck near its
  // release in a run observed to move `observed` m: it stopped within a
  // tenth of the run's runout (kStuckShare), and within no less than
  // kStuckDistance, of where it started: it never got going.
  static bool StuckNearRelease(double moved, double observed) {
    const double near = std::max(kStuckDistance, kStuckShare * observed);
    return moved < near && observed > near;
  }
};

// How the tracked runs' simulated paths compare with the observed tracks:
// each distribution, observed and simulated, ascending.
struct TrackFit {
  int tracks = 0;  // observed tracks compared
  int rocks = 0;   // simulated rocks of their groups (each once)
  std::vector<double> observed_heights, simulated_heights;  // m, jump heights
  std::vector<double> observed_lengths, simulated_lengths;  // m, jump lengths
  std::vector<double> observed_speeds, simulated_speeds;    // m/s, impact speeds
};

// How the replays of one measured impact (Observations::impacts) compare with
// it (docs/field-campaigns.md, "Impacts").
struct ImpactFit {
  std::string id;
  int group = 0;                    // index into core::Scene::groups
  double incidence_deg = 0.0;       // incoming velocity's angle from the ground's normal
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();       // the ground's at the impact
  Eigen::Vector3d observed = Eigen::Vector3d::Zero();      // m/s, the measured rebound
  Eigen::Vector3d simulated = Eigen::Vector3d::Zero();     // m/s, the draws' median per component
  double speed_sd = 0.0;            // m/s, the draws' robust spread of the rebound speed
  int draws = 0, left = 0;          // replays, of which in flight again
  // The rebound ratios (core::RatiosOf): observed, the draws' median and
  // robust spread (1.4826 MAD), and the residual's sigma; tangential NaN for
  // a near-normal impact.
  double normal_observed = 0.0, normal_simulated = 0.0, normal_spread = 0.0, normal_sigma = 0.0;
  double tangential_observed = 0.0, tangential_simulated = 0.0, tangential_spread = 0.0,
         tangential_sigma = 0.0;
  std::vector<double> normal_draws, tangential_draws;  // each draw's ratios
};

struct Misfit {
  std::vector<Residual> residuals;  // empty when the result was non-finite
  // Measured impacts only: each impact's fit, in the observations' order.
  std::vector<ImpactFit> impacts;
  // Per-run observations only: each run's fit, in the observations' order.
  std::vector<RunFit> runs;
  // With tracks (Observations::tracks): their distributions; tracks = 0 without.
  TrackFit tracks;
  // Mean over the runs of |simulated - observed| runout [m] (0 without runs).
  double MeanRunError() const;
  int StuckRocks() const;  // summed over the runs
  double value = 0.0;               // 0.5 * sum of residual values squared
  // The sum over the residuals of log(sigma / fixed_sigma) (those with a
  // fixed_sigma): the part of the negative log-likelihood that the
  // simulation's own Monte Carlo and predictive spread add through the
  // sigmas (docs/posterior.md, "The method"). The posterior adds it to
  // `value` when asked (calibrate::PosteriorOptions::sigma_log_term); the
  // search, the verdict and the reports read `value` alone.
  double log_scale = 0.0;
  // True when a penalty entered the value: a non-finite result (value =
  // penalty, no residuals) or a distribution with fewer than 2 simulated
  // values (its residuals add up to the penalty).
  bool penalised = false;
  std::string message;  // why it was penalised, one sentence per cause

  // One line per residual, then the total.
  std::string Report() const;
};

// Compares `result` (simulated with at least RequiredRecording(observations,
// ...)) with `observations`. Throws std::invalid_argument when `options` is
// invalid or the records lack what the observations need (programmer errors).
// Always returns a finite value.
Misfit ComputeMisfit(const Observations& observations, const core::Scene& scene,
                     const core::SimulationResult& result, const MisfitOptions& options = {});

// A plain verdict on a fit: which compared quantities lie outside their
// uncertainty, and whether so many, or one so far, are what a correct model
// gives. Under a correct model each residual is a standard normal draw, so
// with N of them some lie beyond 2 sigma by chance (each with probability
// 0.0455) and the largest grows with N. Two tests, each the chance that a
// correct model does at least as badly (residuals taken as independent):
// - the count beyond 2 sigma, a binomial tail P(K >= k), K ~ B(N, 0.0455);
// - the largest |residual| x, 1 - (1 - P(|Z| >= x))^N (Sidak).
// Poor when either chance is below kPoorChance (or the misfit was
// penalised), fair when below kFairChance, good otherwise.
struct FitVerdict {
  static constexpr double kFairChance = 0.05;
  static constexpr double kPoorChance = 0.01;
  // A residual beyond 2 sigma, one line each: "runout distance p50: simulated
  // 52.1 against 40 observed (+3.1 sigma)", the largest first.
  std::vector<std::string> outside;
  int compared = 0;  // residuals compared
  // The chance that a correct model puts at least outside.size() of
  // `compared` residuals beyond 2 sigma (1 when none are).
  double count_chance = 1.0;
  // The chance that a correct model's largest |residual| of `compared` is at
  // least the largest here (1 without residuals).
  double largest_chance = 1.0;
  bool fair = false;  // either chance below kFairChance, neither below kPoorChance
  bool poor = false;  // either chance below kPoorChance, or penalised
  bool penalised = false;
  // One sentence: "good: every compared quantity (25) within 2 sigma",
  // "good: 3 of 73 compared quantities outside 2 sigma, as many as a correct
  // model gives (...)" or "poor: 24 of 73 ... (a correct model: ...), the
  // worst ...".
  std::string Sentence() const;
};
FitVerdict AssessFit(const Misfit& misfit);
// The verdict on the tracks' residuals alone (ObservationKind::kTracks), and
// its sentence: "tracks: the jumps are not reproduced: poor: ...", "tracks:
// the jumps are reproduced only fairly: ..." or "tracks: the jumps are
// reproduced: good: ..."; "" without tracks residuals.
FitVerdict AssessTracks(const Misfit& misfit);
std::string TracksVerdictSentence(const Misfit& misfit);

// The verdict on the measured impacts' residuals alone (ObservationKind
// kImpact, kImpactsNormal and kImpactsTangential), as AssessFit forms it, in one sentence that
// says plainly whether the rebounds are reproduced: "rebounds reproduced
// (good: ...)", or "rebounds NOT reproduced (poor: ...)"; "" without impacts.
std::string ImpactVerdict(const Misfit& misfit);

// The 0-based position of the level-p quantile the misfit compares in an
// ascending sample of n values: Hyndman & Fan's type 8, (n + 1/3) p - 2/3
// clamped to [0, n - 1], approximately median-unbiased whatever the
// distribution and n (Hyndman & Fan 1996, Sample quantiles in statistical
// packages, The American Statistician 50:361-365), so that samples of
// different sizes from one distribution compare without bias. The type-7
// position (n - 1) p lies nearer the median the fewer the values, by
// (1 - 2p) / (n + 1) in probability, which set a smaller observed sample's
// tails inside a larger simulated one's (observations/README.md). At p = 1/2
// both are (n - 1) / 2. n >= 1.
double ComparedQuantilePosition(std::size_t n, double level);
// The value at ComparedQuantilePosition, interpolated linearly. n >= 1.
double ComparedQuantile(const std::vector<double>& sorted, double level);
// Standard error of the level-p quantile of an ascending sample of n values,
// weighing every order statistic (Maritz & Jarrett 1978, A note on
// estimating the variance of the sample median, JASA 73:194-196): the
// quantile is the order statistic at c = ComparedQuantilePosition, the
// (c + 1)-th of n, whose rank's share is Beta(c + 1, n - c); the i-th value
// (1-based) weighs W_i = I_{i/n}(c + 1, n - c) - I_{(i-1)/n}(c + 1, n - c)
// and the error is the square root of sum W_i (x_i - sum W_j x_j)^2. Where
// the values are spread smoothly it is about half the spread of the order
// statistics one standard deviation of rank either side; where they are
// clustered (rocks stopped in the hollows between virtual spheres) it keeps
// the chance that the quantile falls in the next cluster, which that
// spread misses. 0 for n < 2.
double QuantileStandardError(const std::vector<double>& sorted, double level);
// The design effect of the level-p quantile `q` of values drawn in
// clusters (the flights of one tracked run, of one simulated rock): the
// variance of the quantile's estimating sum, sum_i (1{x_i < q} - p) (a value
// at q counting 1/2), taken over the clusters' sums S_c as the clusters are
// the independent draws, over its variance for independent values:
// sum_c S_c^2 / (n p (1 - p)) (the linearised variance of a quantile of a
// clustered sample: Woodruff 1952, Confidence intervals for medians and
// other position measures, JASA 47:635-646). Values and clusters side by
// side; at least 1 (so few clusters never make the error smaller than for
// independent values); 1 when every cluster holds one value or p is 0 or 1.
double QuantileDesignEffect(const std::vector<double>& values, const std::vector<int>& clusters,
                            double q, double level);
// I_x(a, b), the regularised incomplete beta function: P(U <= x) for U ~
// Beta(a, b). a, b > 0; 0 for x <= 0, 1 for x >= 1.
double RegularisedIncompleteBeta(double x, double a, double b);
// Standard error of the maximum: the larger of the gap between the two
// largest values and the mean excess of the j = clamp(n / 10, 1, n - 1)
// largest over the next one. For an exponential tail of scale b each
// normalised spacing i (x(n-i+1) - x(n-i)) is an exponential draw of mean b,
// the gap the first of them and the mean excess their mean; the larger of
// the two has a mean of 1.25-1.35 b for j = 2..10, near the spread of the
// maximum itself (pi / sqrt(6) b = 1.28 b), and does not fall to 0 when the
// two largest tie. Below 20 values (j = 1) it is the gap. 0 for n < 2.
double MaxStandardError(const std::vector<double>& sorted);
// The 0-based fractional position, in an ascending sample of `simulated`
// values, of the order statistic that exceeds the maximum of `observed`
// values with probability 1/2 when both are draws of one continuous
// distribution. The k-th largest of n simulated values exceeds the largest
// of m observed ones when the k largest of the n + m values pooled are all
// simulated: P_k = prod_{i<k} (n - i) / (n + m - i). k = 1 (the simulated
// maximum, n - 1) when P_1 = n / (n + m) <= 1/2 (as many values or fewer);
// else k interpolates linearly between the last k with P_k > 1/2 and the
// next, and the position is n - k. Both counts >= 1.
double MaxOrderPosition(std::size_t simulated, std::size_t observed);
// Standard error of the order statistic at 0-based fractional position
// `position` of an ascending sample of n values: the local slope of the
// order statistics over h = max(1, sqrt(n p (1 - p))) positions either side
// (p = position / (n - 1), the span clamped to [0, n - 1]) times h. In the
// interior it is half the spread of the order statistics h positions either
// side (about QuantileStandardError's on smoothly spread values); at the
// top it is the gap between
// the two largest values (MaxStandardError's below 20 values). 0 for n < 2.
double OrderStatisticError(const std::vector<double>& sorted, double position);
// "p10" for 0.1, "p2.5" for 0.025, "p100" for 1.
std::string LevelName(double level);

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_MISFIT_H_
