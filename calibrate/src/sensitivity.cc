#include "rockcal/calibrate/sensitivity.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/recording.h"
#include "rockcal/core/error.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/random.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using text::Num;

using core::kNaN;
// The random stream of the output noise's resampling, apart from the rocks'
// streams (rock index) and the methods' (sensitivity_methods.cc).
constexpr std::uint64_t kNoiseStream = (std::uint64_t{1} << 52) + 4;

}  // namespace

// ---- Site outputs -----------------------------------------------------------------------

namespace {

// Quantile q of the finite values, NaN when there are none.
double FiniteQuantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  return core::QuantileOf(&v, q);
}

}  // namespace

std::vector<SiteOutput> SiteOutputs(const core::Scene& scene, const observations::Observations* obs,
                                    const observations::MisfitOptions& misfit) {
  std::vector<SiteOutput> out;
  for (std::size_t p = 0; p < scene.partitions.size(); ++p) {
    const std::string& id = scene.partitions[p].id;
    auto heights = [p](const core::SimulationResult& r) {
      std::vector<double> h;
      for (const core::RockRecord& rock : r.rocks)
        if (p < rock.crossings.size() && rock.crossings[p].crossed)
          h.push_back(rock.crossings[p].height);
      return h;
    };
    for (const auto& [level, tag] : {std::pair<double, const char*>{0.5, "p50"}, {0.9, "p90"}}) {
      out.push_back({id + ".height." + tag, "m",
                     std::string("bounce height ") + tag + " at partition " + id +
                         " (rock centre above the ground, crossing rocks)",
                     [heights, level = level](const core::Scene&, const core::SimulationResult& r) {
                       return FiniteQuantile(heights(r), level);
                     }});
    }
    out.push_back({id + ".passing", "fraction",
                   "share of the released rocks that crossed partition " + id,
                   [p](const core::Scene&, const core::SimulationResult& r) {
                     if (r.rocks.empty()) return kNaN;
                     int n = 0;
                     for (const core::RockRecord& rock : r.rocks)
                       n += p < rock.crossings.size() && rock.crossings[p].crossed;
                     return static_cast<double>(n) / static_cast<double>(r.rocks.size());
                   }});
  }
  // Runout: along the observations' direction, or the stop x as summary.json.
  std::shared_ptr<const observations::Runout> line;
  if (obs && obs->runout) line = std::make_shared<const observations::Runout>(*obs->runout);
  const std::string along =
      line ? "distance along the observed runout direction from its origin" : "stop x";
  auto runout = [line](const core::SimulationResult& r) {
    std::vector<double> d;
    for (const core::RockRecord& rock : r.rocks) {
      if (rock.outcome != core::Outcome::kStopped) continue;
      d.push_back(line ? line->Distance(rock.stop.head<2>()) : rock.stop.x());
    }
    return d;
  };
  for (const auto& [level, tag] : {std::pair<double, const char*>{0.5, "p50"}, {0.9, "p90"}}) {
    out.push_back({std::string("runout.") + tag, "m",
                   std::string("runout ") + tag + " of the stopped rocks (" + along + ")",
                   [runout, level = level](const core::Scene&, const core::SimulationResult& r) {
                     return FiniteQuantile(runout(r), level);
                   }});
  }
  out.push_back({"stopped", "fraction", "share of the released rocks that stopped on the slope",
                 [](const core::Scene&, const core::SimulationResult& r) {
                   if (r.rocks.empty()) return kNaN;
                   return static_cast<double>(r.count(core::Outcome::kStopped)) /
                          static_cast<double>(r.rocks.size());
                 }});
  if (obs) {
    auto observed = std::make_shared<const observations::Observations>(*obs);
    out.push_back({"misfit", "",
                   "calibration misfit against the observations (half the sum of squared "
                   "scaled residuals, as rockcal calibrate minimises)",
                   [observed, misfit](const core::Scene& s, const core::SimulationResult& r) {
                     return observations::ComputeMisfit(*observed, s, r, misfit).value;
                   }});
  }
  return out;
}

