#include "statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "rockcal/core/format.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::observations {

using core::FormatNumber;

namespace {

// P(|Z| >= x) for a standard normal Z.
double TwoSidedTail(double x) { return std::erfc(std::abs(x) / std::sqrt(2.0)); }

// P(K >= k) for K ~ Binomial(n, p), 0 < p < 1.
double BinomialTail(int n, int k, double p) {
  if (k <= 0) return 1.0;
  if (k > n) return 0.0;
  double sum = 0.0;
  for (int j = k; j <= n; ++j)
    sum += std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) +
                    j * std::log(p) + (n - j) * std::log1p(-p));
  return std::min(1.0, sum);
}

std::string Chance(double p) {
  return p < 1e-4 ? "< 0.01 %" : FormatNumber(100.0 * p, "%.2g") + " %";
}

}  // namespace

std::string FitVerdict::Sentence() const {
  if (penalised) return "poor: the misfit was penalised (see its message)";
  if (outside.empty() && !poor && !fair)
    return "good: every compared quantity (" + std::to_string(compared) + ") within 2 sigma";
  std::string s = std::string(poor   ? "poor"
                              : fair ? "fair"
                                     : "good") +
                  ": " + std::to_string(outside.size()) + " of " + std::to_string(compared) +
                  " compared quantities outside 2 sigma";
  const std::string chances = "at least as many with probability " + Chance(count_chance) +
                              ", a largest as far with probability " + Chance(largest_chance);
  s += poor || fair ? " (a correct model gives " + chances + ")"
                    : ", as a correct model gives (" + chances + ")";
  for (std::size_t k = 0; k < outside.size() && k < 3; ++k)
    s += (k ? "; " : ", the worst ") + outside[k];
  return s;
}

FitVerdict AssessFit(const Misfit& misfit) {
  FitVerdict v;
  v.compared = static_cast<int>(misfit.residuals.size());
  v.penalised = misfit.penalised;
  std::vector<const Residual*> far;
  double largest = 0.0;
  for (const Residual& r : misfit.residuals) {
    if (std::abs(r.value) > 2.0) far.push_back(&r);
    largest = std::max(largest, std::abs(r.value));
  }
  std::sort(far.begin(), far.end(), [](const Residual* a, const Residual* b) {
    return std::abs(a->value) > std::abs(b->value);
  });
  for (const Residual* r : far) {
    char line[160];
    std::snprintf(line, sizeof line, ": simulated %.3g against %.3g observed (%+.1f sigma)",
                  r->simulated, r->observed, r->value);
    v.outside.push_back(r->id.observation() + " " + r->id.quantity() + line);
  }
  if (v.compared > 0) {
    v.count_chance = BinomialTail(v.compared, static_cast<int>(far.size()), TwoSidedTail(2.0));
    // 1 - (1 - q)^N without cancellation for a small q.
    v.largest_chance = -std::expm1(v.compared * std::log1p(-TwoSidedTail(largest)));
  }
  const double chance = std::min(v.count_chance, v.largest_chance);
  v.poor = misfit.penalised || chance < FitVerdict::kPoorChance;
  v.fair = !v.poor && chance < FitVerdict::kFairChance;
  return v;
}

FitVerdict AssessTracks(const Misfit& misfit) {
  // A tracks distribution with fewer than 2 simulated values has residuals
  // of sqrt(2 penalty / 3) each, so its verdict is poor by the largest alone.
  Misfit tracks;
  for (const Residual& r : misfit.residuals)
    if (r.id.kind == ObservationKind::kTracks) tracks.residuals.push_back(r);
  return AssessFit(tracks);
}

std::string TracksVerdictSentence(const Misfit& misfit) {
  const FitVerdict v = AssessTracks(misfit);
  if (v.compared == 0) return "";
  const std::string what = v.poor   ? "the jumps are not reproduced: "
                           : v.fair ? "the jumps are reproduced only fairly: "
                                    : "the jumps are reproduced: ";
  return "tracks: " + what + v.Sentence();
}

std::string ImpactVerdict(const Misfit& misfit) {
  if (misfit.impacts.empty()) return "";
  Misfit own;
  own.penalised = misfit.penalised;
  for (const Residual& r : misfit.residuals)
    if (r.id.kind == ObservationKind::kImpact || r.id.kind == ObservationKind::kImpactsNormal ||
        r.id.kind == ObservationKind::kImpactsTangential)
      own.residuals.push_back(r);
  const FitVerdict v = AssessFit(own);
  return std::string(v.poor ? "rebounds NOT reproduced" : "rebounds reproduced") + " (" +
         v.Sentence() + ")";
}

double ComparedQuantilePosition(std::size_t n, double level) {
  const double count = static_cast<double>(n);
  return std::clamp((count + 1.0 / 3.0) * level - 2.0 / 3.0, 0.0, count - 1.0);
}

double ComparedQuantile(const std::vector<double>& sorted, double level) {
  return AtPosition(sorted, ComparedQuantilePosition(sorted.size(), level));
}

