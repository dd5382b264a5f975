// The reach check: the space-filling designs alone, then RunReach on the
// twin slope against observations it can and cannot produce.
#include "rockcal/calibrate/reach.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using ::testing::HasSubstr;
using testing::TwinObservations;
using testing::TwinSite;

// ---- Designs ---------------------------------------------------------------------

TEST(SpaceFillingDesign, LatinHypercubeIsStratifiedInEveryCoordinate) {
  const int n = 13, dims = 4;
  const auto x = SpaceFillingDesign(DesignKind::kLatinHypercube, n, dims, 7, 10);
  ASSERT_EQ(x.size(), static_cast<std::size_t>(n));
  for (int d = 0; d < dims; ++d) {
    std::set<int> strata;
    for (const auto& p : x) {
      ASSERT_EQ(p.size(), static_cast<std::size_t>(dims));
      const double u = p[static_cast<std::size_t>(d)];
      ASSERT_TRUE(u >= 0.0 && u < 1.0) << u;
      strata.insert(static_cast<int>(std::floor(u * n)));
    }
    EXPECT_EQ(strata.size(), static_cast<std::size_t>(n)) << "coordinate " << d;
  }
}

TEST(SpaceFillingDesign, IsDeterministicForASeed) {
  for (DesignKind kind : {DesignKind::kLatinHypercube, DesignKind::kHalton}) {
    const auto a = SpaceFillingDesign(kind, 9, 3, 42, 5);
    EXPECT_EQ(a, SpaceFillingDesign(kind, 9, 3, 42, 5)) << DesignKindToString(kind);
    EXPECT_NE(a, SpaceFillingDesign(kind, 9, 3, 43, 5)) << DesignKindToString(kind);
    for (const auto& p : a)
      for (double u : p) EXPECT_TRUE(u >= 0.0 && u < 1.0) << u;
  }
}

TEST(SpaceFillingDesign, MaximinSpreadsThePointsAtLeastAsWellAsOneCandidate) {
  const auto one = SpaceFillingDesign(DesignKind::kLatinHypercube, 12, 3, 3, 1);
  const auto best = SpaceFillingDesign(DesignKind::kLatinHypercube, 12, 3, 3, 20);
  EXPECT_GE(MinimumDistance(best), MinimumDistance(one));
  EXPECT_GT(MinimumDistance(best), 0.1) << "12 points in the unit cube";
}

TEST(SpaceFillingDesign, HaltonFirstCoordinateIsAShiftedVanDerCorput) {
  const auto x = SpaceFillingDesign(DesignKind::kHalton, 4, 2, 1);
  // Base 2: 1/2, 1/4, 3/4, 1/8 shifted by one common amount modulo 1.
  const double shift = x[0][0] - 0.5;
  const double expected[] = {0.5, 0.25, 0.75, 0.125};
  for (int i = 0; i < 4; ++i) {
    double u = expected[i] + shift;
    u -= std::floor(u);
    EXPECT_NEAR(x[static_cast<std::size_t>(i)][0], u, 1e-12) << i;
  }
}

TEST(SpaceFillingDesign, RejectsEmptyDesigns) {
  EXPECT_THROW(SpaceFillingDesign(DesignKind::kLatinHypercube, 0, 2, 1), std::invalid_argument);
  EXPECT_THROW(SpaceFillingDesign(DesignKind::kLatinHypercube, 3, 0, 1), std::invalid_argument);
  EXPECT_THROW(SpaceFillingDesign(DesignKind::kLatinHypercube, 3, 2, 1, 0), std::invalid_argument);
  EXPECT_THROW(SpaceFillingDesign(DesignKind::kHalton, 3, 65, 1), std::invalid_argument);
}