// ---- The site study -------------------------------------------------------------------

int SensitivityOptions::EffectiveSamples() const {
  if (samples > 0) return samples;
  return method == SensitivityMethod::kMorris ? MorrisOptions{}.trajectories
                                              : SobolOptions{}.samples;
}

bool SensitivityOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
    *error = "sensitivity." + field + " = " + value + ": " + rule;
    return false;
  };
  const bool morris = method == SensitivityMethod::kMorris;
  if (samples != 0 && (samples < (morris ? 2 : 4) || samples > 100000))
    return fail("samples", std::to_string(samples),
                morris ? "Morris trajectories must be in [2, 100000] (0: default 10)"
                       : "Sobol rows must be in [4, 100000] (0: default 64)");
  if (levels < 2 || levels > 100 || levels % 2 != 0)
    return fail("levels", std::to_string(levels), "must be even and in [2, 100]");
  if (bootstrap < 20 || bootstrap > 100000)
    return fail("bootstrap", std::to_string(bootstrap), "must be in [20, 100000]");
  if (!(confidence > 0.5 && confidence < 1))
    return fail("confidence", Num(confidence), "must be in (0.5, 1)");
  if (threads < 0) return fail("threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  return true;
}

namespace {

// A copy of `r` whose rocks are r.rocks[pick[0]], r.rocks[pick[1]], ...
core::SimulationResult Resampled(const core::SimulationResult& r,
                                 const std::vector<std::size_t>& pick) {
  core::SimulationResult out;
  out.rocks.reserve(pick.size());
  for (std::size_t k : pick) out.rocks.push_back(r.rocks[k]);
  return out;
}

// Bootstrap standard error of each output over the rocks of `r`; NaN when
// fewer than half the resamples give a value.
std::vector<double> OutputNoise(const std::vector<SiteOutput>& outputs, const core::Scene& scene,
                                const core::SimulationResult& r, int resamples,
                                std::uint64_t seed) {
  std::vector<std::vector<double>> reps(outputs.size());
  const std::size_t n = r.rocks.size();
  std::vector<double> out(outputs.size(), kNaN);
  if (n == 0) return out;
  core::RandomStream rng(seed, kNoiseStream);
  std::vector<std::size_t> pick(n);
  for (int b = 0; b < resamples; ++b) {
    for (auto& k : pick) k = rng.Index(n);
    const core::SimulationResult sample = Resampled(r, pick);
    for (std::size_t o = 0; o < outputs.size(); ++o)
      reps[o].push_back(outputs[o].compute(scene, sample));
  }
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    std::vector<double> v;
    for (double x : reps[o])
      if (std::isfinite(x)) v.push_back(x);
    if (v.size() < 2 || 2 * v.size() < reps[o].size()) continue;
    out[o] = core::SampleStandardDeviation(v);
  }
  return out;
}

}  // namespace