double RegularisedIncompleteBeta(double x, double a, double b) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  // The continued fraction of I_x(a, b) converges fast for x < (a + 1) / (a
  // + b + 2); above, I_x(a, b) = 1 - I_{1-x}(b, a). Evaluated by the
  // modified Lentz method (Lentz 1976, Applied Optics 15:668-671; Thompson
  // & Barnett 1986, J. Comput. Phys. 64:490-509).
  if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - RegularisedIncompleteBeta(1.0 - x, b, a);
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x)) /
                       a;
  constexpr double kTiny = 1e-300;
  auto guard = [](double v) { return std::abs(v) < kTiny ? kTiny : v; };
  double c = 1.0, d = 1.0 / guard(1.0 - (a + b) * x / (a + 1.0)), f = d;
  for (int m = 1; m <= 300; ++m) {
    const double even = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
    d = 1.0 / guard(1.0 + even * d);
    c = guard(1.0 + even / c);
    f *= d * c;
    const double odd = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
    d = 1.0 / guard(1.0 + odd * d);
    c = guard(1.0 + odd / c);
    const double step = d * c;
    f *= step;
    if (std::abs(step - 1.0) < 1e-14) break;
  }
  return std::clamp(front * f, 0.0, 1.0);
}

double QuantileDesignEffect(const std::vector<double>& values, const std::vector<int>& clusters,
                            double q, double level) {
  const std::size_t n = values.size();
  if (n == 0 || clusters.size() != n || !(level > 0.0 && level < 1.0)) return 1.0;
  std::map<int, double> sums;
  for (std::size_t i = 0; i < n; ++i)
    sums[clusters[i]] += (values[i] < q ? 1.0 : values[i] == q ? 0.5 : 0.0) - level;
  if (sums.size() == n) return 1.0;
  double squares = 0.0;
  for (const auto& [cluster, sum] : sums) squares += sum * sum;
  return std::max(1.0, squares / (static_cast<double>(n) * level * (1.0 - level)));
}

double QuantileStandardError(const std::vector<double>& sorted, double level) {
  const std::size_t n = sorted.size();
  if (n < 2) return 0.0;
  const double count = static_cast<double>(n);
  // The order statistic at 0-based position c is the (c + 1)-th of n: its
  // rank's share is Beta(c + 1, n - c), which weighs the i-th value by
  // I_{i/n} - I_{(i-1)/n}.
  const double c = ComparedQuantilePosition(n, level);
  const double a = c + 1.0, b = count - c;
  // Ranks beyond 10 standard deviations and 20 positions (the rank's share
  // is skewed near p = 0 and 1) weigh nothing that counts; their mass goes
  // to the window's end values.
  const double spread = 10.0 * std::sqrt(count * level * (1.0 - level)) + 20.0;
  const auto first = static_cast<std::size_t>(std::max(0.0, std::floor(c - spread)));
  const auto last = static_cast<std::size_t>(std::min(count - 1.0, std::ceil(c + spread)));
  std::vector<double> weight;
  weight.reserve(last - first + 1);
  double below = 0.0;  // I at the window's lower edge, lumped into its first value
  for (std::size_t i = first; i <= last; ++i) {
    const double upper =
        i == last ? 1.0 : RegularisedIncompleteBeta(static_cast<double>(i + 1) / count, a, b);
    weight.push_back(upper - below);
    below = upper;
  }
  double mean = 0.0;
  for (std::size_t i = first; i <= last; ++i) mean += weight[i - first] * sorted[i];
  double variance = 0.0;
  for (std::size_t i = first; i <= last; ++i)
    variance += weight[i - first] * (sorted[i] - mean) * (sorted[i] - mean);
  return std::sqrt(std::max(variance, 0.0));
}

double MaxStandardError(const std::vector<double>& sorted) {
  const std::size_t n = sorted.size();
  if (n < 2) return 0.0;
  const std::size_t j = std::clamp<std::size_t>(n / 10, 1, n - 1);
  const double threshold = sorted[n - 1 - j];
  double excess = 0.0;
  for (std::size_t i = n - j; i < n; ++i) excess += sorted[i] - threshold;
  return std::max(sorted[n - 1] - sorted[n - 2], excess / static_cast<double>(j));
}

double MaxOrderPosition(std::size_t simulated, std::size_t observed) {
  const double n = static_cast<double>(simulated), m = static_cast<double>(observed);
  // P_k for k = 1, 2, ...: the chance that the k-th largest simulated value
  // exceeds the observed maximum; it falls with k, to 0 at k = n + 1.
  double before = 1.0, p = n / (n + m);
  double k = 1.0;
  while (p > 0.5) {
    before = p;
    p *= (n - k) / (n + m - k);
    k += 1.0;
  }
  if (k == 1.0) return n - 1.0;
  // P_{k-1} = before > 1/2 >= P_k = p.
  return n - (k - 1.0 + (before - 0.5) / (before - p));
}

double OrderStatisticError(const std::vector<double>& sorted, double position) {
  const std::size_t n = sorted.size();
  if (n < 2) return 0.0;
  const double last = static_cast<double>(n - 1);
  const double p = std::clamp(position / last, 0.0, 1.0);
  const double h = std::max(1.0, std::sqrt(static_cast<double>(n) * p * (1.0 - p)));
  const double lo = std::clamp(position - h, 0.0, last);
  const double hi = std::clamp(position + h, 0.0, last);
  return hi > lo ? h * (AtPosition(sorted, hi) - AtPosition(sorted, lo)) / (hi - lo) : 0.0;
}

std::string LevelName(double level) {
  const double percent = 100.0 * level;
  const double rounded = std::round(percent);
  if (std::abs(percent - rounded) < 1e-9) {
    return "p" + std::to_string(static_cast<long>(rounded));
  }
  return "p" + FormatNumber(percent, "%.6g");
}

}  // namespace rockcal::observations
