#include "rockcal/reports/calibration_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "rockcal/calibrate/default_table.h"
#include "rockcal/calibrate/parameters_file.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/format.h"
#include "rockcal/core/scene.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::reports {
namespace {

using core::FormatNumber;

using calibrate::MethodResult;
using calibrate::Parameter;
using calibrate::ParameterKind;

// A value in the site's units for display (roughness in ft for US sites).
std::string SiteValue(const Parameter& p, double v, sites::Units units) {
  if (p.kind == ParameterKind::kRoughness && units == sites::Units::kUS)
    return FormatNumber(v / core::kFoot, "%.3g") + " ft";
  if (p.kind == ParameterKind::kContactTime) return FormatNumber(v * 1e3, "%.3g") + " ms";
  if (p.kind == ParameterKind::kRoughness) return FormatNumber(v, "%.3g") + " m";
  if (p.kind == ParameterKind::kVegetation)
    return FormatNumber(v / sites::StressToSI(1.0, units), "%.3g") + " " + sites::StressUnit(units);
  return FormatNumber(v, "%.3f");
}

// The best method's standard error of parameter k, if computed.
const double* StdError(const MethodResult& m, std::size_t k) {
  const auto& u = m.uncertainty;
  return u.computed && !u.rank_deficient && k < u.std_error.size() ? &u.std_error[k] : nullptr;
}

}  // namespace

std::string ParametersCsv(const calibrate::CalibratedSite& site) {
  std::ostringstream out;
  const bool post = site.has_posterior();
  out << "material,class,name,value,lower,upper,std_error,unit"
      << (post ? ",posterior_median,posterior_p05,posterior_p95,determined" : "") << "\n";
  for (const calibrate::CalibratedParameter& p : site.parameters) {
    out << p.material << ',' << p.material_class << ',' << p.name << ','
        << FormatNumber(p.value, "%.10g") << ',' << FormatNumber(p.lower, "%.10g") << ','
        << FormatNumber(p.upper, "%.10g") << ','
        << (p.std_error ? FormatNumber(*p.std_error, "%.6g") : "") << ','
        << calibrate::SiUnitOf(p);
    if (p.posterior)
      out << ',' << FormatNumber(p.posterior->median, "%.6g") << ','
          << FormatNumber(p.posterior->p05, "%.6g") << ',' << FormatNumber(p.posterior->p95, "%.6g")
          << ',' << (p.posterior->determined ? "yes" : "no");
    out << '\n';
  }
  return out.str();
}

std::string ParametersMarkdown(const CalibrationSummary& record) {
  const MethodResult& best = record.methods[static_cast<std::size_t>(record.best)];
  std::ostringstream out;
  out << "| material | class | parameter | calibrated | std. error | start | bounds |\n"
      << "|---|---|---|---|---|---|---|\n";
  const auto& ps = record.space.parameters();
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const double* se = StdError(best, k);
    // Within 1 % of the range from a bound, as report.html and rockcal table
    // flag it: stopped by the bound, not by the data.
    const calibrate::BoundPosition at =
        calibrate::AtBound(best.best[k], ps[k].lower, ps[k].upper, 0.01);
    // And what the posterior says of it, where there is one.
    std::string flags;
    if (at != calibrate::BoundPosition::kInside)
      flags += std::string(" **at the ") + calibrate::BoundName(at) + " bound**";
    if (record.posterior) {
      const calibrate::ParameterPosterior& q = record.posterior->parameters[k];
      if (q.undetermined) flags += " **not determined**";
      if (best.best[k] < q.p05 || best.best[k] > q.p95) flags += " **outside its posterior**";
    }
    out << "| " << ps[k].material << " | " << ps[k].class_name() << " | " << ps[k].name() << " | "
        << SiteValue(ps[k], best.best[k], record.units) << flags
        << " | " << (se ? SiteValue(ps[k], *se, record.units) : std::string("-")) << " | "
        << SiteValue(ps[k], record.start[k], record.units) << " | ["
        << SiteValue(ps[k], ps[k].lower, record.units) << ", "
        << SiteValue(ps[k], ps[k].upper, record.units) << "] |\n";
  }
  const bool refined = record.final_rocks > 0 && record.final_rocks != record.rocks;
  out << "\nSite " << record.site << "; " << (refined ? "stage " : "method ") << best.stage.name()
      << ", " << best.evaluations << " evaluations in " << FormatNumber(best.wall_seconds, "%.1f")
      << " s; misfit " << FormatNumber(record.misfit_before.value, "%.4g") << " before, "
      << FormatNumber(best.best_misfit, "%.4g") << " after, both at "
      << (record.final_rocks > 0 ? record.final_rocks : record.rocks)
      << " rocks (half the sum of squared residuals in units of their uncertainty); ";
  if (refined)
    out << record.rocks << " rocks per evaluation in the first stage, " << record.final_rocks
        << " in the refining stage";
  else
    out << record.rocks << " rocks per evaluation";
  out << ", seed " << record.seed << ".\n";
  if (const std::string d = DeterminationSentence(record); !d.empty()) out << "\n" << d << "\n";
  if (record.posterior) out << "\n" << PosteriorMarkdown(record);
  return out.str();
}

