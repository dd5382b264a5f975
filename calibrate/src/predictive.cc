// The posterior predictive bands (posterior.h): draws of the posterior, each
// simulated at its own seed, and the bands of the compared statistics over
// them. See docs/posterior.md.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>

#include "rockcal/calibrate/posterior.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"

namespace rockcal::calibrate {

PredictiveDraw SiteDraw(const sites::Site& site, const observations::Observations& obs,
                        const observations::MisfitOptions& misfit, const ParameterSpace& space,
                        int rocks, int threads) {
  return [&site, &obs, misfit, space, rocks, threads](const std::vector<double>& physical,
                                                      std::uint64_t seed) {
    core::Scene scene = RunScene(site, rocks, seed, threads);
    space.Apply(physical, &scene);
    RecordingNeeds needs;
    needs.observations = &obs;
    needs.partitions = true;
    needs.energy_check = scene.options.record.energy_check;
    scene.options.record = RecordingFor(scene, needs);
    PredictiveOutcome out;
    try {
      const core::SimulationResult sim = parallel::Simulate(scene);
      out.misfit = observations::ComputeMisfit(obs, scene, sim, misfit);
      out.statistics =
          DrawStatistics(scene, core::ComputeStats(scene, sim), static_cast<int>(sim.rocks.size()));
    } catch (const std::exception& e) {
      out = PredictiveOutcome{};
      out.misfit.penalised = true;
      out.misfit.message = std::string("simulation failed: ") + e.what();
    }
    return out;
  };
}

namespace {

// A predictive draw's outcome as bytes for parallel::Map, and back.
std::string EncodeOutcome(const PredictiveOutcome& outcome) {
  parallel::Writer w;
  w.String(EncodeMisfit(outcome.misfit));
  w.Int(static_cast<long long>(outcome.statistics.size()));
  for (const DrawValue& v : outcome.statistics) {
    w.String(v.where);
    w.String(v.quantity);
    w.String(v.unit);
    w.Double(v.value);
  }
  return w.bytes();
}

PredictiveOutcome DecodeOutcome(const std::string& bytes) {
  parallel::Reader r(bytes);
  PredictiveOutcome out;
  out.misfit = DecodeMisfit(r.String());
  out.statistics.resize(static_cast<std::size_t>(r.Int()));
  for (DrawValue& v : out.statistics) {
    v.where = r.String();
    v.quantity = r.String();
    v.unit = r.String();
    v.value = r.Double();
  }
  return out;
}

// The `level` quantile of the equal mixture of normals N(means[k], sds[k]^2)
// (sds > 0), by bisection on the mixture's distribution function.
double NormalMixtureQuantile(const std::vector<double>& means, const std::vector<double>& sds,
                             double level) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < means.size(); ++k) {
    lo = std::min(lo, means[k] - 9.0 * sds[k]);
    hi = std::max(hi, means[k] + 9.0 * sds[k]);
  }
  const auto cdf = [&](double x) {
    double f = 0.0;
    for (std::size_t k = 0; k < means.size(); ++k)
      f += 0.5 * std::erfc(-(x - means[k]) / (sds[k] * std::sqrt(2.0)));
    return f / static_cast<double>(means.size());
  };
  for (int it = 0; it < 200 && hi - lo > 1e-12 * std::max(1.0, std::fabs(lo) + std::fabs(hi));
       ++it) {
    const double mid = 0.5 * (lo + hi);
    (cdf(mid) < level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

void PredictiveBands(const PredictiveDraw& draw, std::uint64_t seed, int rocks, int draws,
                     PosteriorResult* result, const PosteriorProgress& progress) {
  result->bands.clear();
  result->statistic_bands.clear();
  if (draws <= 0 || result->samples.empty()) return;
  const std::size_t n = result->samples.size();
  std::vector<std::vector<double>> chosen;
  for (int k = 0; k < draws; ++k)
    chosen.push_back(result->samples[(static_cast<std::size_t>(k) * n + n / 2) /
                                     static_cast<std::size_t>(draws) % n]);
  int done = 0;
  if (progress) progress("predictive bands", 0, draws);
  const std::vector<std::string> bytes = parallel::Map(
      draws,
      [&](int k) {
        return EncodeOutcome(
            draw(chosen[static_cast<std::size_t>(k)], seed + 1000 + static_cast<std::uint64_t>(k)));
      },
      [&](int, const std::string&) {
        if (progress) progress("predictive bands", ++done, draws);
      });
  std::vector<observations::Misfit> misfits;
  std::vector<std::vector<DrawValue>> statistics;
  for (const std::string& b : bytes) {
    PredictiveOutcome o = DecodeOutcome(b);
    misfits.push_back(std::move(o.misfit));
    if (!o.statistics.empty()) statistics.push_back(std::move(o.statistics));
  }
  result->statistic_bands = BandsOverDraws(statistics);
  // The residuals by their identity, in the first draw's order.
  std::vector<observations::ResidualId> keys;
  std::map<observations::ResidualId, std::vector<double>> values, sigmas;
  std::map<observations::ResidualId, double> observed;
  for (const observations::Misfit& m : misfits)
    for (const observations::Residual& r : m.residuals) {
      if (!std::isfinite(r.simulated) || !(r.sigma > 0.0) || !std::isfinite(r.sigma)) continue;
      const observations::ResidualId& key = r.id;
      if (!values.count(key)) keys.push_back(key);
      values[key].push_back(r.simulated);
      sigmas[key].push_back(r.sigma);
      observed[key] = r.observed;
    }
  for (const auto& key : keys) {
    std::vector<double> v = values[key];
    PredictiveBand b;
    b.id = key;
    b.observed = observed[key];
    b.new_p05 = NormalMixtureQuantile(v, sigmas[key], 0.05);
    b.new_p95 = NormalMixtureQuantile(v, sigmas[key], 0.95);
    b.p05 = core::QuantileOf(&v, 0.05);
    b.median = core::QuantileOf(&v, 0.5);
    b.p95 = core::QuantileOf(&v, 0.95);
    result->bands.push_back(b);
  }
  result->band_draws = draws;
  result->band_rocks = rocks;
}

}  // namespace rockcal::calibrate
