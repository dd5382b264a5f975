// to_json / from_json of the results: each struct, written and read back,
// is the struct again (every field its file holds, unknown numbers included:
// NaN values and +inf errors come back as such), and writes the same JSON.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::calibrate {
namespace {

using observations::ObservationKind;
using observations::ResidualId;
using observations::Statistic;

constexpr double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::nan("");

// Written, read back and written again: the same JSON; returns the struct read.
template <typename Result>
Result RoundTrip(const Result& result) {
  const nlohmann::json j = result;
  const Result back = j.get<Result>();
  EXPECT_EQ(nlohmann::json(back), j);
  // Through the text, as a file holds it.
  EXPECT_EQ(nlohmann::json(nlohmann::json::parse(j.dump(2)).get<Result>()), j);
  return back;
}

bool Same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

Parameter ParameterOf(const std::string& material, ParameterKind kind, double lower, double upper) {
  Parameter p;
  p.material = material;
  p.kind = kind;
  p.lower = lower, p.upper = upper;
  return p;
}

TEST(ResultsJson, StabilityStudyRoundTrips) {
  StabilityStudy study;
  study.site = "slope";
  study.limits.rocks = 7;
  study.limits.max_time = 12.5;
  study.limits.max_case_steps = 123456;
  study.limits.energy_tolerance = 2e-3;
  study.limits.penetration_limit = 0.25;
  StabilityCase a;
  a.name = "site";
  a.description = "the site's \"scene\"";
  a.max_time = 12.5;
  a.figures.rocks = 7;
  a.figures.steps = 4520921234L;
  a.figures.flights = 76547;
  a.figures.dt_min = 1.0 / 3e4;
  a.figures.dt_max = 2e-4;
  a.figures.dt_shrunk = 2;
  a.figures.max_relative_energy_gain = 2.8e-11;
  a.figures.max_penetration = 0.0516;
  a.wall_seconds = 0.1234;
  a.stopped = 4, a.left = 2, a.timeout = 1;
  a.pass = true;
  StabilityCase b = a;
  b.name = "flat_runout";
  b.must_stop = true;
  b.pass = false;
  b.figures.non_finite = 1;
  b.figures.tunneled = 3;
  b.figures.max_relative_energy_gain = kNaN;
  b.reason = "1 rocks non-finite";
  b.warning = "overlap";
  study.cases = {a, b};
  const StabilityStudy back = RoundTrip(study);
  EXPECT_EQ(back.site, "slope");
  EXPECT_EQ(back.limits.max_case_steps, 123456);
  EXPECT_EQ(back.limits.penetration_limit, 0.25);
  ASSERT_EQ(back.cases.size(), 2u);
  EXPECT_EQ(back.cases[0].figures.steps, 4520921234L);
  EXPECT_EQ(back.cases[0].figures.dt_min, 1.0 / 3e4);
  EXPECT_EQ(back.cases[0].figures.dt_shrunk, 2);
  EXPECT_EQ(back.cases[0].timeout, 1);
  EXPECT_TRUE(back.cases[0].pass);
  EXPECT_TRUE(std::isnan(back.cases[1].figures.max_relative_energy_gain));
  EXPECT_EQ(back.cases[1].figures.tunneled, 3);
  EXPECT_TRUE(back.cases[1].must_stop);
  EXPECT_FALSE(back.cases[1].pass);
  EXPECT_EQ(back.cases[1].reason, "1 rocks non-finite");
  EXPECT_EQ(back.passed(), 1);
}

ConvergenceResult Convergence() {
  ConvergenceResult r;
  r.site = "slope";
  r.quantities = {"P.height.p90"};
  r.notes = {"a note"};
  r.target = 0.05;
  r.bootstrap = 40;
  r.confidence = 0.9;
  r.seed = 18446744073709551557ull;
  r.threads = 2;
  for (int nc : {10, 20}) {
    ConvergenceRow row;
    row.steps_per_contact = nc;
    row.rocks = 30;
    row.figures.dt_min = 1e-3 / nc;
    row.figures.dt_max = 2e-3 / nc;
    row.figures.dt_shrunk = 3;
    row.figures.steps = 1000L * nc;
    row.figures.flights = 77;
    row.wall_seconds = 0.01 * nc;
    row.stopped = 28, row.left = 1, row.timeout = 1;
    QuantityError q;
    q.name = "P.height.p90";
    q.value = nc == 10 ? kNaN : 5.25;
    q.count = 29;
    q.total_error = nc == 10 ? kInf : 0.0;
    q.mc_error = 0.125;
    q.discretisation_error = 0.0625;
    q.discretisation_noise = 0.03;
    q.estimate = nc == 10 ? kInf : 0.1875;
    row.quantities = {q};
    row.max_total_error = q.total_error;
    row.max_mc_error = q.mc_error;
    row.max_discretisation_error = q.discretisation_error;
    row.max_discretisation_noise = q.discretisation_noise;
    row.max_estimate = q.estimate;
    row.meets_target = nc == 20;
    r.rows.push_back(row);
  }
  r.reference = 1;
  r.recommended = 1;
  r.recommendation = "N_c = 20 with 30 rocks";
  return r;
}

TEST(ResultsJson, ConvergenceResultRoundTrips) {
  ConvergenceResult r = Convergence();
  for (int recommended : {1, -1}) {
    r.recommended = recommended;
    const ConvergenceResult back = RoundTrip(r);
    EXPECT_EQ(back.site, "slope");
    EXPECT_EQ(back.seed, r.seed);
    EXPECT_EQ(back.reference, 1);
    EXPECT_EQ(back.recommended, recommended);
    EXPECT_EQ(back.notes, r.notes);
    ASSERT_EQ(back.rows.size(), 2u);
    const ConvergenceRow& row = back.rows[0];
    EXPECT_EQ(row.figures.dt_max, 2e-4);
    EXPECT_EQ(row.figures.dt_shrunk, 3);
    EXPECT_EQ(row.figures.flights, 77);
    EXPECT_EQ(row.left, 1);
    ASSERT_EQ(row.quantities.size(), 1u);
    EXPECT_TRUE(std::isnan(row.quantities[0].value)) << "absent: NaN";
    EXPECT_EQ(row.quantities[0].total_error, kInf) << "unknown: +inf";
    EXPECT_EQ(row.max_estimate, kInf);
    EXPECT_EQ(back.rows[1].quantities[0].discretisation_noise, 0.03);
    EXPECT_TRUE(back.rows[1].meets_target);
  }
}

// Two parameters (one an offset), two outputs, by the method given.
SensitivityResult Sensitivity(SensitivityMethod method) {
  SensitivityResult r;
  r.site = "slope";
  r.method = method;
  r.seed = 3;
  r.rocks = 4;
  r.threads = 2;
  Parameter roughness = ParameterOf("site:rock", ParameterKind::kRoughness, -0.05, 0.05);
  roughness.offset = true;
  r.parameters = {ParameterOf("talus", ParameterKind::kHardness, 0.1, 0.9), roughness};
  r.current = {0.5, 0.0};
  r.outputs = {{"runout.p50", "m", "the median", 41.5, 0.75},
               {"stopped", "fraction", "stopped rocks", kNaN, kNaN}};
  if (method == SensitivityMethod::kMorris) {
    r.samples = 3;
    r.morris = {2, 2, 3, 4, 2.0 / 3.0, 9, {}};
  } else {
    r.samples = 8;
    r.sobol = {2, 2, 8, 40, 0.95, 32, {12.5, kNaN}, {8, 0}, {}};
  }
  r.morris.index.assign(2, std::vector<MorrisIndex>(2));
  r.sobol.index.assign(method == SensitivityMethod::kSobol ? 2 : 0, std::vector<SobolIndex>(2));
  for (int p = 0; p < 2; ++p)
    for (int o = 0; o < 2; ++o) {
      SensitivityEntry e;
      e.parameter = p, e.output = o;
      if (method == SensitivityMethod::kMorris) {
        e.morris = {1.5 * p - 0.25, 1.5 * p + 0.25, o ? kNaN : 0.5, 3 - o};
        r.morris.index[static_cast<std::size_t>(o)][static_cast<std::size_t>(p)] = e.morris;
      } else {
        e.sobol = {0.5 * p, 0.25, 0.75, o ? kNaN : 0.625, 0.5, 0.875};
        r.sobol.index[static_cast<std::size_t>(o)][static_cast<std::size_t>(p)] = e.sobol;
      }
      e.effect_over_noise = o ? kNaN : 2.5 * p;
      r.entries.push_back(e);
    }
  if (method == SensitivityMethod::kSobol) r.morris = MorrisResult{};
  r.simulations = 10;
  r.wall_seconds = 1.25;
  r.simulation_seconds = 1.125;
  r.non_finite_runs = 1;
  r.notes = {"stopped: no value"};
  r.summary = "a summary";
  return r;
}

TEST(ResultsJson, SensitivityResultRoundTrips) {
  for (SensitivityMethod method : {SensitivityMethod::kMorris, SensitivityMethod::kSobol}) {
    const SensitivityResult r = Sensitivity(method);
    const SensitivityResult back = RoundTrip(r);
    EXPECT_EQ(back.method, method);
    EXPECT_EQ(back.samples, r.samples);
    ASSERT_EQ(back.parameters.size(), 2u);
    EXPECT_EQ(back.parameters[0].label(), "talus.hardness");
    EXPECT_EQ(back.parameters[1].label(), "site:rock.roughness_offset");
    EXPECT_EQ(back.parameters[1].kind, ParameterKind::kRoughness);
    EXPECT_TRUE(back.parameters[1].offset);
    EXPECT_EQ(back.parameters[1].lower, -0.05);
    EXPECT_EQ(back.current, r.current);
    ASSERT_EQ(back.outputs.size(), 2u);
    EXPECT_EQ(back.outputs[0].noise, 0.75);
    EXPECT_TRUE(std::isnan(back.outputs[1].value));
    ASSERT_EQ(back.entries.size(), 4u);
    for (std::size_t e = 0; e < 4; ++e) {
      EXPECT_EQ(back.entries[e].parameter, r.entries[e].parameter);
      EXPECT_EQ(back.entries[e].output, r.entries[e].output);
      EXPECT_TRUE(Same(back.entries[e].effect_over_noise, r.entries[e].effect_over_noise)) << e;
    }
    if (method == SensitivityMethod::kMorris) {
      EXPECT_EQ(back.morris.delta, 2.0 / 3.0);
      EXPECT_EQ(back.morris.evaluations, 9);
      EXPECT_EQ(back.morris.index[0][1].mu_star, 1.75);
      EXPECT_EQ(back.morris.index[1][1].effects, 2);
      EXPECT_EQ(back.EffectNoise(0), r.EffectNoise(0));
    } else {
      EXPECT_EQ(back.sobol.variance[0], 12.5);
      EXPECT_EQ(back.sobol.rows, (std::vector<int>{8, 0}));
      EXPECT_EQ(back.sobol.index[0][1].first, 0.5);
      EXPECT_TRUE(std::isnan(back.sobol.index[1][0].total));
    }
  }
}

TEST(ResultsJson, ReachResultRoundTrips) {
  ReachResult r;
  r.site = "slope";
  r.design = DesignKind::kLatinHypercube;
  r.candidates = 10;
  r.design_seed = 5;
  r.simulation_seed = 6;
  r.rocks = 12;
  r.parameters = {ParameterOf("talus", ParameterKind::kContactTime, 0.005, 0.05)};
  ReachStatistic s;
  s.id = ResidualId::Of(ObservationKind::kRunoutDistance).With(Statistic::kQuantile, 0.5);
  s.observed = 40.0, s.sigma = 4.5, s.min = 20.0, s.max = 38.0;
  s.min_point = 0, s.max_point = 1, s.closest_point = 1;
  s.closest_simulated = 38.0, s.closest_sigmas = -0.4;
  s.points_with_value = 2;
  s.verdict = ReachVerdict::kInReach;
  ReachStatistic none = s;
  none.id =
      ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] BP-1").With(Statistic::kFraction);
  none.sigma = none.min = none.max = kNaN;
  none.closest_simulated = none.closest_sigmas = kNaN;
  none.min_point = none.max_point = none.closest_point = -1;
  none.points_with_value = 0;
  none.verdict = ReachVerdict::kNoValue;
  r.statistics = {s, none};
  r.points = {{{0.25}, {0.01625}, 3.5, false, "", {20.0, kNaN}, {4.5, kNaN}},
              {{0.75}, {0.03875}, kNaN, true, "too few rocks", {38.0, kNaN}, {4.5, kNaN}}};
  r.best_point = 0;
  r.wall_seconds = 2.5;
  for (DesignKind kind : {DesignKind::kLatinHypercube, DesignKind::kHalton}) {
    r.design = kind;
    r.candidates = kind == DesignKind::kHalton ? 0 : 10;
    const ReachResult back = RoundTrip(r);
    EXPECT_EQ(back.design, kind);
    EXPECT_EQ(back.candidates, r.candidates);
    ASSERT_EQ(back.parameters.size(), 1u);
    EXPECT_EQ(back.parameters[0].kind, ParameterKind::kContactTime);
    EXPECT_EQ(back.parameters[0].material, "talus");
    ASSERT_EQ(back.statistics.size(), 2u);
    EXPECT_EQ(back.statistics[0].closest_sigmas, -0.4);
    EXPECT_EQ(back.statistics[0].id, s.id);
    EXPECT_EQ(back.statistics[1].id, none.id);
    EXPECT_EQ(back.statistics[1].verdict, ReachVerdict::kNoValue);
    EXPECT_TRUE(std::isnan(back.statistics[1].sigma));
    ASSERT_EQ(back.points.size(), 2u);
    EXPECT_TRUE(std::isnan(back.points[1].misfit));
    EXPECT_TRUE(back.points[1].penalised);
    EXPECT_EQ(back.points[1].physical, std::vector<double>{0.03875});
    EXPECT_TRUE(std::isnan(back.points[0].simulated[1]));
  }
}

