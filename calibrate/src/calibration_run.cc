// One calibration from start to end: the reach check, the noise check, the
// search, the refining stage with its race, the posterior stage and the
// final run (calibration_run.h).
#include "rockcal/calibrate/calibration_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"

namespace rockcal::calibrate {

std::string CalibrationSummary::BriefReport() const {
  std::ostringstream out;
  out << site << ": misfit " << misfit_before.value << " at the start, " << misfit_after.value
      << " at the calibrated values";
  if (!methods.empty()) {
    const MethodResult& m = best_method();
    out << " (" << m.stage.name() << ", " << m.evaluations << " evaluations, "
        << TerminationName(termination.type) << ": " << termination.message << ")";
  }
  out << "; " << rocks << " rocks per evaluation, seed " << seed << ", " << wall_seconds << " s\n";
  return out.str();
}

ContenderSpread SpreadOfContenders(std::vector<double> misfits) {
  ContenderSpread out;
  if (misfits.size() < 2) return out;
  std::sort(misfits.begin(), misfits.end());
  const std::size_t n = misfits.size();
  const std::size_t k = std::min(n, std::max<std::size_t>(4, (n + 3) / 4));
  misfits.resize(k);
  out.points = static_cast<int>(k);
  out.spread = core::SampleStandardDeviation(misfits);
  return out;
}

namespace {

std::string Numbers(const std::vector<double>& values) {
  std::ostringstream s;
  s.precision(17);
  for (std::size_t k = 0; k < values.size(); ++k) s << (k ? " " : "") << values[k];
  return s.str();
}

// The evaluation log at options.log_path (none when it is empty), resumed
// when options.resume, fingerprinted with what determines `scene`'s
// evaluations; `accepted` as EvaluationLog's (also called without a log).
std::optional<EvaluationLog> OpenLog(const sites::Site& site, const observations::Observations& obs,
                                     const CalibrationOptions& options, const ParameterSpace& space,
                                     const core::Scene& scene,
                                     const std::function<void()>& accepted = {}) {
  std::optional<EvaluationLog> log;
  if (!options.log_path.empty())
    log.emplace(options.log_path, options.resume, space, scene.options.seed, scene.total_rocks(),
                CalibrationFingerprint(site, obs, options, space), accepted);
  else if (accepted)
    accepted();
  return log;
}

// The first stage's share of the evaluations when a refining stage follows.
int FirstStageEvaluations(const CalibrationOptions& options) {
  const int total = options.method.max_evals;
  const int refining = static_cast<int>(std::lround(options.refine_share * total));
  return std::max(2, total - refining);
}

// The log of the refining stage: "<stem>-refine.jsonl" beside the log.
std::string RefineLogPath(const std::string& log_path) {
  if (log_path.empty()) return log_path;
  const std::filesystem::path p(log_path);
  return (p.parent_path() / (p.stem().string() + "-refine" + p.extension().string())).string();
}

// CalibrationOptions::race_points: the candidates for the refining
// search's start simulated on `objective` (the refining stage's rocks);
// returns the values of the lowest misfit (the first stage's best without a
// race).
// start_misfit_before: the start's misfit at the first stage's rocks
// (summary->misfit_before is already the refining stage's, and the start
// is not simulated again).
std::vector<double> RaceCandidates(const CalibrationOptions& options, const Objective& objective,
                                   double start_misfit_before, CalibrationSummary* summary) {
  const std::vector<double>& first_best = summary->best_method().best;
  if (options.race_points <= 0) return first_best;
  using Entry = CalibrationSummary::RaceEntry;
  std::vector<Entry>& race = summary->race;
  race.push_back({"first stage", first_best, summary->best_method().best_misfit, 0.0, false});
  race.push_back({"start", summary->start, start_misfit_before, 0.0, false});
  if (summary->reach) {
    const std::vector<ReachPoint>& points = summary->reach->points;
    std::vector<std::size_t> order;
    for (std::size_t k = 0; k < points.size(); ++k)
      if (!points[k].penalised) order.push_back(k);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return points[a].misfit < points[b].misfit;
    });
    const std::size_t n = std::min(order.size(), static_cast<std::size_t>(options.race_points));
    for (std::size_t k = 0; k < n; ++k)
      race.push_back({"design point " + std::to_string(order[k] + 1), points[order[k]].physical,
                      points[order[k]].misfit, 0.0, false});
  }
  // The candidates are independent: simulated over the ranks of an MPI run.
  std::vector<std::vector<double>> points;
  for (const Entry& entry : race)
    if (entry.physical != summary->start) points.push_back(entry.physical);
  const std::vector<observations::Misfit> misfits = objective.EvaluateAll(points);
  double lowest = 0.0;
  std::size_t next = 0;
  for (std::size_t k = 0; k < race.size(); ++k) {
    const observations::Misfit& m =
        race[k].physical == summary->start ? summary->misfit_before : misfits[next++];
    race[k].misfit = m.value;
    race[k].penalised = m.penalised;
    if (summary->race_winner < 0 || m.value < lowest) {
      summary->race_winner = static_cast<int>(k);
      lowest = m.value;
    }
  }
  return race[static_cast<std::size_t>(summary->race_winner)].physical;
}

