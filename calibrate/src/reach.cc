#include "rockcal/calibrate/reach.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rockcal/core/name_table.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"

namespace rockcal::calibrate {
namespace {

using core::kNaN;
// Random streams of the designs (RandomStream(seed, stream)): one per Latin
// hypercube candidate from kLhsStream on, and one for the Halton shift.
constexpr std::uint64_t kLhsStream = 0x5245414348000000ull;     // "REACH"
constexpr std::uint64_t kHaltonStream = 0x48414c544f4e0000ull;  // "HALTON"
constexpr int kMaxHaltonDimensions = 64;

// A whole number in [0, n) from the stream.
int Below(core::RandomStream& rng, int n) {
  return std::min(n - 1, static_cast<int>(rng.Uniform() * n));
}

std::vector<std::vector<double>> LatinHypercube(int points, int dimensions,
                                                core::RandomStream& rng) {
  std::vector<std::vector<double>> x(static_cast<std::size_t>(points),
                                     std::vector<double>(static_cast<std::size_t>(dimensions)));
  std::vector<int> strata(static_cast<std::size_t>(points));
  for (int d = 0; d < dimensions; ++d) {
    for (int i = 0; i < points; ++i) strata[static_cast<std::size_t>(i)] = i;
    for (int i = points - 1; i > 0; --i)  // Fisher-Yates
      std::swap(strata[static_cast<std::size_t>(i)],
                strata[static_cast<std::size_t>(Below(rng, i + 1))]);
    for (int i = 0; i < points; ++i) {
      const double u = (strata[static_cast<std::size_t>(i)] + rng.Uniform()) / points;
      // Keep the point inside its stratum whatever the rounding.
      x[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)] =
          std::min(u, std::nextafter((strata[static_cast<std::size_t>(i)] + 1.0) / points, 0.0));
    }
  }
  return x;
}

// The first `count` primes.
std::vector<int> Primes(int count) {
  std::vector<int> primes;
  for (int n = 2; static_cast<int>(primes.size()) < count; ++n) {
    bool prime = true;
    for (int p : primes) {
      if (p * p > n) break;
      if (n % p == 0) {
        prime = false;
        break;
      }
    }
    if (prime) primes.push_back(n);
  }
  return primes;
}

// The radical inverse of `index` in `base`: its digits mirrored about the point.
double RadicalInverse(long index, int base) {
  double result = 0.0, scale = 1.0 / base;
  for (; index > 0; index /= base, scale /= base)
    result += static_cast<double>(index % base) * scale;
  return result;
}

std::vector<std::vector<double>> ShiftedHalton(int points, int dimensions,
                                               core::RandomStream& rng) {
  const std::vector<int> bases = Primes(dimensions);
  std::vector<double> shift(static_cast<std::size_t>(dimensions));
  for (double& s : shift) s = rng.Uniform();
  std::vector<std::vector<double>> x(static_cast<std::size_t>(points),
                                     std::vector<double>(static_cast<std::size_t>(dimensions)));
  for (int i = 0; i < points; ++i)
    for (int d = 0; d < dimensions; ++d) {
      double u = RadicalInverse(i + 1, bases[static_cast<std::size_t>(d)]) +
                 shift[static_cast<std::size_t>(d)];
      if (u >= 1.0) u -= 1.0;
      x[static_cast<std::size_t>(i)][static_cast<std::size_t>(d)] = u;
    }
  return x;
}

// True when the residual compares its simulated value with the observed one:
// a penalty (which replaces the comparison) leaves value != (sim - obs) / sigma.
bool Usable(const observations::Residual& r, bool penalised) {
  if (r.id.kind == observations::ObservationKind::kNone || !std::isfinite(r.simulated) ||
      !std::isfinite(r.observed) || !(std::isfinite(r.sigma) && r.sigma > 0.0))
    return false;
  if (!penalised) return true;
  const double expected = (r.simulated - r.observed) / r.sigma;
  return std::abs(r.value - expected) <= 1e-9 * std::max(1.0, std::abs(expected));
}

// Reduces the per-point values of statistic `s` to its range and verdict.
void Reduce(const std::vector<ReachPoint>& points, std::size_t s, ReachStatistic* stat) {
  std::vector<double> sigmas;
  double best = std::numeric_limits<double>::infinity();
  stat->min = stat->max = kNaN;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double sim = points[p].simulated[s], sigma = points[p].sigma[s];
    if (std::isnan(sim)) continue;
    const int index = static_cast<int>(p);
    ++stat->points_with_value;
    sigmas.push_back(sigma);
    if (stat->min_point < 0 || sim < stat->min) {
      stat->min = sim;
      stat->min_point = index;
    }
    if (stat->max_point < 0 || sim > stat->max) {
      stat->max = sim;
      stat->max_point = index;
    }
    const double z = (sim - stat->observed) / sigma;
    if (std::abs(z) < best) {
      best = std::abs(z);
      stat->closest_point = index;
      stat->closest_simulated = sim;
      stat->closest_sigmas = z;
    }
  }
  stat->sigma = core::Median(sigmas);
  if (stat->points_with_value == 0) {
    stat->verdict = ReachVerdict::kNoValue;
    stat->closest_simulated = stat->closest_sigmas = kNaN;
  } else if (stat->observed < stat->min - stat->sigma) {
    stat->verdict = ReachVerdict::kBelow;
  } else if (stat->observed > stat->max + stat->sigma) {
    stat->verdict = ReachVerdict::kAbove;
  } else {
    stat->verdict = ReachVerdict::kInReach;
  }
}