TEST(ReachOptions, ValidatesAndNamesTheField) {
  ReachOptions opt;
  std::string error;
  EXPECT_TRUE(opt.IsValid(&error)) << error;
  EXPECT_EQ(opt.EffectivePoints(4), 40);
  EXPECT_EQ(opt.EffectivePoints(30), ReachOptions::kMaxDefaultPoints);
  opt.points = 1;
  EXPECT_FALSE(opt.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("points = 1"));
  opt.points = 5;
  opt.candidates = 0;
  EXPECT_FALSE(opt.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("candidates = 0"));
  DesignKind kind;
  EXPECT_TRUE(StringToDesignKind("halton", &kind));
  EXPECT_EQ(kind, DesignKind::kHalton);
  EXPECT_FALSE(StringToDesignKind("sobol", &kind));
}

TEST(ReachStatistic, AtTheEdgeWhenOnlyTheSigmaAllowancePutsItInReach) {
  ReachStatistic s;
  s.id = observations::ResidualId::Of(observations::ObservationKind::kRunoutDistance)
             .With(observations::Statistic::kQuantile, 0.9);
  s.min = 10.0;
  s.max = 20.0;
  s.verdict = ReachVerdict::kInReach;
  s.observed = 15.0;
  EXPECT_FALSE(s.at_edge());
  s.observed = 20.5;
  EXPECT_TRUE(s.at_edge());
  s.verdict = ReachVerdict::kAbove;
  EXPECT_FALSE(s.at_edge()) << "out of reach is not at the edge";
  EXPECT_EQ(s.name(), "runout distance p90");
}

// ---- RunReach on the twin slope -----------------------------------------------------

// The twin slope with two parameters, few rocks: quick under the sanitizers.
// The observations come from 60 rocks at the true values, so that their
// quantiles lie near the truth's (from 20, the runout p50 could fall more
// than a sigma beyond what 6-rock points reach: a draw, not the box).
struct Twin {
  explicit Twin(int threads = 1) {
    site.calibrate = {site.calibrate[0], site.calibrate[2]};  // slope and runout hardness
    site.scene.options.threads = threads;
    sites::Site observed = TwinSite(60);
    observed.calibrate = site.calibrate;
    obs = TwinObservations(observed, {0.5, 0.3}, 5);
  }
  Objective MakeObjective() const {
    return Objective(site.scene, ParameterSpace::FromSite(site), obs, {});
  }
  sites::Site site = TwinSite(6);
  observations::Observations obs;
};

const ReachStatistic* Find(const ReachResult& r, const std::string& name) {
  for (const ReachStatistic& s : r.statistics)
    if (s.name() == name) return &s;
  return nullptr;
}

// What the points said, for a failure message: misfit and why penalised.
std::string Points(const ReachResult& r) {
  std::string out = std::to_string(r.statistics.size()) + " statistics; points:";
  for (const ReachPoint& p : r.points)
    out +=
        "\n  misfit " + std::to_string(p.misfit) + (p.penalised ? " penalised: " + p.message : "");
  return out;
}

ReachOptions FewPoints() {
  ReachOptions opt;
  opt.points = 5;
  opt.seed = 3;
  return opt;
}

TEST(RunReach, ObservationsFromInsideTheBoxAreInReach) {
  const Twin twin;
  const ReachResult r = RunReach(twin.MakeObjective(), FewPoints());
  ASSERT_EQ(r.points.size(), 5u);
  EXPECT_EQ(r.rocks, 6);
  // Statistics are the misfit's residuals: two scar sets and the runout,
  // each with 9 quantiles and the max, and the share of rocks that stopped.
  EXPECT_EQ(r.statistics.size(), 4u * 10u + 1u);
  const ReachStatistic* p50 = Find(r, "runout distance p50");
  ASSERT_NE(p50, nullptr) << Points(r);
  EXPECT_TRUE(p50->in_reach()) << "observed " << p50->observed << ", reached " << p50->min << " to "
                               << p50->max << ", sigma " << p50->sigma;
  EXPECT_LE(p50->min, p50->max);
  EXPECT_EQ(p50->points_with_value, 5);
  ASSERT_GE(p50->closest_point, 0);
  EXPECT_LE(std::abs(p50->closest_sigmas), std::abs(p50->observed - p50->min) / p50->sigma + 1e-9);
  ASSERT_GE(r.best_point, 0);
  for (const ReachPoint& p : r.points) EXPECT_GE(p.misfit, r.points[r.best_point].misfit);
  EXPECT_THAT(r.BriefReport(), HasSubstr("5 points (lhs, seed 3)"));
}

