// tree_impacts.csv, trees.csv and summary.json's "forest"
// (docs/reference/outputs.md).
#include "rockcal/reports/forest_outputs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace rockcal::reports {
namespace {

// Two rocks: the first strikes stem 1 twice (breaking it the second time)
// and stops, the second strikes stem 0 once and leaves.
core::SimulationResult TwoRocks() {
  core::SimulationResult r;
  r.strikes_recorded = true;
  r.rocks.resize(2);
  r.rocks[0].rock = 0;
  r.rocks[0].outcome = core::Outcome::kStopped;
  core::TreeStrike a;
  a.tree = 1;
  a.point = Eigen::Vector3d(3.048, 6.096, 1.0);
  a.height = 0.3048;
  a.speed = 3.048;
  a.energy = 1000.0;
  a.absorbed = 400.0;
  core::TreeStrike b = a;
  b.absorbed = 500.0;
  b.broken = true;
  r.rocks[0].strikes = {a, b};
  r.rocks[1].rock = 1;
  r.rocks[1].outcome = core::Outcome::kLeft;
  core::TreeStrike c = a;
  c.tree = 0;
  c.absorbed = 100.0;
  r.rocks[1].strikes = {c};
  return r;
}

TEST(ForestOutputs, TreeImpactsCsvInSiteUnits) {
  const std::string csv = TreeImpactsCsv(TwoRocks(), 1.0 / 0.3048);  // feet
  EXPECT_EQ(csv,
            "rock,tree,x,y,height,speed,energy,absorbed,broken\n"
            "0,1,10,20,1,10,1000,400,0\n"
            "0,1,10,20,1,10,1000,500,1\n"
            "1,0,10,20,1,10,1000,100,0\n");
}

TEST(ForestOutputs, ANonFiniteValueIsAnInternalFailure) {
  core::SimulationResult r = TwoRocks();
  r.rocks[1].strikes[0].absorbed = std::numeric_limits<double>::quiet_NaN();
  try {
    TreeImpactsCsv(r, 1.0);
    ADD_FAILURE() << "expected a failure";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("rock 1 column absorbed"), std::string::npos) << e.what();
  }
}

TEST(ForestOutputs, SummaryCountsStrikesBreaksAndStops) {
  core::Scene scene;
  scene.forest.Add(0, 0, 0.3, 20, core::SpeciesClass::kConifer);
  scene.forest.Add(5, 0, 0.2, 20, core::SpeciesClass::kBroadleaf);
  const nlohmann::json j = ForestSummaryJson(scene, TwoRocks());
  EXPECT_EQ(j["stems"], 2);
  EXPECT_EQ(j["strikes"], 3);
  EXPECT_EQ(j["rocks_struck"], 2);
  EXPECT_EQ(j["rocks_stopped_after_strike"], 1);
  EXPECT_DOUBLE_EQ(j["energy_absorbed_j"].get<double>(), 1000.0);
  EXPECT_EQ(j["breaks"], 1);
  EXPECT_EQ(j["stems_broken"], 1);
  core::SimulationResult unrecorded = TwoRocks();
  unrecorded.strikes_recorded = false;
  EXPECT_EQ(ForestSummaryJson(scene, unrecorded), nlohmann::json({{"stems", 2}}));
}

TEST(ForestOutputs, TreesCsvListsTheDrawnStemsAsATreeFile) {
  core::Forest f;
  f.Add(1, 2, 0.3, 20, core::SpeciesClass::kConifer);
  f.Add(3.048, 6.096, 0.25, 15.24, core::SpeciesClass::kBroadleaf);
  EXPECT_EQ(TreesCsv(f, 1, 1.0 / 0.3048), "x,y,dbh_cm,species,height\n10,20,25,broadleaf,50\n");
}

}  // namespace
}  // namespace rockcal::reports
