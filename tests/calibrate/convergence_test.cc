// The convergence study on a small scene built in code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "rockcal/calibrate/study.h"
#include "rockcal/core/material.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/simulate.h"
#include "small_slope.h"

namespace rockcal::calibrate {
namespace {

using fixtures::SmallSlope;

// ---- Convergence -------------------------------------------------------------------

ConvergenceOptions QuickConvergence() {
  ConvergenceOptions opt;
  opt.steps_per_contact = {20, 10};  // any order
  opt.rock_counts = {30, 12};
  opt.bootstrap = 50;
  opt.min_values = 5;
  opt.seed = 7;
  return opt;
}

core::Scene ConvergenceScene() {
  core::Scene scene = SmallSlope();
  scene.options.max_time = 4.0;
  return scene;
}

TEST(Convergence, TinySceneGivesATableAndARecommendation) {
  ConvergenceOptions opt = QuickConvergence();
  opt.target = 10.0;  // generous: some setting must meet it
  int calls = 0, last_done = 0, last_total = 0;
  opt.progress = [&](int done, int total, const std::string&) {
    ++calls;
    EXPECT_GE(done, last_done);
    last_done = done;
    last_total = total;
  };
  const ConvergenceResult r = RunConvergence(ConvergenceScene(), opt);
  EXPECT_EQ(calls, 2 * (12 + 30));
  EXPECT_EQ(last_done, last_total);
  ASSERT_EQ(r.rows.size(), 4u);
  // N_c ascending, then rocks ascending; the reference is the last.
  EXPECT_EQ(r.rows[0].steps_per_contact, 10);
  EXPECT_EQ(r.rows[0].rocks, 12);
  EXPECT_EQ(r.rows[1].rocks, 30);
  EXPECT_EQ(r.rows[3].steps_per_contact, 20);
  EXPECT_EQ(r.reference, 3);
  EXPECT_EQ(r.seed, 7u);
  ASSERT_FALSE(r.quantities.empty());
  EXPECT_EQ(r.quantities[0], "P-slope.height.p50");
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const ConvergenceRow& row = r.rows[k];
    ASSERT_EQ(row.quantities.size(), r.quantities.size());
    EXPECT_GT(row.wall_seconds, 0.0);
    // t_c / N_c, or less where the stability bound of the soft soil (e = 0.2)
    // is tighter (N_c = 10 and 20).
    EXPECT_LE(row.figures.dt_max, 5e-3 / row.steps_per_contact * (1 + 1e-15));
    if (row.figures.dt_shrunk == 0) {
      EXPECT_NEAR(row.figures.dt_max, 5e-3 / row.steps_per_contact, 1e-15);
    }
    for (const QuantityError& q : row.quantities) {
      if (row.steps_per_contact == 20) {
        EXPECT_EQ(q.discretisation_error, 0.0) << q.name;
      }
      if (static_cast<int>(k) == r.reference) {
        EXPECT_EQ(q.total_error, 0.0) << q.name;
      }
      if (q.count >= opt.min_values) {
        EXPECT_TRUE(std::isfinite(q.mc_error)) << q.name;
      }
      EXPECT_GE(q.mc_error, 0.0) << q.name;
      // The discretisation part comes from the same N_c at the most rocks.
      const ConvergenceRow& most = r.rows[k | 1];
      ASSERT_EQ(most.steps_per_contact, row.steps_per_contact);
      ASSERT_EQ(most.rocks, 30);
      const QuantityError& m =
          most.quantities[static_cast<std::size_t>(&q - row.quantities.data())];
      EXPECT_EQ(q.estimate, m.discretisation_error + q.mc_error) << q.name;
    }
  }
  ASSERT_GE(r.recommended, 0) << r.recommendation;
  const ConvergenceRow& best = r.rows[static_cast<std::size_t>(r.recommended)];
  EXPECT_TRUE(best.meets_target);
  for (const auto& row : r.rows)
    if (row.meets_target) {
      EXPECT_LE(best.wall_seconds, row.wall_seconds);
    }
  EXPECT_EQ(r.recommendation.rfind("N_c = ", 0), 0u) << r.recommendation;

  const nlohmann::json j = r;
  EXPECT_EQ(j["site"], ConvergenceScene().name);
  EXPECT_EQ(j["rows"].size(), 4u);
  EXPECT_EQ(j["reference"]["steps_per_contact"], 20);
  EXPECT_EQ(j["recommended"]["rocks"], best.rocks);
  EXPECT_NE(ConvergenceReport(r).find("recommendation: N_c = "), std::string::npos);
}

TEST(Convergence, SaysNoneWhenNoSettingMeetsTheTarget) {
  ConvergenceOptions opt = QuickConvergence();
  opt.steps_per_contact = {10, 20};
  opt.rock_counts = {12};
  opt.target = 1e-9;
  const ConvergenceResult r = RunConvergence(ConvergenceScene(), opt);
  EXPECT_EQ(r.recommended, -1);
  EXPECT_EQ(r.recommendation.rfind("none", 0), 0u) << r.recommendation;
  EXPECT_TRUE(nlohmann::json(r)["recommended"].is_null());
}

TEST(Convergence, SameSeedSameTable) {
  ConvergenceOptions opt = QuickConvergence();
  opt.steps_per_contact = {10};
  opt.rock_counts = {12};
  const ConvergenceResult a = RunConvergence(ConvergenceScene(), opt);
  opt.threads = 1;
  const ConvergenceResult b = RunConvergence(ConvergenceScene(), opt);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t q = 0; q < a.rows[0].quantities.size(); ++q) {
    EXPECT_EQ(a.rows[0].quantities[q].value, b.rows[0].quantities[q].value);
    EXPECT_EQ(a.rows[0].quantities[q].mc_error, b.rows[0].quantities[q].mc_error);
  }
}

TEST(Convergence, OptionsAreValidated) {
  std::string error;
  ConvergenceOptions opt;
  EXPECT_TRUE(opt.IsValid(&error)) << error;
  opt.steps_per_contact = {10, 2};
  EXPECT_FALSE(opt.IsValid(&error));
  EXPECT_NE(error.find("convergence.steps_per_contact = 2"), std::string::npos) << error;
  opt = ConvergenceOptions{};
  opt.target = 0.0;
  EXPECT_FALSE(opt.IsValid(&error));
  EXPECT_NE(error.find("convergence.target"), std::string::npos) << error;
  opt = ConvergenceOptions{};
  opt.rock_counts = {};
  EXPECT_FALSE(opt.IsValid(&error));
  EXPECT_THROW(RunConvergence(ConvergenceScene(), opt), std::invalid_argument);
}

}  // namespace
}  // namespace rockcal::calibrate