// The refining stage of Calibrate: the best method again, with
// refine_factor times the rocks, from the winner of the race
// (RaceCandidates). Appends its result to summary->methods (and makes it
// the best); returns the scene it searched.
core::Scene RefineStage(const sites::Site& site, const observations::Observations& obs,
                        const CalibrationOptions& options, const ParameterSpace& space,
                        const CalibrationCallbacks& callbacks, CalibrationSummary* summary) {
  CalibrationOptions o = options;
  o.rocks = summary->rocks * options.refine_factor;
  o.refine_factor = 1;
  o.log_path = RefineLogPath(options.log_path);
  o.resume = options.resume && !o.log_path.empty() && std::filesystem::exists(o.log_path);
  const core::Scene scene = RunScene(site, o.rocks, options.seed, options.threads);
  const Objective objective(scene, space, obs, options.misfit);
  // Before and after at the same rocks, so that they compare.
  const double start_misfit_before = summary->misfit_before.value;
  summary->misfit_before = objective.Evaluate(summary->start);
  const std::vector<double> refine_start =
      RaceCandidates(options, objective, start_misfit_before, summary);
  std::optional<EvaluationLog> log = OpenLog(site, obs, o, space, scene);
  MethodOptions method_options = options.method;
  method_options.seed = scene.options.seed;
  method_options.max_evals = std::max(2, options.method.max_evals - FirstStageEvaluations(options));
  method_options.initial_step = options.refine_step;
  Stage stage = summary->best_method().stage;
  stage.rocks = scene.total_rocks();
  if (callbacks.method_started) callbacks.method_started(stage);
  MethodResult result = RunMethod(stage.method, objective, refine_start, method_options,
                                  log ? &*log : nullptr, callbacks.evaluated);
  result.stage = stage;
  if (callbacks.method_finished) callbacks.method_finished(result);
  summary->methods.push_back(std::move(result));
  summary->best = static_cast<int>(summary->methods.size()) - 1;
  return scene;
}

// CalibrationOptions::noise_seeds: the calibrated values at other seeds.
void MeasureMisfitNoise(const sites::Site& site, const observations::Observations& obs,
                        const CalibrationOptions& options, const ParameterSpace& space,
                        CalibrationSummary* summary) {
  if (options.noise_seeds <= 0) return;
  std::vector<double> all = {summary->misfit_after.value};
  // The seeds are independent: simulated over the ranks of an MPI run.
  const std::vector<std::string> misfits = parallel::Map(options.noise_seeds, [&](int k) {
    const std::uint64_t seed = summary->seed + static_cast<std::uint64_t>(k + 1);
    const core::Scene scene = RunScene(site, summary->final_rocks, seed, options.threads);
    parallel::Writer w;
    w.Double(
        Objective(scene, space, obs, options.misfit).Evaluate(summary->best_method().best).value);
    return w.bytes();
  });
  for (int k = 1; k <= options.noise_seeds; ++k) {
    const std::uint64_t seed = summary->seed + static_cast<std::uint64_t>(k);
    const double misfit = parallel::Reader(misfits[static_cast<std::size_t>(k - 1)]).Double();
    summary->noise_seeds.push_back(seed);
    summary->noise_misfits.push_back(misfit);
    all.push_back(misfit);
  }
  summary->misfit_noise_sd = core::SampleStandardDeviation(all);
  summary->noise_dip = NoiseDip(summary->misfit_after.value, summary->noise_misfits);
}