std::string PosteriorMarkdown(const CalibrationSummary& record) {
  if (!record.posterior) return "";
  const calibrate::PosteriorResult& post = *record.posterior;
  std::ostringstream out;
  out << "Posterior (uniform prior on the bounds; " << post.samples.size() << " samples):\n\n"
      << "| parameter | median | 5 % | 95 % | interval / prior | determined by the data |\n"
      << "|---|---|---|---|---|---|\n";
  const auto& ps = record.space.parameters();
  std::vector<std::string> loose;
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const calibrate::ParameterPosterior& q = post.parameters[k];
    out << "| " << ps[k].label() << " | " << SiteValue(ps[k], q.median, record.units) << " | "
        << SiteValue(ps[k], q.p05, record.units) << " | " << SiteValue(ps[k], q.p95, record.units)
        << " | " << FormatNumber(q.width_share, "%.2f") << " | "
        << (q.undetermined ? "no (about as wide as the prior)" : "yes") << " |\n";
    if (q.undetermined) loose.push_back(ps[k].label());
  }
  std::vector<std::string> pairs;
  for (std::size_t a = 0; a < ps.size(); ++a)
    for (std::size_t b = a + 1; b < ps.size(); ++b)
      if (std::abs(post.correlation[a][b]) >= 0.7)
        pairs.push_back(ps[a].label() + " and " + ps[b].label() + " (" +
                        FormatNumber(post.correlation[a][b], "%+.2f") + ")");
  out << "\n";
  if (!loose.empty()) {
    out << "Not determined by the observations (5-95 % interval over "
        << "three quarters of the prior's): ";
    for (std::size_t k = 0; k < loose.size(); ++k) out << (k ? ", " : "") << loose[k];
    out << ". Carry these values with their whole interval, or fix them from other sources.\n";
  }
  if (const std::string advice = PosteriorAdvice(record); !advice.empty()) out << advice << "\n";
  if (!pairs.empty()) {
    out << "Strongly correlated (determined only together): ";
    for (std::size_t k = 0; k < pairs.size(); ++k) out << (k ? ", " : "") << pairs[k];
    out << ".\n";
  }
  out << "Emulated from " << post.emulated << " evaluations (" << post.reused
      << " of the reach design, " << post.evaluated << " of the posterior stage, " << post.rounds
      << " refining rounds); max R-hat " << FormatNumber(post.max_rhat, "%.3f") << ".\n";
  if (post.left_out > 0)
    out << "Its likelihood leaves out the " << post.left_out
        << " per-run residuals: the pooled runout quantiles compare the same stops "
           "(docs/posterior.md, \"Tracked runs\").\n";
  if (!post.message.empty()) out << "Warning: " << post.message << "\n";
  if (!post.bands.empty()) {
    out << "Posterior predictive: " << post.BandsInside() << " of " << post.bands.size()
        << " observed statistics inside the 5-95 % band of a new observation "
           "(90 % or a little more when the model holds; "
        << post.band_draws << " posterior draws at " << post.band_rocks
        << " rocks, each at its own seed).\n";
    if (!post.statistic_bands.empty())
      out << "The same draws' bands of the runout and of every partition's passing share, "
             "heights, velocity and energies: calibration.json (posterior.predictive.statistics) "
             "and report.html.\n";
  }
  return out.str();
}