std::string G(double v, const char* format = "%.4g") {
  if (std::isnan(v)) return "-";
  return core::FormatNumber(v, format);
}

}  // namespace

namespace {
constexpr core::Named<DesignKind> kDesignKinds[] = {{DesignKind::kLatinHypercube, "lhs"},
                                                    {DesignKind::kHalton, "halton"}};
}  // namespace

const char* DesignKindToString(DesignKind kind) { return core::NameOf(kDesignKinds, kind); }
std::string DesignKindNames() { return core::NameList(kDesignKinds); }
bool StringToDesignKind(const std::string& name, DesignKind* kind) {
  return core::IdOf(kDesignKinds, name, kind);
}

std::vector<std::vector<double>> SpaceFillingDesign(DesignKind kind, int points, int dimensions,
                                                    std::uint64_t seed, int candidates) {
  if (points < 1 || dimensions < 1 || candidates < 1)
    throw std::invalid_argument("SpaceFillingDesign: points " + std::to_string(points) +
                                ", dimensions " + std::to_string(dimensions) + ", candidates " +
                                std::to_string(candidates) + " (each must be >= 1)");
  if (kind == DesignKind::kHalton) {
    if (dimensions > kMaxHaltonDimensions)
      throw std::invalid_argument("SpaceFillingDesign: " + std::to_string(dimensions) +
                                  " dimensions (Halton takes at most " +
                                  std::to_string(kMaxHaltonDimensions) + ")");
    core::RandomStream rng(seed, kHaltonStream);
    return ShiftedHalton(points, dimensions, rng);
  }
  std::vector<std::vector<double>> best;
  double best_distance = -1.0;
  for (int c = 0; c < candidates; ++c) {
    core::RandomStream rng(seed, kLhsStream + static_cast<std::uint64_t>(c));
    std::vector<std::vector<double>> x = LatinHypercube(points, dimensions, rng);
    const double d = MinimumDistance(x);
    if (d > best_distance) {
      best_distance = d;
      best = std::move(x);
    }
  }
  return best;
}

double MinimumDistance(const std::vector<std::vector<double>>& design) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < design.size(); ++i)
    for (std::size_t j = i + 1; j < design.size(); ++j) {
      double d2 = 0.0;
      for (std::size_t k = 0; k < design[i].size(); ++k) {
        const double d = design[i][k] - design[j][k];
        d2 += d * d;
      }
      best = std::min(best, std::sqrt(d2));
    }
  return best;
}

int ReachOptions::DefaultPoints(int parameters) {
  return std::min(8 * (std::max(parameters, 1) + 1), kMaxDefaultPoints);
}

int ReachOptions::EffectivePoints(int parameters) const {
  return points > 0 ? points : DefaultPoints(parameters);
}