// CalibrationOptions::noise_check_seeds: the misfit at the start at other
// seeds against the spread of the reach design's misfits.
void CheckNoise(const sites::Site& site, const observations::Observations& obs,
                const CalibrationOptions& options, const ParameterSpace& space,
                CalibrationSummary* summary) {
  if (options.noise_check_seeds <= 0 || !summary->reach) return;
  CalibrationSummary::NoiseCheck& check = summary->noise_check;
  check.start_misfits = {summary->misfit_before.value};
  const std::vector<std::string> misfits = parallel::Map(options.noise_check_seeds, [&](int k) {
    const std::uint64_t seed = summary->seed + static_cast<std::uint64_t>(k + 1);
    const core::Scene scene = RunScene(site, summary->rocks, seed, options.threads);
    parallel::Writer w;
    w.Double(Objective(scene, space, obs, options.misfit).Evaluate(summary->start).value);
    return w.bytes();
  });
  for (const std::string& m : misfits) check.start_misfits.push_back(parallel::Reader(m).Double());
  check.start_sd = core::SampleStandardDeviation(check.start_misfits);
  std::vector<double> design;
  for (const ReachPoint& p : summary->reach->points)
    if (!p.penalised) design.push_back(p.misfit);
  const ContenderSpread spread = SpreadOfContenders(design);
  check.design_spread = spread.spread;
  check.contenders = spread.points;
  check.ratio = check.design_spread > 0 ? check.start_sd / check.design_spread
                                        : std::numeric_limits<double>::infinity();
  check.noise_dominates = check.ratio > options.noise_check_ratio;
  check.rocks_checked = summary->rocks;
  check.rocks_needed = summary->rocks;
  check.rocks_used = summary->rocks;
  char text[400];
  std::snprintf(text, sizeof text,
                "the misfit at the start varies by %.3g (sd over %zu seeds) against a spread of "
                "%.3g over the design's best %d points (ratio %.2f %s %.2f)",
                check.start_sd, check.start_misfits.size(), check.design_spread, check.contenders,
                check.ratio, check.noise_dominates ? ">" : "<=", options.noise_check_ratio);
  check.message = std::string(check.noise_dominates ? "noise dominates: " : "noise small: ") + text;
  check.done = true;
  if (!check.noise_dominates) return;
  // The noise's standard deviation falls as 1 / sqrt(rocks); at most 100 times the rocks.
  const double wanted =
      std::isfinite(check.ratio) ? std::pow(check.ratio / options.noise_check_ratio, 2.0) : 100.0;
  const double factor = std::min(wanted, 100.0);
  check.rocks_needed = static_cast<int>(std::ceil(summary->rocks * factor));
  const int multiple = std::min(options.noise_raise, static_cast<int>(std::ceil(factor)));
  check.rocks_used = summary->rocks * multiple;
  if (multiple > 1) {
    std::snprintf(text, sizeof text, "; the rocks per evaluation raised from %d to %d (%d times)",
                  check.rocks_checked, check.rocks_used, multiple);
    check.message += text;
  }
  if (check.still_dominates())
    std::snprintf(text, sizeof text,
                  "; about %d rocks per evaluation (--rocks %d) would bring the ratio to %.2f",
                  check.rocks_needed, check.rocks_needed, options.noise_check_ratio);
  else
    std::snprintf(text, sizeof text, ", enough to bring the ratio to %.2f",
                  options.noise_check_ratio);
  check.message += text;
}

