// Reach before fit (`rockcal study reach`, and the first stage of a
// calibration): can the calibration box produce what was observed at all?
//  - A space-filling design of the unit box (a maximin Latin hypercube, or a
//    randomly shifted Halton sequence), seeded and deterministic.
//  - Each design point is simulated through the calibration Objective, with
//    common random numbers (every point releases the same rocks the same way).
//  - The statistics are exactly the residuals of the misfit, keyed by
//    (observation, quantity): whatever the misfit compares (runout quantiles,
//    scar heights, passing fractions, ...) is checked, with no list of its own.
//    For each: the range of the simulated value over the design, the observed
//    value, its sigma, the point that came closest in sigmas, and a verdict.
// The result is a struct, read from and written to reach.json by to_json /
// from_json; the console report is written here; the files (reach.json,
// reach.csv, the plot and report.html) by rockcal/reports/reach_report.h.
// See calibrate/STUDIES.md.
#ifndef ROCKCAL_CALIBRATE_REACH_H_
#define ROCKCAL_CALIBRATE_REACH_H_

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::calibrate {

// ---- Space-filling designs ----------------------------------------------------

enum class DesignKind {
  // A Latin hypercube (each of the n strata [k/n, (k+1)/n) of every
  // coordinate holds exactly one point, at a random place inside it); of
  // `candidates` such hypercubes, the one whose closest pair of points lies
  // farthest apart (maximin).
  kLatinHypercube,
  // The Halton sequence (bases 2, 3, 5, ...), each coordinate shifted by a
  // random amount modulo 1 (Cranley-Patterson rotation). Low discrepancy, but
  // the strata are not guaranteed.
  kHalton,
};
const char* DesignKindToString(DesignKind kind);  // "lhs", "halton"
std::string DesignKindNames();                 // "lhs, halton"
// Sets *kind from its name; false for an unknown name.
bool StringToDesignKind(const std::string& name, DesignKind* kind);

// `points` points of the unit box [0, 1)^dimensions, the same for the same
// arguments on every machine. `candidates` (>= 1) is used by the Latin
// hypercube only. Throws std::invalid_argument when points < 1,
// dimensions < 1, dimensions > 64 (Halton) or candidates < 1.
std::vector<std::vector<double>> SpaceFillingDesign(DesignKind kind, int points, int dimensions,
                                                    std::uint64_t seed, int candidates = 10);
// The smallest distance between two points of `design` (+inf below 2 points).
double MinimumDistance(const std::vector<std::vector<double>>& design);

// ---- The reach check ------------------------------------------------------------

struct ReachOptions {
  // Design points; 0: the default for n parameters, DefaultPoints(n). When
  // set: in [2, 100000].
  int points = 0;
  DesignKind design = DesignKind::kLatinHypercube;
  // Latin hypercubes drawn for the maximin choice; in [1, 1000].
  int candidates = 10;
  // Seed of the design (the simulations use the Objective's scene seed).
  std::uint64_t seed = 1;
  StudyProgressFn progress;  // after each design point (may be empty)

  // 8 (n + 1), at most kMaxDefaultPoints.
  static constexpr int kMaxDefaultPoints = 120;
  static int DefaultPoints(int parameters);
  // points, or DefaultPoints(parameters) when it is 0.
  int EffectivePoints(int parameters) const;
  // Checks each field; on failure sets *error naming the field, its value and
  // the rule, and returns false.
  bool IsValid(std::string* error) const;
};

enum class ReachVerdict {
  kInReach,  // observed within [min - sigma, max + sigma]
  kBelow,    // observed < min - sigma: every design point gave more
  kAbove,    // observed > max + sigma: every design point gave less
  kNoValue,  // no design point gave a value (every point was penalised for it)
};
// "in reach", "out of reach (below)", "out of reach (above)", "out of reach (no value)".
const char* ReachVerdictText(ReachVerdict verdict);

// One statistic (one residual of the misfit) over the design.
struct ReachStatistic {
  observations::ResidualId id;  // the residual's: its observation and quantity
  double observed = 0.0;    // SI
  // The median over the points with a value of the residual's sigma (SI):
  // the measurement error, the Monte Carlo error of the simulated value and
  // the sampling error of the observed one. NaN when no point gave a value.
  double sigma = 0.0;
  double min = 0.0, max = 0.0;         // of the simulated value over the design (NaN: none)
  int min_point = -1, max_point = -1;  // design points that gave them
  // The point whose simulated value came closest to the observed one in its
  // own sigmas, its value and (simulated - observed) / sigma there.
  int closest_point = -1;
  double closest_simulated = 0.0, closest_sigmas = 0.0;
  int points_with_value = 0;  // design points that gave a value
  ReachVerdict verdict = ReachVerdict::kNoValue;

  std::string name() const;  // "runout distance p90"
  bool in_reach() const { return verdict == ReachVerdict::kInReach; }
  // In reach only by the sigma allowance: the observed value lies outside
  // [min, max]. The box's edge is there; a calibration may end at a bound.
  bool at_edge() const { return in_reach() && (observed < min || observed > max); }
};

// One design point.
struct ReachPoint {
  std::vector<double> unit, physical;  // in the unit box, and SI
  double misfit = 0.0;
  bool penalised = false;
  std::string message;  // why it was penalised
  // Per statistic (ReachResult::statistics order): the simulated value and the
  // residual's sigma; NaN where this point gave no value.
  std::vector<double> simulated, sigma;
  // observations::Misfit::log_scale there; NaN when not known (a reach.json
  // written without it).
  double log_scale = std::numeric_limits<double>::quiet_NaN();
};

struct ReachResult {
  std::string site;  // the Objective's scene's name
  DesignKind design = DesignKind::kLatinHypercube;
  int candidates = 0;
  std::uint64_t design_seed = 0;
  std::uint64_t simulation_seed = 0;  // the Objective's scene seed
  int rocks = 0;
  std::vector<Parameter> parameters;
  std::vector<ReachPoint> points;
  std::vector<ReachStatistic> statistics;  // in the misfit's residual order
  int best_point = -1;                     // lowest misfit (first on ties)
  double wall_seconds = 0.0;

  int out_of_reach() const;  // statistics not in reach
  // A few lines: what ran, how long, the best point, and each statistic out
  // of reach.
  std::string BriefReport() const;
  // A table with one line per statistic, then the best point.
  std::string FullReport() const;
};

// Simulates every point of the design through `objective` (one after the
// other; each simulation uses the scene's threads) and reduces the residuals.
// A point's value of a statistic is left out when its misfit was penalised
// and the residual does not equal (simulated - observed) / sigma: the
// penalty replaced the comparison (a failed simulation, a distribution with
// fewer than 2 simulated values, no rocks released). Throws
// std::invalid_argument when the options are not valid.
ReachResult RunReach(const Objective& objective, const ReachOptions& options);

// One plain sentence per statistic out of reach, naming it, the observed
// value, the range reached and (with `advice`) what to do; empty when all
// are in reach. For the calibrate command to print before it searches.
std::vector<std::string> OutOfReachWarnings(const ReachResult& result, bool advice = true);
// What to do, said once for every statistic out of reach, with their list
// ("For the 3 statistics out of reach (a, b, c): widen the box, ..."); empty
// when all are in reach. A console prints the warnings without advice, then
// this.
std::string OutOfReachAdvice(const ReachResult& result);

// reach.json: the design, the rule, one object per statistic and per point
// (calibrate/src/reach_json.cc; reports/ writes the file and reach.csv).
void to_json(nlohmann::json& j, const ReachResult& result);
void from_json(const nlohmann::json& j, ReachResult& result);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_REACH_H_