bool ReachOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& field, const std::string& value, const std::string& rule) {
    if (error) *error = field + " = " + value + " " + rule;
    return false;
  };
  if (points != 0 && (points < 2 || points > 100000))
    return fail("points", std::to_string(points),
                "must be in [2, 100000] (or 0 for 8 (n + 1), at most " +
                    std::to_string(kMaxDefaultPoints) + ")");
  if (candidates < 1 || candidates > 1000)
    return fail("candidates", std::to_string(candidates), "must be in [1, 1000]");
  if (design != DesignKind::kLatinHypercube && design != DesignKind::kHalton)
    return fail("design", std::to_string(static_cast<int>(design)),
                "is not a design (allowed: " + DesignKindNames() + ")");
  return true;
}

const char* ReachVerdictText(ReachVerdict verdict) {
  switch (verdict) {
    case ReachVerdict::kInReach:
      return "in reach";
    case ReachVerdict::kBelow:
      return "out of reach (below)";
    case ReachVerdict::kAbove:
      return "out of reach (above)";
    case ReachVerdict::kNoValue:
      break;
  }
  return "out of reach (no value)";
}

std::string ReachStatistic::name() const {
  const std::string quantity = id.quantity();
  return quantity.empty() ? id.observation() : id.observation() + " " + quantity;
}

int ReachResult::out_of_reach() const {
  int n = 0;
  for (const ReachStatistic& s : statistics) n += s.in_reach() ? 0 : 1;
  return n;
}

std::string ReachResult::BriefReport() const {
  std::ostringstream out;
  out << "reach: " << points.size() << " points (" << DesignKindToString(design) << ", seed "
      << design_seed << ") of " << parameters.size() << " parameters, " << rocks
      << " rocks each, in " << G(wall_seconds, "%.1f") << " s; " << statistics.size()
      << " statistics, " << (statistics.size() - static_cast<std::size_t>(out_of_reach()))
      << " in reach, " << out_of_reach() << " out of reach\n";
  int penalised = 0;
  for (const ReachPoint& p : points) penalised += p.penalised ? 1 : 0;
  if (penalised > 0)
    out << penalised << " of " << points.size()
        << " points were penalised (each point records why); their penalised "
           "statistics are left out\n";
  if (best_point >= 0) {
    const ReachPoint& b = points[static_cast<std::size_t>(best_point)];
    out << "best point " << best_point << ": misfit " << G(b.misfit) << " at";
    for (std::size_t k = 0; k < parameters.size(); ++k)
      out << (k ? ", " : " ") << parameters[k].label() << " = " << G(b.physical[k]);
    out << "\n";
  }
  for (const std::string& w : OutOfReachWarnings(*this, false))
    out << "OUT OF REACH: " << w << "\n";
  if (const std::string advice = OutOfReachAdvice(*this); !advice.empty()) out << advice << "\n";
  return out.str();
}

std::string ReachResult::FullReport() const {
  std::ostringstream out;
  char line[320];
  std::snprintf(line, sizeof line, "%-30s %11s %9s %11s %11s %9s  %s\n", "statistic", "observed",
                "sigma", "min", "max", "closest", "verdict");
  out << line;
  for (const ReachStatistic& s : statistics) {
    std::snprintf(
        line, sizeof line, "%-30s %11s %9s %11s %11s %9s  %s\n", s.name().c_str(),
        G(s.observed).c_str(), G(s.sigma, "%.3g").c_str(), G(s.min).c_str(), G(s.max).c_str(),
        G(s.closest_sigmas, "%+.2f").c_str(),
        (std::string(ReachVerdictText(s.verdict)) + (s.at_edge() ? " (edge)" : "")).c_str());
    out << line;
  }
  out << "(SI units; closest: (simulated - observed) / sigma at the design point that came "
         "closest; edge: in reach only by the sigma allowance, outside [min, max])\n";
  out << BriefReport();
  return out.str();
}