// CalibrationOptions::posterior: the posterior on the objective of the
// stage options.posterior_stage names (`scene`, its rocks and seed), reusing
// the reach design's evaluations in the first stage (space-filling), not
// the search's (crowded about its best point, they pulled the posterior to
// the optimum of that stage's one set of random numbers: docs/posterior.md,
// step 3), and appending to its log.
PosteriorResult RunPosteriorStage(const sites::Site& site, const observations::Observations& obs,
                                  const CalibrationOptions& options, const ParameterSpace& space,
                                  const core::Scene& scene, const CalibrationCallbacks& callbacks,
                                  const CalibrationSummary& summary) {
  const Objective objective(scene, space, obs, options.misfit);
  const bool refined =
      options.refine_factor > 1 && options.posterior_stage == PosteriorStage::kFinal;
  CalibrationOptions o = options;
  if (refined) {
    o.rocks = summary.final_rocks;
    o.refine_factor = 1;
    o.log_path = RefineLogPath(options.log_path);
  }
  o.resume = !o.log_path.empty() && std::filesystem::exists(o.log_path);
  std::optional<EvaluationLog> log = OpenLog(site, obs, o, space, scene);
  std::vector<Evaluation> reused;
  if (!refined && summary.reach) {
    // The design's residuals from its statistics (in the misfit's order).
    const ReachResult& r = *summary.reach;
    for (const ReachPoint& p : r.points) {
      if (p.penalised || p.simulated.size() != r.statistics.size() ||
          static_cast<int>(r.statistics.size()) != objective.residual_count())
        continue;
      Evaluation e;
      e.parameters = p.physical;
      e.misfit = p.misfit;
      e.log_scale = p.log_scale;
      for (std::size_t s = 0; s < r.statistics.size(); ++s)
        e.residuals.push_back((p.simulated[s] - r.statistics[s].observed) / p.sigma[s]);
      bool finite = true;
      for (double v : e.residuals) finite = finite && std::isfinite(v);
      if (finite) reused.push_back(std::move(e));
    }
  }
  PosteriorOptions po = *options.posterior;
  po.mcmc.seed = scene.options.seed;
  PosteriorResult result = SamplePosterior(objective, reused, po, log ? &*log : nullptr,
                                           callbacks.posterior, summary.misfit_before.residuals);
  if (const std::string points = PointReleaseWarning(scene); !points.empty())
    result.message += (result.message.empty() ? "" : " ") + points + ".";
  PredictiveBands(SiteDraw(site, obs, options.misfit, space, scene.total_rocks(), options.threads),
                  scene.options.seed, scene.total_rocks(), options.posterior->predictive_draws, &result,
                  callbacks.posterior);
  return result;
}

}  // namespace

bool NoiseDip(double own, const std::vector<double>& others) {
  if (others.size() < 2) return false;
  const double k = static_cast<double>(others.size());
  double mean = 0.0;
  for (const double m : others) mean += m / k;
  const double bound = mean - core::StudentT975(static_cast<int>(others.size()) - 1) *
                                  core::SampleStandardDeviation(others) * std::sqrt(1.0 + 1.0 / k);
  return own < bound;
}

Fingerprint CalibrationFingerprint(const sites::Site& site, const observations::Observations& obs,
                                   const CalibrationOptions& options, const ParameterSpace& space) {
  core::Scene scene = site.scene;
  if (options.rocks > 0) scene.SetTotalRocks(options.rocks);
  Fingerprint f;
  const std::vector<std::string> inputs =
      site.inputs.empty() ? std::vector<std::string>{site.path} : site.inputs;
  const std::filesystem::path site_dir = std::filesystem::path(site.path).parent_path();
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k].empty()) continue;
    const std::string name = std::filesystem::path(inputs[k])
                                 .lexically_relative(site_dir.empty() ? "." : site_dir)
                                 .string();
    f.Add(k == 0 ? "site file" : "site data file " + name, HashFile(inputs[k]));
  }
  if (!obs.path.empty()) f.Add("observations file", HashFile(obs.path));
  const std::filesystem::path obs_dir = std::filesystem::path(obs.path).parent_path();
  for (std::size_t k = 1; k < obs.inputs.size(); ++k)
    f.Add("observations data file " + std::filesystem::path(obs.inputs[k])
                                          .lexically_relative(obs_dir.empty() ? "." : obs_dir)
                                          .string(),
          HashFile(obs.inputs[k]));
  if (!options.observations_subset.empty())
    f.Add("observations subset", options.observations_subset);
  f.Add("seed", std::to_string(options.seed ? *options.seed : scene.options.seed));
  f.Add("rocks", std::to_string(scene.total_rocks()));
  // The stems the rocks strike (none with --no-forest); left out for a bare
  // scene, so that logs written before forests existed resume.
  if (!scene.forest.empty()) f.Add("forest stems", std::to_string(scene.forest.stems.size()));
  std::string methods;
  for (const Method m : options.methods)
    methods += std::string(methods.empty() ? "" : ",") + MethodToString(m);
  f.Add("methods", methods);
  const MethodOptions& m = options.method;
  std::ostringstream method;
  method.precision(17);
  method << "polish_fraction " << m.polish_fraction << ", initial_step " << m.initial_step
         << ", ceres_step " << m.ceres_step << ", ceres_loss " << CeresLossToString(m.ceres_loss)
         << ", estimate " << EstimateToString(m.estimate) << ", smoothing_radius "
         << m.smoothing_radius;
  f.Add("method options", method.str());
  std::ostringstream misfit;
  misfit.precision(17);
  misfit << "levels " << Numbers(options.misfit.levels) << ", include_max "
         << options.misfit.include_max << ", penalty " << options.misfit.penalty << ", sigma_floor "
         << options.misfit.sigma_floor;
  f.Add("misfit options", misfit.str());
  std::ostringstream parameters;
  parameters.precision(17);
  for (const Parameter& p : space.parameters())
    parameters << p.label() << " [" << p.lower << ", " << p.upper << "] ";
  parameters << "start " << Numbers(space.Current(scene));
  f.Add("parameters", parameters.str());
  // Where the refining search starts (RaceCandidates); left out without a
  // race, so that logs written before races existed resume.
  if (options.race_points > 0) f.Add("race", std::to_string(options.race_points));
  return f;
}