TEST(ResultsJson, ScoreResultRoundTrips) {
  ScoreResult s;
  s.site = "slope";
  s.observations_file = "obs.json";
  s.rocks = 40;
  s.seed = 1;
  s.stopped = 38, s.left = 1, s.timeout = 1;
  s.misfit.value = 8.25;
  s.misfit.penalised = true;
  s.misfit.message = "too few rocks";
  // A residual of each kind one site's misfit has, and a penalty's (no identity).
  const ResidualId distance = ResidualId::Of(ObservationKind::kRunoutDistance);
  const std::vector<ResidualId> ids = {
      distance.With(Statistic::kQuantile, 0.5),
      distance.With(Statistic::kMax),
      ResidualId::Of(ObservationKind::kTreeScars, 1, "tree_scars[1] trees")
          .With(Statistic::kQuantile, 0.025),
      ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] BP-2").With(Statistic::kFraction),
      ResidualId::Of(ObservationKind::kRunoutLateral).With(Statistic::kQuantile, 0.9),
      ResidualId::Of(ObservationKind::kRunoutStopped).With(Statistic::kShare),
      ResidualId::Of(ObservationKind::kRunoutMassClass, -1, "10-40")
          .With(Statistic::kQuantile, 0.1),
      ResidualId::Of(ObservationKind::kRun, -1, "v083").With(Statistic::kRunout),
      ResidualId{}};
  for (const ResidualId& id : ids) {
    observations::Residual r;
    r.id = id;
    r.simulated = 45.1, r.observed = 40.0, r.sigma = 4.1, r.value = 1.25;
    s.misfit.residuals.push_back(r);
  }
  // Two measured impacts of group "b2" (the scene's second), the second
  // near-normal (no tangential residual: its tangential figures are null).
  s.groups = {"b1", "b2"};
  for (int k = 0; k < 2; ++k) {
    observations::ImpactFit f;
    f.id = k == 0 ? "i0" : "i1";
    f.group = 1;
    f.incidence_deg = k == 0 ? 35.5 : 1.5;
    f.normal = Eigen::Vector3d(0.1, 0, 0.99498743710662);
    f.observed = Eigen::Vector3d(3.25, 0.5, 2.0);
    f.simulated = Eigen::Vector3d(3.0, 0.25, 2.5);
    f.speed_sd = 0.375;
    f.draws = 16, f.left = 15 - k;
    f.normal_observed = 0.25, f.normal_simulated = 0.3125, f.normal_spread = 0.0625;
    f.normal_sigma = 0.09;
    f.tangential_observed = k == 0 ? 0.625 : std::numeric_limits<double>::quiet_NaN();
    f.tangential_simulated = 0.5, f.tangential_spread = 0.125;
    f.tangential_sigma = k == 0 ? 0.15 : 0.0;
    s.misfit.impacts.push_back(f);
  }
  for (const char* parameters : {"", "calibration/parameters.json"}) {
    s.parameters_file = parameters;
    const nlohmann::json j = s;
    EXPECT_EQ(j["parameters"].is_null(), s.parameters_file.empty());
    const ScoreResult back = RoundTrip(s);
    EXPECT_EQ(back.parameters_file, parameters);
    EXPECT_EQ(back.observations_file, "obs.json");
    EXPECT_EQ(back.timeout, 1);
    EXPECT_EQ(back.misfit.value, 8.25);
    EXPECT_TRUE(back.misfit.penalised);
    ASSERT_EQ(back.misfit.residuals.size(), ids.size());
    // The identities come back from their texts (a mass class's or a run's
    // index, which the text does not carry, is -1 here as in `ids`).
    for (std::size_t k = 0; k < ids.size(); ++k)
      EXPECT_EQ(back.misfit.residuals[k].id, ids[k]) << ids[k].observation() << ids[k].quantity();
    EXPECT_EQ(back.misfit.residuals[0].value, 1.25);
    // The impacts: their block is calibration.json's (ImpactsJson), read back
    // field for field; the group by its id.
    ASSERT_EQ(j["impacts"]["per_impact"].size(), 2u);
    EXPECT_EQ(j["impacts"]["per_impact"][0]["group"], "b2");
    EXPECT_TRUE(j["impacts"]["per_impact"][1]["tangential_ratio"]["simulated"].is_null());
    EXPECT_EQ(nlohmann::json(back), j);
    ASSERT_EQ(back.misfit.impacts.size(), 2u);
    EXPECT_EQ(back.groups, std::vector<std::string>{"b2"});
    const observations::ImpactFit& f = back.misfit.impacts[0];
    EXPECT_EQ(f.id, "i0");
    EXPECT_EQ(f.group, 0);
    EXPECT_EQ(f.incidence_deg, 35.5);
    EXPECT_EQ(f.observed, Eigen::Vector3d(3.25, 0.5, 2.0));
    EXPECT_EQ(f.simulated, Eigen::Vector3d(3.0, 0.25, 2.5));
    EXPECT_EQ(f.left, 15);
    EXPECT_EQ(f.tangential_sigma, 0.15);
    EXPECT_TRUE(std::isnan(back.misfit.impacts[1].tangential_observed));
  }
}

TEST(ResultsJson, AnUnknownNameIsRefused) {
  nlohmann::json j = Sensitivity(SensitivityMethod::kMorris);
  j["method"] = "fast";
  EXPECT_THROW(j.get<SensitivityResult>(), std::invalid_argument);
  nlohmann::json reach = ReachResult{};
  reach["design"]["kind"] = "grid";
  EXPECT_THROW(reach.get<ReachResult>(), std::invalid_argument);
  nlohmann::json score = ScoreResult{};
  score["residuals"] = {{{"observation", "runout distance"},
                         {"quantity", "median"},
                         {"simulated", 1.0},
                         {"observed", 1.0},
                         {"sigma", 1.0},
                         {"residual", 0.0}}};
  EXPECT_THROW(score.get<ScoreResult>(), std::invalid_argument);
}

}  // namespace
}  // namespace rockcal::calibrate
