// Measured impacts as observations (kinds/impacts.cc): the reader's forms and
// its errors (each naming file:line and the column), the misfit of a twin
// (impacts written from replays at hidden values: near zero there, larger
// away), the verdict and the folds.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "file_fixture.h"
#include "rockcal/core/error.h"
#include "rockcal/core/impact_replay.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"

namespace rockcal::observations {
namespace {

using ::testing::HasSubstr;

// A plane z = -0.3 x, 21 x 21 nodes 1 m apart, one material of hardness H;
// one rock group "b1" of spheres 0.6 m across.
core::Scene PlaneScene(double hardness = 0.5, double roughness = 0.0) {
  core::Scene scene;
  scene.grid.spacing = 1.0;
  scene.grid.nx = scene.grid.ny = 21;
  for (int j = 0; j < 21; ++j)
    for (int i = 0; i < 21; ++i) {
      scene.grid.z.push_back(-0.3 * i);
      scene.grid.material.push_back(0);
    }
  core::Material m;
  m.id = "m";
  m.hardness = hardness;
  m.roughness_m = roughness;
  m.contact_time_s = 0.002;
  scene.materials = {m};
  core::RockGroup g;
  g.id = "b1";
  g.shape = core::Shape::kSphere;
  g.size_min = g.size_max = 0.6;
  g.release.point = Eigen::Vector2d(2, 10);
  scene.groups = {g};
  scene.options.threads = 1;
  return scene;
}

class ImpactsFileTest : public testing::FileTest {
 protected:
  Observations Load(const std::string& json) const {
    return LoadObservations(Write("obs.json", json), scene_);
  }
  // The error of loading impacts.csv holding `csv`; "" if none.
  std::string CsvError(const std::string& csv) const {
    Write("impacts.csv", csv);
    try {
      Load(R"({"units": "si", "impacts_file": "impacts.csv"})");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  core::Scene scene_ = PlaneScene();
};

constexpr char kHeader[] = "group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out\n";

TEST_F(ImpactsFileTest, ReadsTheCsvAndJsonForms) {
  Write("impacts.csv",
        "# a tracked block\nid,vx_out,vy_out,vz_out,group,x,y,z,vx_in,vy_in,vz_in,wx,wy,wz\n"
        "c1,5,0,2,b1,10,10,-2.7,6,0,-4,0,-3,0\n"
        "c2,4,1,1.5,b1,12,8,-3.3,5,1,-5,0,0,0\n");
  const Observations csv = Load(
      R"({"units": "si", "impacts_file": "impacts.csv", "impact_draws": 8,
          "error": {"rebound": 0.08}})");
  ASSERT_EQ(csv.impacts.size(), 2u);
  EXPECT_EQ(csv.impacts[0].id, "c1");
  EXPECT_EQ(csv.impacts[0].group, 0);
  EXPECT_EQ(csv.impacts[0].centre, Eigen::Vector3d(10, 10, -2.7));
  EXPECT_EQ(csv.impacts[0].velocity_in, Eigen::Vector3d(6, 0, -4));
  EXPECT_EQ(csv.impacts[0].velocity_out, Eigen::Vector3d(5, 0, 2));
  ASSERT_TRUE(csv.impacts[0].spin.has_value());
  EXPECT_EQ(*csv.impacts[0].spin, Eigen::Vector3d(0, -3, 0));
  // The ground's normal as the replays take it (core::GroundNormal).
  Eigen::Vector3d n;
  ASSERT_TRUE(core::GroundNormal(core::BuildTerrain(scene_), 10, 10, &n));
  EXPECT_NEAR((csv.impacts[0].normal - n).norm(), 0.0, 1e-12) << csv.impacts[0].normal.transpose();
  EXPECT_NEAR((n - Eigen::Vector3d(0.3, 0, 1).normalized()).norm(), 0.0, 1e-12);
  EXPECT_EQ(csv.impact_draws, 8);
  EXPECT_DOUBLE_EQ(csv.error.rebound, 0.08);
  EXPECT_FALSE(csv.empty());
  // The replays asked of a simulation, one per impact.
  const core::RecordOptions record = RequiredRecording(csv, {});
  ASSERT_EQ(record.impacts.size(), 2u);
  EXPECT_EQ(record.impacts[1].draws, 8);
  EXPECT_EQ(record.impacts[1].centre, Eigen::Vector3d(12, 8, -3.3));

  // JSON in US units: lengths and velocities in ft; spin in rad/s; ids by number.
  const Observations json = Load(R"({"units": "us", "impacts": [
      {"group": "b1", "centre": [32.8084, 32.8084, -8.8583],
       "velocity_in": [20, 0, -10], "velocity_out": [10, 0, 5]}]})");
  ASSERT_EQ(json.impacts.size(), 1u);
  EXPECT_EQ(json.impacts[0].id, "1");
  EXPECT_NEAR(json.impacts[0].centre.x(), 10.0, 1e-4);
  EXPECT_NEAR(json.impacts[0].velocity_in.x(), 20 * 0.3048, 1e-12);
  EXPECT_FALSE(json.impacts[0].spin.has_value());
  EXPECT_EQ(json.impact_draws, kDefaultImpactDraws);
  EXPECT_DOUBLE_EQ(json.error.rebound, 0.05);
}

TEST_F(ImpactsFileTest, EveryBadRowNamesFileLineAndColumn) {
  const std::string file = (dir_ / "impacts.csv").string();
  const std::string good = "b1,10,10,-2.7,6,0,-4,5,0,2\n";
  EXPECT_THAT(CsvError(std::string(kHeader) + good + "b9,10,10,-2.7,6,0,-4,5,0,2\n"),
              HasSubstr(file + ":3: column 'group': no rock group of the site has the id 'b9' "
                               "(expected the 'id' of the group of the tracked rock; ids: b1)"));
  EXPECT_THAT(CsvError(std::string(kHeader) + "b1,10,10,-2.7,nan,0,-4,5,0,2\n"),
              HasSubstr(file + ":2: expected a number for 'vx_in' (found 'nan')"));
  EXPECT_THAT(CsvError(std::string(kHeader) + "b1,10,10,-2.7,6,0,-4,5,zero,2\n"),
              HasSubstr(file + ":2: expected a number for 'vy_out' (found 'zero')"));
  EXPECT_THAT(
      CsvError(std::string(kHeader) + good + good + "b1,25,10,-2.7,6,0,-4,5,0,2\n"),
      HasSubstr(file + ":4: columns 'x', 'y': the impact at (25, 10) m is off the terrain"));
  // A centre below the surface is a rock sunk between rough ground's
  // spheres, down to one sphere spacing (1 m here); deeper is inside the terrain.
  EXPECT_THAT(CsvError(std::string(kHeader) + "b1,10,10,-4.1,6,0,-4,5,0,2\n"),
              HasSubstr(file + ":2: column 'z': the rock's centre -4.1 m is 1.1 m below the "
                               "ground (-3 m there): inside the terrain; expected the centre at "
                               "the impact, at most one sphere spacing (1 m) below the ground"));
  Write("impacts.csv", std::string(kHeader) + "b1,10,10,-3.9,6,0,-4,5,0,2\n");
  EXPECT_EQ(Load(R"({"units": "si", "impacts_file": "impacts.csv"})").impacts.size(), 1u)
      << "a centre 0.9 m below the surface is read";
  EXPECT_THAT(CsvError(std::string(kHeader) + "b1,10,10,-2.7,6,0,4,5,0,2\n"),
              HasSubstr(file + ":2: columns 'vx_in', 'vy_in', 'vz_in': (6, 0, 4) m/s does not "
                               "approach the ground"));
  EXPECT_THAT(CsvError(std::string(kHeader) + "b1,10,10,-2.7,6,0,-4,5,0,-3\n"),
              HasSubstr(file + ":2: columns 'vx_out', 'vy_out', 'vz_out'"));
  EXPECT_THAT(CsvError(std::string(kHeader) + "b1,10,10,-2.7,6,0,-4,5,0\n"),
              HasSubstr(file + ":2: expected 10 values per row (as the header), found 9"));
  // Headers: a column missing, an unknown one, one twice, a spin in part, none at all.
  EXPECT_THAT(CsvError("group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out\n" + good),
              HasSubstr(file + ":1: no column 'vz_out': expected a header naming the columns"));
  EXPECT_THAT(CsvError("group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out,mass\n" + good),
              HasSubstr(file + ":1: column 11 'mass' is unknown"));
  EXPECT_THAT(CsvError("group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out,x\n" + good),
              HasSubstr(file + ":1: column 11 'x' is given twice"));
  EXPECT_THAT(CsvError("group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out,wx\n" + good),
              HasSubstr(file + ":1: expected all of wx,wy,wz or none"));
  EXPECT_THAT(CsvError(good), HasSubstr(file + ":1: no column 'group'"));
  EXPECT_THAT(CsvError(std::string(kHeader)), HasSubstr(file + ": no data rows"));
  EXPECT_THAT(CsvError("id," + std::string(kHeader) + "a," + good + "a," + good),
              HasSubstr(file + ":3: column 'id': impact 'a' is given twice"));
  // The JSON form names its path.
  try {
    Load(R"({"units": "si", "impacts": [{"group": "b1", "centre": [10, 10],
             "velocity_in": [6, 0, -4], "velocity_out": [5, 0, 2]}]})");
    ADD_FAILURE() << "a centre of 2 coordinates was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("$.impacts[0].centre"));
  }
  try {
    Load(R"({"units": "si", "impact_draws": 0, "impacts": [{"group": "b1",
             "centre": [10, 10, -2.7], "velocity_in": [6, 0, -4], "velocity_out": [5, 0, 2]}]})");
    ADD_FAILURE() << "0 draws were read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("$.impact_draws"));
  }
}