void SearchMethods(const ObjectiveFunction& objective, const std::vector<double>& start,
                   const std::vector<Method>& methods, const MethodOptions& options,
                   EvaluationLog* log, const CalibrationCallbacks& callbacks,
                   CalibrationSummary* summary) {
  const std::size_t first = summary->methods.size();
  for (const Method method : methods) {
    if (callbacks.method_started) callbacks.method_started(Stage{method});
    summary->methods.push_back(
        RunMethod(method, objective, start, options, log, callbacks.evaluated));
    if (callbacks.method_finished) callbacks.method_finished(summary->methods.back());
  }
  summary->best = static_cast<int>(first);
  for (std::size_t k = first + 1; k < summary->methods.size(); ++k)
    if (summary->methods[k].best_misfit < summary->best_method().best_misfit)
      summary->best = static_cast<int>(k);
  if (summary->methods.size() == first || summary->best_method().best.empty())
    throw std::runtime_error("no evaluation finished; nothing to report");
}

void CheckCalibration(const sites::Site& site, const CalibrationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("calibration options", error);
  ParameterSpace::FromSite(site);
}

void CheckResume(const sites::Site& site, const observations::Observations& obs,
                 const CalibrationOptions& given, int folds) {
  if (!given.resume || given.log_path.empty()) return;
  CheckCalibration(site, given);
  const ParameterSpace space = ParameterSpace::FromSite(site);
  const CalibrationOptions options = given.Resolved(space.size());
  const core::Scene scene = RunScene(site, options.rocks, options.seed, options.threads);
  // The rocks of the search are known unless the noise check may raise them.
  const bool raised =
      options.reach_points > 0 && options.noise_check_seeds > 0 && options.noise_raise > 1;
  const auto check = [&](const CalibrationOptions& o) {
    if (!std::filesystem::exists(o.log_path)) return;  // a stage not begun starts afresh
    std::optional<int> rocks;
    if (!raised) rocks = scene.total_rocks();
    EvaluationLog::Check(o.log_path, space, scene.options.seed, rocks,
                         CalibrationFingerprint(site, obs, o, space));
  };
  const auto stages = [&](const CalibrationOptions& o) {
    check(o);
    if (o.refine_factor <= 1) return;
    CalibrationOptions r = o;
    r.log_path = RefineLogPath(o.log_path);
    r.refine_factor = 1;
    if (!std::filesystem::exists(r.log_path)) return;
    std::optional<int> rocks;
    if (!raised) rocks = scene.total_rocks() * o.refine_factor;
    if (rocks) r.rocks = *rocks;
    EvaluationLog::Check(r.log_path, space, scene.options.seed, rocks,
                         CalibrationFingerprint(site, obs, r, space));
  };
  stages(options);
  for (int k = 1; k <= folds; ++k) {
    // As CrossValidate names and fingerprints each fold's log.
    CalibrationOptions o = options;
    o.posterior.reset();
    o.observations_subset = "fold " + std::to_string(k) + " of " + std::to_string(folds) +
                            ", seed " + std::to_string(scene.options.seed);
    o.log_path = (std::filesystem::path(options.log_path).parent_path() /
                  ("evaluations-fold-" + std::to_string(k) + ".jsonl"))
                     .string();
    stages(o);
  }
}