std::string PosteriorAdvice(const CalibrationSummary& record) {
  if (!record.posterior) return "";
  const std::vector<double>& value = record.best_method().best;
  const auto& ps = record.space.parameters();
  std::vector<std::string> outside;
  for (std::size_t k = 0; k < ps.size() && k < value.size(); ++k) {
    const calibrate::ParameterPosterior& q = record.posterior->parameters[k];
    if (value[k] >= q.p05 && value[k] <= q.p95) continue;
    outside.push_back(ps[k].label() + " " + SiteValue(ps[k], value[k], record.units) +
                      " against [" + SiteValue(ps[k], q.p05, record.units) + ", " +
                      SiteValue(ps[k], q.p95, record.units) + "], median " +
                      SiteValue(ps[k], q.median, record.units));
  }
  if (outside.empty()) return "";
  std::string s = "The search's value lies outside its posterior 5-95 % interval for ";
  for (std::size_t k = 0; k < outside.size(); ++k) s += (k ? "; " : "") + outside[k];
  return s +
         ". Use the posterior for a design: the search's point is the lowest misfit of one set "
         "of simulated rocks, which their Monte Carlo noise moves, while the posterior averages "
         "over that noise and carries the uncertainty (its median, or `rockcal simulate "
         "--parameters` of this folder, which draws from it).";
}

std::string DeterminationSentence(const CalibrationSummary& record) {
  const MethodResult& best = record.methods[static_cast<std::size_t>(record.best)];
  const calibrate::Uncertainty& u = best.uncertainty;
  if (!u.computed)
    return "Standard errors not computed (too few evaluations near the calibrated values for a "
           "model of the residuals): how well the observations determine each value is unknown.";
  if (u.rank_deficient) return "Standard errors not available: " + u.message + ".";
  const auto& ps = record.space.parameters();
  std::vector<std::string> loose, pairs;
  for (std::size_t k = 0; k < ps.size() && k < u.std_error.size(); ++k)
    if (u.std_error[k] > 0.25 * (ps[k].upper - ps[k].lower))
      loose.push_back(ps[k].label() + " (" + SiteValue(ps[k], u.std_error[k], record.units) + ")");
  for (std::size_t a = 0; a < ps.size() && a < u.correlation.size(); ++a)
    for (std::size_t b = a + 1; b < ps.size() && b < u.correlation[a].size(); ++b)
      if (std::abs(u.correlation[a][b]) >= 0.9)
        pairs.push_back(ps[a].label() + " and " + ps[b].label() + " (" +
                        FormatNumber(u.correlation[a][b], "%.2f") + ")");
  auto join = [](const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& x : v) out += (out.empty() ? "" : ", ") + x;
    return out;
  };
  std::string s;
  if (!loose.empty())
    s += "Not determined by the observations (standard error above a quarter of the range): " +
         join(loose) + ". ";
  if (!pairs.empty())
    s += "Determined only together (correlation of 0.9 or more in size): " + join(pairs) + ". ";
  if (!s.empty()) s += "Standard errors: " + u.message + ".";
  return s;
}

std::string TraceCsv(const CalibrationSummary& record) {
  std::ostringstream out;
  out << "method,evaluation,wall_seconds,misfit,best_misfit";
  for (const auto& p : record.space.parameters()) out << ',' << p.label();
  out << ",replayed\n";
  for (const MethodResult& m : record.methods) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& e : m.trace) {
      best = std::min(best, e.misfit);
      out << m.stage.name() << ',' << e.index << ',' << FormatNumber(e.elapsed, "%.4f") << ','
          << FormatNumber(e.misfit, "%.8g") << ',' << FormatNumber(best, "%.8g");
      for (double v : e.parameters) out << ',' << FormatNumber(v, "%.10g");
      out << ',' << (e.replayed ? 1 : 0) << '\n';
    }
  }
  return out.str();
}

double LowestMisfitOfAll(const CalibrationSummary& record) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& m : record.methods) lowest = std::min(lowest, m.lowest_misfit);
  return lowest;
}