TEST(RunReach, ARunoutFarBeyondTheSlopeIsOutOfReachAbove) {
  Twin twin;
  // Every rock stops on the 90 m slope; the "observed" rocks stopped 500 m on.
  for (double& d : twin.obs.runout->distances) d += 500.0;
  const ReachResult r = RunReach(twin.MakeObjective(), FewPoints());
  const ReachStatistic* p50 = Find(r, "runout distance p50");
  ASSERT_NE(p50, nullptr) << Points(r);
  EXPECT_EQ(p50->verdict, ReachVerdict::kAbove)
      << "observed " << p50->observed << ", reached " << p50->min << " to " << p50->max;
  // (A rock that left the slope is censored in the upper tail, so p50 may
  // exceed the slope's length where most rocks left; never the observed.)
  EXPECT_LT(p50->max, p50->observed);
  EXPECT_GT(p50->observed, 500.0);
  // The scar heights were not moved: still in reach.
  const ReachStatistic* scar = Find(r, "tree_scars[0] P p50");
  ASSERT_NE(scar, nullptr) << Points(r);
  EXPECT_TRUE(scar->in_reach()) << scar->observed << " vs " << scar->min << " to " << scar->max;
  const std::vector<std::string> warnings = OutOfReachWarnings(r);
  ASSERT_FALSE(warnings.empty());
  bool named = false;
  for (const std::string& w : warnings)
    named = named || w.rfind("runout distance p50 is out of reach: observed", 0) == 0;
  EXPECT_TRUE(named) << warnings[0];
  EXPECT_THAT(r.BriefReport(), HasSubstr("OUT OF REACH: runout distance p50"));
  // The advice once, after the lines, naming every statistic it concerns.
  const std::vector<std::string> bare = OutOfReachWarnings(r, false);
  ASSERT_EQ(bare.size(), warnings.size());
  for (std::size_t k = 0; k < bare.size(); ++k) {
    EXPECT_EQ(bare[k].find("Widen the box"), std::string::npos) << bare[k];
    EXPECT_EQ(warnings[k].rfind(bare[k], 0), 0u) << warnings[k];
  }
  const std::string advice = OutOfReachAdvice(r);
  EXPECT_THAT(advice, HasSubstr("runout distance p50"));
  EXPECT_THAT(advice, HasSubstr("widen the box"));
  const std::string brief = r.BriefReport();
  std::size_t times = 0;
  for (std::size_t at = brief.find("widen the box"); at != std::string::npos;
       at = brief.find("widen the box", at + 1))
    ++times;
  EXPECT_EQ(times, 1u) << brief;
  EXPECT_EQ(brief.find("Widen the box"), std::string::npos) << brief;
}

TEST(RunReach, ARunoutShorterThanAnyRockIsOutOfReachBelow) {
  Twin twin;
  for (double& d : twin.obs.runout->distances) d = -200.0 + 0.01 * d;
  const ReachResult r = RunReach(twin.MakeObjective(), FewPoints());
  const ReachStatistic* p10 = Find(r, "runout distance p10");
  ASSERT_NE(p10, nullptr) << Points(r);
  EXPECT_EQ(p10->verdict, ReachVerdict::kBelow) << p10->observed << " vs " << p10->min;
  EXPECT_EQ(std::string(ReachVerdictText(p10->verdict)), "out of reach (below)");
}

