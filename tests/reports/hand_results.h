// Results by hand for the report tests: stability cases and studies, a
// convergence result and a reach check with unknown values among them, and
// a small real sensitivity study; an example site and its report input.
#ifndef ROCKCAL_TESTS_REPORTS_HAND_RESULTS_H_
#define ROCKCAL_TESTS_REPORTS_HAND_RESULTS_H_

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/reports/study_report.h"
#include "rockcal/sites/site.h"

namespace rockcal::reports::testing {

// sites/examples/<name>/site.json.
inline sites::Site Example(const std::string& name) {
  return sites::LoadSite(std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/" + name +
                         "/site.json");
}

// The site section's input of a study's report on `site`.
inline StudyReportInput Input(const sites::Site& site) {
  StudyReportInput in;
  in.scene = &site.scene;
  in.site_file = site.path;
  in.units = site.units;
  in.notes = site.notes;
  return in;
}

inline calibrate::StabilityCase Case(const std::string& name, bool pass) {
  calibrate::StabilityCase c;
  c.name = name;
  c.description = "a case & its <description>";
  c.figures.rocks = 20;
  c.max_time = 60.0;
  c.figures.dt_min = c.figures.dt_max = 1e-4;
  c.figures.steps = 452092;
  c.figures.flights = 76547;
  c.wall_seconds = 0.1234;
  c.stopped = 13, c.left = 7, c.timeout = 0;
  c.figures.max_relative_energy_gain = 2.8e-11;
  c.figures.max_penetration = 0.0516;
  c.pass = pass;
  return c;
}

// Three cases by hand: a PASS, a FAIL with a reason and different steps, and
// a must-stop FAIL whose energy gain is not finite (null in the JSON), with a
// warning.
inline std::vector<calibrate::StabilityCase> HandCases() {
  std::vector<calibrate::StabilityCase> cases = {Case("site", true), Case("hardness_1", false),
                                                 Case("flat_runout", false)};
  cases[1].figures.dt_min = 2.61e-5;
  cases[1].figures.dt_shrunk = 20;
  cases[1].figures.tunneled = 2;
  cases[1].figures.max_relative_energy_gain = 0.5;
  cases[1].reason = "2 rocks tunneled; energy gain 0.5 > tolerance 0.001";
  cases[2].must_stop = true;
  cases[2].stopped = 18, cases[2].left = 0, cases[2].timeout = 2;
  cases[2].figures.non_finite = 1;
  cases[2].figures.max_relative_energy_gain = std::nan("");
  cases[2].figures.max_penetration = 3.68;
  cases[2].reason = "1 rocks non-finite; 2 of 20 rocks did not stop (0 left, 2 timeout)";
  cases[2].warning = "overlap reached 3.68 element radii (advisory limit 0.5)";
  return cases;
}

// The study of `cases` on `site` with the limits of `limits`.
inline calibrate::StabilityStudy Study(const sites::Site& site,
                                       const calibrate::StabilityLimits& limits,
                                       std::vector<calibrate::StabilityCase> cases) {
  calibrate::StabilityStudy study;
  study.site = site.scene.name;
  study.seed = site.scene.options.seed;
  study.limits = limits;
  study.cases = std::move(cases);
  return study;
}

inline calibrate::QuantityError ConvergenceQuantity(const std::string& name, double value,
                                                    double total, double mc,
                                                    double discretisation) {
  calibrate::QuantityError q;
  q.name = name;
  q.value = value;
  q.count = 100;
  q.total_error = total;
  q.mc_error = mc;
  q.discretisation_error = discretisation;
  q.discretisation_noise = 0.5 * discretisation;
  q.estimate = discretisation + mc;
  return q;
}

// N_c 10 and 20 at 50 and 100 rocks, two quantities; the runout of the
// cheapest setting rests on too few values (unknown errors).
inline calibrate::ConvergenceResult HandConvergence(bool recommend) {
  calibrate::ConvergenceResult r;
  r.site = "small <slope>";
  r.quantities = {"P-talus.height.p90", "runout.p50"};
  r.notes = {"runout quantities are distances & more"};
  r.target = 0.2;
  r.bootstrap = 200;
  r.confidence = 0.9;
  r.seed = 7;
  r.threads = 2;
  const int ncs[] = {10, 20}, counts[] = {50, 100};
  for (int nc : ncs)
    for (int rocks : counts) {
      calibrate::ConvergenceRow row;
      row.steps_per_contact = nc;
      row.rocks = rocks;
      row.figures.dt_min = 5e-3 / nc;
      row.figures.dt_max = nc == 10 ? 2 * row.figures.dt_min : row.figures.dt_min;
      row.figures.dt_shrunk = nc == 10 ? rocks : 0;
      row.wall_seconds = 0.001 * nc * rocks;
      row.figures.steps = 1000L * nc * rocks;
      row.stopped = rocks;
      const double mc = 0.3 * std::sqrt(50.0 / rocks), d = nc == 10 ? 0.04 : 0.0;
      row.quantities = {ConvergenceQuantity(r.quantities[0], 5.28, d + 0.01, mc, d),
                        ConvergenceQuantity(r.quantities[1], 91.8, d, 0.5 * mc, d)};
      if (nc == 10 && rocks == 50) {
        row.quantities[1].value = std::nan("");
        row.quantities[1].count = 3;
        row.quantities[1].total_error = row.quantities[1].mc_error =
            std::numeric_limits<double>::infinity();
        row.quantities[1].estimate = std::numeric_limits<double>::infinity();
      }
      row.max_total_error = row.max_mc_error = row.max_discretisation_error = 0.0;
      row.max_discretisation_noise = row.max_estimate = 0.0;
      for (const auto& q : row.quantities) {
        row.max_total_error = std::max(row.max_total_error, q.total_error);
        row.max_mc_error = std::max(row.max_mc_error, q.mc_error);
        row.max_discretisation_error =
            std::max(row.max_discretisation_error, q.discretisation_error);
        row.max_discretisation_noise =
            std::max(row.max_discretisation_noise, q.discretisation_noise);
        row.max_estimate = std::max(row.max_estimate, q.estimate);
      }
      row.meets_target = row.max_estimate <= r.target;
      r.rows.push_back(row);
    }
  r.reference = 3;
  r.recommended = recommend ? 3 : -1;
  r.recommendation = recommend ? "N_c = 20 with 100 rocks: error estimate 21.2 % <= target"
                               : "none: no setting's error estimate is within the target";
  return r;
}

// A small real study of profile2d (4 rocks a run).
inline calibrate::SensitivityResult SmallStudy(const sites::Site& site,
                                               calibrate::SensitivityMethod m) {
  calibrate::SensitivityOptions opt;
  opt.method = m;
  opt.samples = m == calibrate::SensitivityMethod::kMorris ? 2 : 4;
  opt.bootstrap = 20;
  opt.threads = 2;
  return calibrate::RunSensitivity(site, nullptr, opt);
}

inline calibrate::ReachStatistic ReachStat(const observations::ResidualId& id, double observed,
                                           double sigma, double min, double max,
                                           calibrate::ReachVerdict verdict) {
  calibrate::ReachStatistic s;
  s.id = id;
  s.observed = observed;
  s.sigma = sigma;
  s.min = min;
  s.max = max;
  s.min_point = 0;
  s.max_point = 1;
  s.closest_point = 1;
  s.closest_simulated = max;
  s.closest_sigmas = (max - observed) / sigma;
  s.points_with_value = 2;
  s.verdict = verdict;
  return s;
}

// Two points, four statistics by hand: one in reach, one far above the
// range (beyond the plot's 10 sigmas), one with no value at any point, and
// one in reach by its sigma only (at the edge).
inline calibrate::ReachResult HandReach() {
  calibrate::ReachResult r;
  r.candidates = 10;
  r.design_seed = 4;
  r.simulation_seed = 1;
  r.rocks = 41;
  calibrate::Parameter p;
  p.material = "talus";
  p.lower = 0.1;
  p.upper = 0.7;
  r.parameters = {p};
  using observations::ObservationKind;
  using observations::ResidualId;
  using observations::Statistic;
  const ResidualId distance = ResidualId::Of(ObservationKind::kRunoutDistance);
  r.statistics = {
      ReachStat(distance.With(Statistic::kQuantile, 0.5), 40.0, 2.5, 31.0, 57.0,
                calibrate::ReachVerdict::kInReach),
      ReachStat(distance.With(Statistic::kMax), 500.0, 3.0, 60.0, 95.0,
                calibrate::ReachVerdict::kAbove),
      ReachStat(ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] <P&1>")
                    .With(Statistic::kFraction),
                0.3, 0.05, NAN, NAN, calibrate::ReachVerdict::kNoValue),
      ReachStat(ResidualId::Of(ObservationKind::kRunoutLateral).With(Statistic::kQuantile, 0.9),
                10.0, 2.0, 1.0, 9.0, calibrate::ReachVerdict::kInReach)};
  calibrate::ReachStatistic& none = r.statistics[2];
  none.min_point = none.max_point = none.closest_point = -1;
  none.points_with_value = 0;
  none.closest_simulated = none.closest_sigmas = NAN;
  for (int k = 0; k < 2; ++k) {
    calibrate::ReachPoint point;
    point.unit = {0.25 + 0.5 * k};
    point.physical = {0.25 + 0.3 * k};
    point.misfit = 80.0 - 30.0 * k;
    point.simulated = {k ? 57.0 : 31.0, k ? 95.0 : 60.0, NAN, k ? 9.0 : 1.0};
    point.sigma = {2.5, 3.0, NAN, 2.0};
    r.points.push_back(point);
  }
  r.best_point = 1;
  r.wall_seconds = 1.25;
  return r;
}

}  // namespace rockcal::reports::testing

#endif  // ROCKCAL_TESTS_REPORTS_HAND_RESULTS_H_