nlohmann::json VerdictJson(const CalibrationSummary& record) {
  const observations::FitVerdict v = observations::AssessFit(record.misfit_after);
  const core::SimulationResult& sim = record.simulation;
  return {{"poor", v.poor},
          {"verdict", v.poor ? "poor" : v.fair ? "fair" : "good"},
          {"count_chance", v.count_chance},
          {"largest_chance", v.largest_chance},
          {"sentence", v.Sentence()},
          {"outside_2_sigma", v.outside},
          {"compared", v.compared},
          {"outcomes",
           {{"stopped", sim.count(core::Outcome::kStopped)},
            {"left", sim.count(core::Outcome::kLeft)},
            {"timeout", sim.count(core::Outcome::kTimeout)}}}};
}

namespace {

// The noise check before the search (CalibrationSummary::NoiseCheck).
nlohmann::json NoiseCheckJson(const CalibrationSummary& record) {
  const CalibrationSummary::NoiseCheck& c = record.noise_check;
  return {{"start_misfits", c.start_misfits},
          {"start_sd", c.start_sd},
          {"design_spread", c.design_spread},
          {"contenders", c.contenders},
          {"ratio", std::isfinite(c.ratio) ? nlohmann::json(c.ratio) : nlohmann::json(nullptr)},
          {"noise_dominates", c.noise_dominates},
          {"rocks", c.rocks_checked},
          {"rocks_needed", c.rocks_needed},
          {"rocks_used", c.rocks_used},
          {"message", c.message}};
}

// Tracked runs: each run's runout against the median of its group's rocks.
nlohmann::json RunsJson(const observations::Misfit& misfit) {
  nlohmann::json runs = nlohmann::json::array();
  for (const observations::RunFit& r : misfit.runs)
    runs.push_back({{"id", r.id},
                    {"observed_m", r.observed},
                    {"simulated_median_m", r.simulated},
                    {"rocks", r.rocks},
                    {"stopped", r.stopped},
                    {"stuck_at_release", r.stuck},
                    {"spread_m", r.spread},
                    {"sigma_m", r.sigma}});
  return {{"mean_abs_error_m", misfit.MeanRunError()},
          {"stuck_at_release", misfit.StuckRocks()},
          {"per_run", runs}};
}

// The tracks' distributions (observed and simulated: count and quartiles)
// and their verdict.
nlohmann::json TracksJson(const observations::Misfit& misfit) {
  const observations::TrackFit& t = misfit.tracks;
  auto side = [](const std::vector<double>& v) {
    nlohmann::json j = {{"n", v.size()}};
    for (const double level : observations::Tracks::Levels())
      j[observations::LevelName(level)] =
          v.empty() ? nlohmann::json(nullptr) : nlohmann::json(core::Quantile(v, level));
    return j;
  };
  auto both = [&](const std::vector<double>& observed, const std::vector<double>& simulated) {
    return nlohmann::json{{"observed", side(observed)}, {"simulated", side(simulated)}};
  };
  const observations::FitVerdict v = observations::AssessTracks(misfit);
  return {{"tracks", t.tracks},
          {"simulated_rocks", t.rocks},
          {"jump_height_m", both(t.observed_heights, t.simulated_heights)},
          {"jump_length_m", both(t.observed_lengths, t.simulated_lengths)},
          {"impact_speed_m_s", both(t.observed_speeds, t.simulated_speeds)},
          {"verdict", v.poor   ? "poor"
                      : v.fair ? "fair"
                               : "good"},
          {"sentence", observations::TracksVerdictSentence(misfit)}};
}

}  // namespace