TEST(RunReach, ScarsWhereNoRockPassesHaveNoValueAnywhere) {
  Twin twin;
  // A partition behind the release (x = 0.3 m; rocks start at 1 to 4 m and
  // run down towards +x): no rock crosses it at any point of the box, so
  // every point's scar distribution there is penalised.
  twin.site.scene.partitions.push_back({"behind", core::Partition::Kind::kX, 0.3});
  observations::ScarSet behind;
  behind.label = "tree_scars[2] behind";
  behind.partition = 2;
  behind.heights = {0.5, 1.0, 1.5};
  twin.obs.tree_scars.push_back(behind);
  const ReachResult r = RunReach(twin.MakeObjective(), FewPoints());
  const ReachStatistic* scar = Find(r, "tree_scars[2] behind p50");
  ASSERT_NE(scar, nullptr) << Points(r);
  EXPECT_EQ(scar->verdict, ReachVerdict::kNoValue);
  EXPECT_EQ(scar->points_with_value, 0);
  EXPECT_TRUE(std::isnan(scar->min) && std::isnan(scar->sigma));
  for (const ReachPoint& p : r.points) EXPECT_TRUE(p.penalised);
  // The other statistics of the same, penalised, misfits keep their values.
  const ReachStatistic* runout = Find(r, "runout distance p50");
  ASSERT_NE(runout, nullptr) << Points(r);
  EXPECT_EQ(runout->points_with_value, 5);
  EXPECT_TRUE(runout->in_reach());
  bool named = false;
  for (const std::string& w : OutOfReachWarnings(r))
    named = named || w.rfind("tree_scars[2] behind p50 is out of reach", 0) == 0;
  EXPECT_TRUE(named);
}

TEST(RunReach, SameResultAtOneAndTwoThreads) {
  const ReachResult a = RunReach(Twin(1).MakeObjective(), FewPoints());
  const ReachResult b = RunReach(Twin(2).MakeObjective(), FewPoints());
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t p = 0; p < a.points.size(); ++p) {
    EXPECT_EQ(a.points[p].unit, b.points[p].unit);
    EXPECT_EQ(a.points[p].misfit, b.points[p].misfit) << p;
    ASSERT_EQ(a.points[p].simulated.size(), b.points[p].simulated.size());
    for (std::size_t s = 0; s < a.points[p].simulated.size(); ++s) {
      const double x = a.points[p].simulated[s], y = b.points[p].simulated[s];
      EXPECT_TRUE(x == y || (std::isnan(x) && std::isnan(y))) << p << " " << s;
    }
  }
  ASSERT_EQ(a.statistics.size(), b.statistics.size());
  for (std::size_t s = 0; s < a.statistics.size(); ++s)
    EXPECT_EQ(a.statistics[s].verdict, b.statistics[s].verdict) << a.statistics[s].name();
  // Every statistic and point alike (the wall time aside).
  nlohmann::json ja = a, jb = b;
  ja.erase("wall_seconds");
  jb.erase("wall_seconds");
  EXPECT_EQ(ja, jb);
}

TEST(RunReach, JsonCarriesEveryStatistic) {
  const Twin twin;
  const ReachResult r = RunReach(twin.MakeObjective(), FewPoints());
  EXPECT_EQ(r.site, twin.site.scene.name);
  const nlohmann::json j = r;
  EXPECT_EQ(j["statistics"].size(), r.statistics.size());
  EXPECT_EQ(j["points"].size(), 5u);
  EXPECT_EQ(j["design"]["kind"], "lhs");
  EXPECT_EQ(j["out_of_reach"], r.out_of_reach());
  EXPECT_EQ(j["statistics"][0]["verdict"], ReachVerdictText(r.statistics[0].verdict));
  const nlohmann::json& statistics = j["statistics"];
  EXPECT_NE(
      std::find_if(statistics.begin(), statistics.end(),
                   [](const nlohmann::json& s) { return s["name"] == "runout distance p50"; }),
      statistics.end());
}

TEST(RunReach, RejectsInvalidOptions) {
  ReachOptions opt;
  opt.points = 1;
  EXPECT_THROW(RunReach(Twin().MakeObjective(), opt), std::invalid_argument);
}

}  // namespace
}  // namespace rockcal::calibrate