// Impacts whose rebounds are the median ratios of replays at hardness 0.5
// (on a rough plane): near-zero misfit there, larger away, and a verdict
// that says so.
struct Twin {
  Observations obs;
  std::vector<Eigen::Vector3d> in;
};

Twin MakeTwin() {
  const core::Scene hidden = PlaneScene(0.5, 0.1);
  Twin twin;
  std::vector<core::ImpactReplay> replays;
  for (int k = 0; k < 6; ++k) {
    core::ImpactReplay r;
    r.centre = Eigen::Vector3d(6 + 2 * k, 6 + k, -0.3 * (6 + 2 * k) + 0.35);
    r.velocity_in = Eigen::Vector3d(4 + k, 0.5 * k - 1, -3 - 0.5 * k);
    r.draws = 16;
    replays.push_back(r);
  }
  const core::Terrain terrain = core::BuildTerrain(hidden);
  const std::vector<core::ImpactRebound> rebounds = core::ReplayImpacts(hidden, terrain, replays);
  for (std::size_t k = 0; k < replays.size(); ++k) {
    const Eigen::Vector3d& v = replays[k].velocity_in;
    const Eigen::Vector3d& n = rebounds[k].normal;
    std::vector<double> rn, rt;
    for (const Eigen::Vector3d& out : rebounds[k].velocity) {
      const core::ReboundRatios r = core::RatiosOf(v, out, n);
      rn.push_back(r.normal);
      rt.push_back(r.tangential);
    }
    std::sort(rn.begin(), rn.end());
    std::sort(rt.begin(), rt.end());
    const double mn = core::Quantile(rn, 0.5), mt = core::Quantile(rt, 0.5);
    const Eigen::Vector3d vt = v - v.dot(n) * n;
    Impact impact;
    impact.id = "i" + std::to_string(k);
    impact.centre = replays[k].centre;
    impact.velocity_in = v;
    impact.velocity_out = -mn * v.dot(n) * n + mt * vt;
    impact.normal = n;
    twin.obs.impacts.push_back(impact);
  }
  twin.obs.error.rebound = 0.05;
  return twin;
}