ReachResult RunReach(const Objective& objective, const ReachOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("ReachOptions: " + error);
  const auto start = std::chrono::steady_clock::now();
  const ParameterSpace& space = objective.space();
  const int n = space.size();
  const int count = options.EffectivePoints(n);

  ReachResult result;
  result.site = objective.scene().name;
  result.design = options.design;
  result.candidates = options.design == DesignKind::kLatinHypercube ? options.candidates : 0;
  result.design_seed = options.seed;
  result.simulation_seed = objective.scene().options.seed;
  result.rocks = objective.scene().total_rocks();
  result.parameters = space.parameters();

  const std::vector<std::vector<double>> design =
      SpaceFillingDesign(options.design, count, n, options.seed, options.candidates);
  // Statistics in first-seen order, keyed by (observation, quantity).
  std::map<observations::ResidualId, std::size_t> index;
  std::vector<std::vector<observations::Residual>> residuals;
  // The design points are independent: simulated over the ranks of an MPI
  // run, in design order all the same.
  std::vector<std::vector<double>> physical;
  for (const std::vector<double>& unit : design) physical.push_back(space.ToPhysical(unit));
  int finished = 0;
  std::vector<observations::Misfit> misfits =
      objective.EvaluateAll(physical, [&](int, const observations::Misfit& m) {
        if (options.progress) options.progress(++finished, count, "misfit " + G(m.value));
      });
  for (int p = 0; p < count; ++p) {
    ReachPoint point;
    point.unit = design[static_cast<std::size_t>(p)];
    point.physical = physical[static_cast<std::size_t>(p)];
    observations::Misfit& misfit = misfits[static_cast<std::size_t>(p)];
    point.misfit = misfit.value;
    point.log_scale = misfit.log_scale;
    point.penalised = misfit.penalised;
    point.message = misfit.message;
    for (const observations::Residual& r : misfit.residuals) {
      // a spread penalty carries no statistic
      if (r.id.kind == observations::ObservationKind::kNone) continue;
      if (index.emplace(r.id, result.statistics.size()).second) {
        ReachStatistic s;
        s.id = r.id;
        s.observed = r.observed;
        result.statistics.push_back(s);
      }
    }
    residuals.push_back(std::move(misfit.residuals));
    result.points.push_back(std::move(point));
  }
  const std::size_t m = result.statistics.size();
  for (std::size_t p = 0; p < result.points.size(); ++p) {
    ReachPoint& point = result.points[p];
    point.simulated.assign(m, kNaN);
    point.sigma.assign(m, kNaN);
    for (const observations::Residual& r : residuals[p]) {
      if (!Usable(r, point.penalised)) continue;
      const std::size_t s = index.at(r.id);
      point.simulated[s] = r.simulated;
      point.sigma[s] = r.sigma;
    }
    if (result.best_point < 0 ||
        point.misfit < result.points[static_cast<std::size_t>(result.best_point)].misfit)
      result.best_point = static_cast<int>(p);
  }
  for (std::size_t s = 0; s < m; ++s) Reduce(result.points, s, &result.statistics[s]);
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::vector<std::string> OutOfReachWarnings(const ReachResult& result, bool advice) {
  std::vector<std::string> out;
  const std::string design = std::to_string(result.points.size()) + " design points of the box";
  for (const ReachStatistic& s : result.statistics) {
    if (s.in_reach()) continue;
    std::string w = s.name() + " is out of reach: observed " + G(s.observed) + ", ";
    if (s.verdict == ReachVerdict::kNoValue) {
      w += "but none of the " + design +
           " gave a value for it (each was penalised: too few simulated rocks to compare, or a "
           "failed simulation).";
    } else {
      w += std::string(s.verdict == ReachVerdict::kAbove ? "above" : "below") + " the range " +
           G(s.min) + " to " + G(s.max) + " that the " + design + " reached (sigma " +
           G(s.sigma, "%.3g") + ", SI units).";
    }
    if (advice)
      w += " Widen the box, change the model (release, shapes, contact parameters) or question "
           "the observation; a calibration gives a best compromise for it, not a fit.";
    out.push_back(w);
  }
  return out;
}

std::string OutOfReachAdvice(const ReachResult& result) {
  std::vector<std::string> names;
  for (const ReachStatistic& s : result.statistics)
    if (!s.in_reach()) names.push_back(s.name());
  if (names.empty()) return "";
  std::string list;
  for (std::size_t k = 0; k < names.size(); ++k) list += (k ? ", " : "") + names[k];
  return std::string("For ") +
         (names.size() == 1 ? "the statistic"
                            : "the " + std::to_string(names.size()) + " statistics") +
         " out of reach (" + list +
         "): widen the box, change the model (release, shapes, contact parameters) or question "
         "the observations; a calibration gives a best compromise for them, not a fit.";
}

}  // namespace rockcal::calibrate