CalibrationSummary Calibrate(const sites::Site& site, const observations::Observations& obs,
                             const CalibrationOptions& given,
                             const CalibrationCallbacks& callbacks) {
  const auto start_time = std::chrono::steady_clock::now();
  std::string error;
  if (!given.IsValid(&error)) throw InputError("calibration options", error);
  const ParameterSpace space = ParameterSpace::FromSite(site);  // once per run
  CalibrationOptions options = given.Resolved(space.size());
  core::Scene scene = RunScene(site, options.rocks, options.seed, options.threads);
  const bool refine = options.refine_factor > 1;
  MethodOptions method_options = options.method;
  method_options.seed = scene.options.seed;
  if (refine) method_options.max_evals = FirstStageEvaluations(options);

  std::optional<Objective> objective(std::in_place, scene, space, obs, options.misfit);

  CalibrationSummary summary;
  summary.site = scene.name;
  summary.units = site.units;
  summary.grid_spacing_m = scene.grid.spacing;
  summary.space = space;
  summary.rocks = scene.total_rocks();
  summary.seed = scene.options.seed;
  summary.start = space.Current(scene);
  summary.misfit_before = objective->Evaluate(summary.start);
  summary.search_start = summary.start;
  if (callbacks.started) callbacks.started(summary);
  if (options.reach_points > 0) {
    ReachOptions reach;
    reach.points = options.reach_points;
    reach.seed = scene.options.seed;
    summary.reach = RunReach(*objective, reach);
    const ReachResult& r = *summary.reach;
    if (r.best_point >= 0) {
      const ReachPoint& best_point = r.points[static_cast<std::size_t>(r.best_point)];
      if (!best_point.penalised && best_point.misfit < summary.misfit_before.value)
        summary.search_start = best_point.physical;
    }
    if (callbacks.reach_done) callbacks.reach_done(r);
    CheckNoise(site, obs, options, space, &summary);
    if (summary.noise_check.done && summary.noise_check.rocks_used > summary.rocks) {
      // The search, its log and the stages after it at the raised rocks.
      options.rocks = summary.noise_check.rocks_used;
      scene = RunScene(site, options.rocks, options.seed, options.threads);
      objective.emplace(scene, space, obs, options.misfit);
      summary.rocks = scene.total_rocks();
      summary.misfit_before = objective->Evaluate(summary.start);
    }
    if (summary.noise_check.done && callbacks.noise_checked) callbacks.noise_checked(summary);
  }
  std::optional<EvaluationLog> log;
  try {
    log = OpenLog(site, obs, options, space, scene, callbacks.log_opened);
  } catch (const InputError& e) {
    // The rocks the noise check chose follow the reach design, which
    // --max-evals and --reach size: say so rather than blame "rocks" alone.
    if (!summary.noise_check.done || e.detail().find("was written: rocks") == std::string::npos)
      throw;
    throw InputError(e.where(),
                     e.detail() + " (the rocks per evaluation, " + std::to_string(summary.rocks) +
                         " here, follow the noise check after the "
                         "reach design of " +
                         std::to_string(options.reach_points) +
                         " points, which --max-evals and --reach size: give the stopped run's, "
                         "or --rocks N to fix the count)");
  }
  SearchMethods(*objective, summary.search_start, options.methods, method_options,
                log ? &*log : nullptr, callbacks, &summary);
  summary.final_rocks = summary.rocks;
  core::Scene final_scene = scene;
  if (refine) {
    final_scene = RefineStage(site, obs, options, space, callbacks, &summary);
    summary.final_rocks = final_scene.total_rocks();
  }
  const MethodResult& best = summary.best_method();
  summary.termination = best.termination;
  if (options.posterior)
    summary.posterior =
        RunPosteriorStage(site, obs, options, space,
                          options.posterior_stage == PosteriorStage::kFinal ? final_scene : scene,
                          callbacks, summary);

  // The site at the calibrated values, simulated with what its files, the
  // misfit and the report need.
  core::Scene calibrated = final_scene;
  space.Apply(best.best, &calibrated);
  ScoreSummary score = Score(calibrated, obs, options.misfit);
  summary.calibrated = std::move(score.scene);
  summary.simulation = std::move(score.simulation);
  summary.misfit_after = std::move(score.misfit);
  MeasureMisfitNoise(site, obs, options, space, &summary);
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return summary;
}

}  // namespace rockcal::calibrate