Misfit MisfitAt(const Observations& obs, double hardness) {
  core::Scene scene = PlaneScene(hardness, 0.1);
  scene.options.record = RequiredRecording(obs, {});
  core::SimulationResult result;
  result.impacts =
      core::ReplayImpacts(scene, core::BuildTerrain(scene), scene.options.record.impacts);
  return ComputeMisfit(obs, scene, result);
}

TEST(ImpactsMisfit, ATwinFitsAtItsHiddenValuesAndNotAway) {
  const Twin twin = MakeTwin();
  const Misfit at = MisfitAt(twin.obs, 0.5);
  ASSERT_EQ(at.impacts.size(), 6u);
  // 6 impacts x 2 ratios, then the pooled ratios at 9 levels and the max each.
  EXPECT_EQ(at.residuals.size(), 12u + 20u);
  for (const Residual& r : at.residuals) {
    if (r.id.kind != ObservationKind::kImpact) continue;
    EXPECT_NEAR(r.value, 0.0, 1e-9) << r.id.observation() << " " << r.id.quantity();
  }
  // (The pooled ratios are not at zero: the observed ones are the draws'
  // medians, narrower than the draws.)
  EXPECT_THAT(ImpactVerdict(at), HasSubstr("rebounds reproduced (good"));
  const ImpactFit& fit = at.impacts[0];
  EXPECT_EQ(fit.draws, 16);
  EXPECT_GT(fit.speed_sd, 0.0) << "rough ground spreads the rebounds";
  EXPECT_GT(fit.incidence_deg, 0.0);
  EXPECT_LT(fit.incidence_deg, 90.0);
  double previous = at.value;
  for (double h : {0.35, 0.2}) {
    const Misfit away = MisfitAt(twin.obs, h);
    EXPECT_GT(away.value, previous) << "hardness " << h << "\n" << away.Report();
    previous = away.value;
  }
  const Misfit far = MisfitAt(twin.obs, 0.9);
  EXPECT_GT(far.value, 50.0) << far.Report();
  EXPECT_THAT(ImpactVerdict(far), HasSubstr("rebounds NOT reproduced (poor"));
  EXPECT_EQ(ImpactVerdict(Misfit{}), "");
}

TEST(ImpactsMisfit, AResultWithoutTheReplaysIsAProgrammerError) {
  const Twin twin = MakeTwin();
  EXPECT_THROW(ComputeMisfit(twin.obs, PlaneScene(), core::SimulationResult{}),
               std::invalid_argument);
}

TEST(ImpactsFolds, EachImpactIsHeldOutOnce) {
  Observations obs = MakeTwin().obs;
  const std::vector<Fold> folds = MakeFolds(obs, 3, 11);
  std::vector<std::string> held;
  for (const Fold& fold : folds) {
    const Observations test = Subset(obs, fold, true), train = Subset(obs, fold, false);
    EXPECT_EQ(test.impacts.size(), 2u);
    EXPECT_EQ(train.impacts.size(), 4u);
    for (const Impact& i : test.impacts) held.push_back(i.id);
  }
  std::sort(held.begin(), held.end());
  EXPECT_EQ(held, (std::vector<std::string>{"i0", "i1", "i2", "i3", "i4", "i5"}));
  EXPECT_THROW(MakeFolds(obs, 7, 11), InputError);
}

}  // namespace
}  // namespace rockcal::observations