namespace {

// The reducer: one entry per parameter and output, with its effect over the
// output's Monte Carlo noise.
void AddEntries(SensitivityMethod method, SensitivityResult* result) {
  SensitivityResult& res = *result;
  const int k = static_cast<int>(res.parameters.size()), m = static_cast<int>(res.outputs.size());
  for (int i = 0; i < k; ++i) {
    for (int o = 0; o < m; ++o) {
      SensitivityEntry e;
      e.parameter = i;
      e.output = o;
      const double noise = res.outputs[static_cast<std::size_t>(o)].noise;
      if (method == SensitivityMethod::kMorris) {
        e.morris = res.morris.index[static_cast<std::size_t>(o)][static_cast<std::size_t>(i)];
        const double ee_noise = res.EffectNoise(static_cast<std::size_t>(o));
        e.effect_over_noise = ee_noise > 0 ? e.morris.mu_star / ee_noise : kNaN;
      } else {
        e.sobol = res.sobol.index[static_cast<std::size_t>(o)][static_cast<std::size_t>(i)];
        const double v = res.sobol.variance[static_cast<std::size_t>(o)];
        e.effect_over_noise =
            noise > 0 ? std::sqrt(std::max(e.sobol.first, 0.0) * v) / noise : kNaN;
      }
      res.entries.push_back(e);
    }
  }
}

// Notes on outputs without a value, without noise, or that no parameter moves.
void AddNotes(SensitivityMethod method, SensitivityResult* result) {
  SensitivityResult& res = *result;
  for (const auto& out : res.outputs) {
    if (std::isnan(out.value))
      res.notes.push_back(out.name + ": no value at the current parameters (no rock counted)");
    else if (!(out.noise > 0))
      res.notes.push_back(out.name +
                          ": no Monte Carlo noise seen at the current parameters (every "
                          "resample gave the same value), so effect / noise is unknown");
  }
  for (std::size_t o = 0; o < res.outputs.size(); ++o) {
    bool constant = true;
    if (method == SensitivityMethod::kMorris) {
      for (const auto& idx : res.morris.index[o]) constant = constant && idx.mu_star == 0.0;
    } else {
      constant = !(res.sobol.variance[o] > 0.0);
    }
    if (constant)
      res.notes.push_back(res.outputs[o].name +
                          ": the same at every point of the design (no parameter moves it)");
  }
  if (res.non_finite_runs > 0)
    res.notes.push_back(std::to_string(res.non_finite_runs) +
                        " simulations had a rock in a non-finite state");
}

// The one-paragraph summary: cost, and how many pairs stand above the noise.
std::string Summary(SensitivityMethod method, const SensitivityResult& res) {
  const int k = static_cast<int>(res.parameters.size()), m = static_cast<int>(res.outputs.size());
  std::ostringstream s;
  s << SensitivityMethodToString(method) << ", "
    << (method == SensitivityMethod::kMorris ? "r = " : "N = ") << res.samples << ": "
    << res.simulations << " simulations of " << res.rocks << " rocks in "
    << Num(res.wall_seconds, "%.3g") << " s (" << Num(res.SimulationsPerSecond(), "%.3g")
    << " simulations/s). ";
  int resolved = 0;
  std::vector<std::string> unresolved;
  for (int i = 0; i < k; ++i) {
    bool any = false;
    for (int o = 0; o < m; ++o) {
      const double ratio = res.at(i, o).effect_over_noise;
      if (ratio >= kResolvedEffectOverNoise) ++resolved, any = true;
    }
    if (!any) unresolved.push_back(res.parameters[static_cast<std::size_t>(i)].label());
  }
  s << resolved << " of " << k * m << " parameter-output pairs have an effect of at least "
    << Num(kResolvedEffectOverNoise, "%g") << " times the Monte Carlo noise";
  if (!unresolved.empty()) {
    s << "; not above the noise on any output: ";
    for (std::size_t u = 0; u < unresolved.size(); ++u) s << (u ? ", " : "") << unresolved[u];
  }
  s << ".";
  return s.str();
}

}  // namespace

namespace {

// One simulation at physical values of a space on a base scene; the
// terrain is rebuilt only when the roughness values change (hardness and
// contact time reuse it).
class DesignRunner {
 public:
  DesignRunner(const ParameterSpace& space, const core::Scene& base) : space_(space), base_(base) {}

  std::pair<core::Scene, core::SimulationResult> Run(const std::vector<double>& physical) {
    core::Scene scene = base_;
    space_.Apply(physical, &scene);
    std::vector<double> key;
    for (int i = 0; i < space_.size(); ++i)
      if (space_.parameters()[static_cast<std::size_t>(i)].kind == ParameterKind::kRoughness)
        key.push_back(physical[static_cast<std::size_t>(i)]);
    if (!terrain_ || key != terrain_key_) {
      terrain_ = std::make_unique<core::Terrain>(core::BuildTerrain(scene));
      terrain_key_ = key;
    }
    core::SimulationResult r = parallel::Simulate(scene, *terrain_);
    return std::make_pair(std::move(scene), std::move(r));
  }