nlohmann::json CalibrationJson(const CalibrationSummary& record) {
  const MethodResult& best = record.methods[static_cast<std::size_t>(record.best)];
  const double best_all = LowestMisfitOfAll(record);
  nlohmann::json methods = nlohmann::json::array();
  for (const MethodResult& m : record.methods) {
    nlohmann::json u = nullptr;
    if (m.uncertainty.computed) {
      u = {{"rank_deficient", m.uncertainty.rank_deficient},
           {"message", m.uncertainty.message},
           {"std_error", m.uncertainty.std_error},
           {"correlation", m.uncertainty.correlation},
           {"singular_values", m.uncertainty.singular_values}};
    }
    const double reach = calibrate::TimeToReach(m, best_all, 0.1);
    methods.push_back({{"method", m.stage.name()},
                       {"termination", m.termination.message},
                       {"misfit", m.best_misfit},
                       {"parameters", m.best},
                       {"evaluations", m.evaluations},
                       {"simulated", m.simulated},
                       {"wall_seconds", m.wall_seconds},
                       {"seconds_to_within_10pct_of_best",
                        reach >= 0 ? nlohmann::json(reach) : nlohmann::json(nullptr)},
                       {"lowest_misfit", m.lowest_misfit},
                       {"lowest_parameters", m.lowest},
                       {"smoothed_estimate",
                        {{"used", m.smoothed.used},
                         {"message", m.smoothed.message},
                         {"points", m.smoothed.points},
                         {"radius", m.smoothed.radius},
                         {"predicted_misfit", m.smoothed.predicted_misfit}}},
                       {"uncertainty", u}});
  }
  nlohmann::json names = nlohmann::json::array();
  for (const auto& p : record.space.parameters()) names.push_back(p.label());
  nlohmann::json race = nlohmann::json::array();
  for (const auto& entry : record.race)
    race.push_back({{"from", entry.from},
                    {"values", entry.physical},
                    {"misfit_before", entry.misfit_before},
                    {"misfit", entry.misfit},
                    {"penalised", entry.penalised}});
  nlohmann::json out = {{"site", record.site},
          {"method", best.stage.name()},
          {"termination", best.termination.message},
          {"evaluations", best.evaluations},
          {"wall_seconds", record.wall_seconds},
          {"rocks_per_evaluation", record.rocks},
          {"rocks_final", record.final_rocks},
          {"seed", record.seed},
          {"misfit_noise",
           {{"seeds", record.noise_seeds},
            {"misfits", record.noise_misfits},
            {"sd", record.noise_seeds.empty() ? nlohmann::json(nullptr)
                                              : nlohmann::json(record.misfit_noise_sd)},
            {"own_seed_dip", record.noise_dip}}},
          {"parameter_names", names},
          {"start", record.start},
          {"search_start", record.search_start},
          {"reach_points", record.reach ? static_cast<int>(record.reach->points.size()) : 0},
          {"race", {{"rocks", record.race.empty() ? 0 : record.final_rocks},
                    {"candidates", race},
                    {"winner", record.race_winner >= 0 ? nlohmann::json(record.race_winner)
                                                       : nlohmann::json(nullptr)}}},
          {"calibrated", best.best},
          {"misfit_before", record.misfit_before.value},
          {"misfit_after", record.misfit_after.value},
          {"fit_before", calibrate::ResidualsJson(record.misfit_before)},
          {"fit", calibrate::ResidualsJson(record.misfit_after)},
          {"verdict", VerdictJson(record)},
          {"methods", methods}};
  if (record.noise_check.done) out["noise_check"] = NoiseCheckJson(record);
  if (!record.misfit_after.runs.empty()) out["runs"] = RunsJson(record.misfit_after);
  if (record.misfit_after.tracks.tracks > 0) out["tracks"] = TracksJson(record.misfit_after);
  if (!record.misfit_after.impacts.empty())
    out["impacts"] =
        calibrate::ImpactsJson(record.misfit_after, calibrate::GroupIds(record.calibrated));
  if (record.posterior) out["posterior"] = calibrate::PosteriorJson(*record.posterior);
  return out;
}

std::string ComparisonCsv(const CalibrationSummary& record) {
  const double best_all = LowestMisfitOfAll(record);
  std::ostringstream out;
  out << "method,misfit,lowest_misfit,evaluations,simulated,wall_seconds,"
         "seconds_to_within_10pct_of_best,termination\n";
  for (const MethodResult& m : record.methods) {
    const double reach = calibrate::TimeToReach(m, best_all, 0.1);
    std::string term = m.termination.message;
    std::replace(term.begin(), term.end(), ',', ';');
    out << m.stage.name() << ',' << FormatNumber(m.best_misfit, "%.6g") << ','
        << FormatNumber(m.lowest_misfit, "%.6g") << ',' << m.evaluations << ',' << m.simulated
        << ',' << FormatNumber(m.wall_seconds, "%.2f") << ','
        << (reach >= 0 ? FormatNumber(reach, "%.2f") : "") << ",\"" << term << "\"\n";
  }
  return out.str();
}