 private:
  const ParameterSpace& space_;
  const core::Scene& base_;
  std::vector<double> terrain_key_;
  std::unique_ptr<core::Terrain> terrain_;
};

// A simulation's share of the result's counts.
void CountRun(double seconds, bool non_finite, SensitivityResult* res) {
  ++res->simulations;
  res->simulation_seconds += seconds;
  if (non_finite) ++res->non_finite_runs;
}

// The site's scene as the study runs it: the seed, threads and recording
// of the options.
core::Scene StudyScene(const sites::Site& site, const observations::Observations* obs,
                       const SensitivityOptions& opt) {
  core::Scene base = site.scene;
  if (opt.seed) base.options.seed = *opt.seed;
  base.options.threads = opt.threads;
  RecordingNeeds needs;
  needs.observations = obs;
  needs.partitions = !base.partitions.empty();
  base.options.record = RecordingFor(base, needs);
  std::string error;
  if (!base.options.IsValid(&error)) throw InputError(site.path, error);
  return base;
}

// One pass of the study's method over k parameters and m outputs with
// `model`, into *res.
void RunDesign(const SensitivityOptions& opt, int k, int m, const SensitivityModel& model,
               SensitivityResult* res) {
  if (opt.method == SensitivityMethod::kMorris) {
    MorrisOptions mo;
    mo.trajectories = res->samples;
    mo.levels = opt.levels;
    mo.seed = res->seed;
    res->morris = RunMorris(k, m, model, mo);
  } else {
    SobolOptions so;
    so.samples = res->samples;
    so.bootstrap = opt.bootstrap;
    so.confidence = opt.confidence;
    so.seed = res->seed;
    res->sobol = RunSobol(k, m, model, so);
  }
}

// The outputs at each of the design's unit points, simulated as independent
// tasks (over the ranks of an MPI run, parallel::Map), in order.
std::vector<std::vector<double>> SimulateDesign(const std::vector<std::vector<double>>& points,
                                                const ParameterSpace& space,
                                                const std::vector<SiteOutput>& outputs,
                                                const SensitivityOptions& opt, int total_runs,
                                                DesignRunner* runner, SensitivityResult* res) {
  const std::string what = SensitivityMethodToString(opt.method);
  int finished = res->simulations;
  const std::vector<std::string> runs = parallel::Map(
      static_cast<int>(points.size()),
      [&](int p) {
        const auto [scene, r] = runner->Run(space.ToPhysical(points[static_cast<std::size_t>(p)]));
        std::vector<double> y(outputs.size());
        for (std::size_t o = 0; o < outputs.size(); ++o) y[o] = outputs[o].compute(scene, r);
        parallel::Writer w;
        w.Doubles(y);
        w.Double(r.wall_seconds);
        w.Int(r.figures.non_finite > 0 ? 1 : 0);
        return w.bytes();
      },
      [&](int, const std::string&) {
        if (opt.progress) opt.progress(++finished, total_runs, what);
      });
  std::vector<std::vector<double>> ys;
  for (const std::string& bytes : runs) {
    parallel::Reader r(bytes);
    ys.push_back(r.Doubles());
    const double seconds = r.Double();
    CountRun(seconds, r.Int() != 0, res);
  }
  return ys;
}

}  // namespace

double SensitivityResult::EffectNoise(std::size_t output) const {
  return std::sqrt(2.0) * outputs[output].noise / morris.delta;
}

double SensitivityResult::SimulationsPerSecond() const {
  return simulations / std::max(wall_seconds, 1e-9);
}

SensitivityResult RunSensitivity(const sites::Site& site, const observations::Observations* obs,
                                 const SensitivityOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (!opt.IsValid(&error)) throw std::invalid_argument(error);
  const ParameterSpace space = ParameterSpace::FromSite(site);  // InputError without bounds
  const core::Scene base = StudyScene(site, obs, opt);
  const std::vector<SiteOutput> outputs = SiteOutputs(base, obs);
  const int k = space.size(), m = static_cast<int>(outputs.size());

  SensitivityResult res;
  res.site = base.name;
  res.method = opt.method;
  res.samples = opt.EffectiveSamples();
  res.seed = base.options.seed;
  res.rocks = base.total_rocks();
  res.threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  res.parameters = space.parameters();
  res.current = space.Current(base);
  const int design_runs =
      opt.method == SensitivityMethod::kMorris ? res.samples * (k + 1) : res.samples * (k + 2);
  const int total_runs = design_runs + 1;
  DesignRunner runner(space, base);

  // The site's current parameters: each output's value and its noise.
  {
    const auto [scene, r] = runner.Run(res.current);
    CountRun(r.wall_seconds, r.figures.non_finite > 0, &res);
    if (opt.progress) opt.progress(res.simulations, total_runs, "current parameters");
    const std::vector<double> noise = OutputNoise(outputs, scene, r, opt.bootstrap, res.seed);
    for (std::size_t o = 0; o < outputs.size(); ++o)
      res.outputs.push_back({outputs[o].name, outputs[o].unit, outputs[o].description,
                             outputs[o].compute(scene, r), noise[o]});
  }

  // The design's points do not depend on the outputs: a first pass of the
  // method with a model that only notes them gives the list, which is
  // simulated; the second pass reads the outputs back in the same order.
  std::vector<std::vector<double>> points;
  RunDesign(
      opt, k, m,
      [&](const std::vector<double>& unit) {
        points.push_back(unit);
        return std::vector<double>(static_cast<std::size_t>(m), 0.0);
      },
      &res);
  const std::vector<std::vector<double>> ys =
      SimulateDesign(points, space, outputs, opt, total_runs, &runner, &res);
  std::size_t next = 0;
  RunDesign(
      opt, k, m,
      [&](const std::vector<double>& unit) {
        if (next >= ys.size() || unit != points[next])
          throw std::logic_error("sensitivity: the design changed between its two passes");
        return ys[next++];
      },
      &res);

  AddEntries(opt.method, &res);
  AddNotes(opt.method, &res);
  res.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  res.summary = Summary(opt.method, res);
  return res;
}

// ---- Tables ----------------------------------------------------------------------------

std::string SensitivityReport(const SensitivityResult& r) {
  const bool morris = r.method == SensitivityMethod::kMorris;
  std::ostringstream out;
  char line[256];
  if (morris)
    std::snprintf(line, sizeof line, "%-22s %-20s %10s %10s %10s %10s %8s\n", "parameter", "output",
                  "mu", "mu*", "sigma", "noise", "mu*/n");
  else
    std::snprintf(line, sizeof line, "%-22s %-20s %8s %17s %8s %17s %8s\n", "parameter", "output",
                  "S1", "interval", "ST", "interval", "eff/n");
  out << line;
  for (const SensitivityEntry& e : r.entries) {
    const std::string p = r.parameters[static_cast<std::size_t>(e.parameter)].label();
    const SensitivityOutputInfo& o = r.outputs[static_cast<std::size_t>(e.output)];
    if (morris) {
      std::snprintf(line, sizeof line, "%-22s %-20s %10.4g %10.4g %10.4g %10.4g %8.3g\n", p.c_str(),
                    o.name.c_str(), e.morris.mu, e.morris.mu_star, e.morris.sigma, o.noise,
                    e.effect_over_noise);
    } else {
      std::snprintf(line, sizeof line,
                    "%-22s %-20s %8.3f [%6.3f, %6.3f] %8.3f [%6.3f, %6.3f] %8.3g\n", p.c_str(),
                    o.name.c_str(), e.sobol.first, e.sobol.first_low, e.sobol.first_high,
                    e.sobol.total, e.sobol.total_low, e.sobol.total_high, e.effect_over_noise);
    }
    out << line;
  }
  for (const auto& note : r.notes) out << "note: " << note << '\n';
  out << r.summary << '\n';
  return out.str();
}

}  // namespace rockcal::calibrate