std::string ComparisonMarkdown(const CalibrationSummary& record) {
  const double best_all = LowestMisfitOfAll(record);
  std::ostringstream out;
  out << "| method | misfit | lowest evaluated | evaluations | wall s | s to within 10 % of "
         "best | stopped because |\n"
      << "|---|---|---|---|---|---|---|\n";
  for (const MethodResult& m : record.methods) {
    const double reach = calibrate::TimeToReach(m, best_all, 0.1);
    out << "| " << m.stage.name() << " | " << FormatNumber(m.best_misfit, "%.4g") << " | "
        << FormatNumber(m.lowest_misfit, "%.4g") << " | " << m.evaluations << " | "
        << FormatNumber(m.wall_seconds, "%.1f") << " | "
        << (reach >= 0 ? FormatNumber(reach, "%.1f") : std::string("never")) << " | "
        << m.termination.message << " |\n";
  }
  return out.str();
}

nlohmann::json RepeatScatterJson(const std::optional<observations::RepeatScatter>& scatter) {
  if (!scatter) return nullptr;
  return {{"sets", scatter->sets},
          {"runs", scatter->runs},
          {"release_radius_m", observations::RepeatScatter::kRepeatRadius},
          {"own_median_abs_error_m", scatter->own_median_error_m},
          {"others_median_abs_error_m", scatter->others_median_error_m}};
}

nlohmann::json HoldoutJson(const calibrate::HoldoutSummary& holdout,
                           const CalibrationSummary& full) {
  auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  nlohmann::json folds = nlohmann::json::array();
  for (const calibrate::FoldResult& f : holdout.results)
    folds.push_back({{"fold", f.fold},
                     {"held_out_values", f.held_out_values},
                     {"in_sample_misfit", f.in_sample_misfit},
                     {"held_out_misfit", f.held_out_misfit},
                     {"runout_median_abs_error_m", optional(f.runout_error_m)},
                     {"calibrated", f.calibrated},
                     {"termination", f.termination.message}});
  return {{"folds", holdout.folds},
          {"seed", holdout.seed},
          {"in_sample_misfit", full.misfit_after.value},
          {"mean_in_sample_misfit", holdout.mean_in_sample_misfit},
          {"mean_held_out_misfit", holdout.mean_held_out_misfit},
          {"mean_runout_median_abs_error_m", optional(holdout.mean_runout_error_m)},
          {"repeat_scatter", RepeatScatterJson(holdout.repeat_scatter)},
          {"per_fold", folds}};
}

std::string HoldoutCsv(const calibrate::HoldoutSummary& holdout, const CalibrationSummary& full) {
  std::ostringstream out;
  out << "fold,held_out_values,in_sample_misfit,held_out_misfit,runout_median_abs_error_m";
  for (const auto& p : full.space.parameters()) out << ',' << p.label();
  out << '\n';
  for (const calibrate::FoldResult& f : holdout.results) {
    out << f.fold << ',' << f.held_out_values << ',' << FormatNumber(f.in_sample_misfit, "%.8g")
        << ',' << FormatNumber(f.held_out_misfit, "%.8g") << ','
        << (f.runout_error_m ? FormatNumber(*f.runout_error_m, "%.6g") : "");
    for (double v : f.calibrated) out << ',' << FormatNumber(v, "%.10g");
    out << '\n';
  }
  out << "mean,," << FormatNumber(holdout.mean_in_sample_misfit, "%.8g") << ','
      << FormatNumber(holdout.mean_held_out_misfit, "%.8g") << ','
      << (holdout.mean_runout_error_m ? FormatNumber(*holdout.mean_runout_error_m, "%.6g") : "");
  for (std::size_t k = 0; k < full.space.parameters().size(); ++k) out << ',';
  out << '\n';
  return out.str();
}

}  // namespace rockcal::reports
