// The small version of the posterior's scene family (issue #54; the family
// itself: bench/posterior_coverage.cc, figures in bench/README.md): 30 twins
// of the twin slope with truths from the prior, two hardnesses calibrated
// from 60 field rocks' bounce heights and stop points at 60 rocks per
// evaluation, at most 3 refining rounds (the product's default is 8; at 8
// these 30 twins take 136 s against about 50 s; at the default errors the
// family's bench found no difference, 76 and 75 of 80: bench/README.md,
// fifth round).
// Labelled "heavy".
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "posterior_twin.h"

namespace rockcal::calibrate {
namespace {

using testing::PosteriorTwin;
using testing::PosteriorTwinOptions;

TEST(PosteriorTwins, NinetyPercentIntervalsHoldTheTruthAndTheRanksAreUniform) {
  PosteriorTwinOptions o;
  o.parameters = 2;
  o.obs_rocks = 60;
  o.rocks = 60;
  o.truths = "prior";
  o.ranks = 99;
  o.rounds = 3;
  ASSERT_EQ(testing::Check(o), "");
  constexpr int kTwins = 30;
  int inside = 0;
  std::vector<int> ranks;
  std::vector<double> width(2, 0.0);
  const ParameterSpace space = ParameterSpace::FromSite(testing::PosteriorTwinSite(o, o.rocks));
  for (int t = 1; t <= kTwins; ++t) {
    const PosteriorTwin twin = testing::RunPosteriorTwin(o, t);
    for (std::size_t k = 0; k < 2; ++k) {
      inside += twin.inside[k];
      ranks.push_back(twin.rank[k]);
      const auto& p = twin.posterior.parameters[k];
      width[k] += (p.p95 - p.p05) / (space.parameters()[k].upper - space.parameters()[k].lower);
    }
  }
  // An honest posterior's 60 intervals hold the truth 54 times on average;
  // 46 or fewer happens with probability 0.002 (binomial, the intervals
  // taken as independent). Intervals too narrow or shifted fail here.
  EXPECT_GE(inside, 47) << "of " << 2 * kTwins << " 90 % intervals";
  // The truth's rank among 99 samples, over both values: uniform within its
  // sampling error (chi-square in 10 bins, p above 0.001). Intervals too
  // wide pile the ranks in the middle bins and fail here.
  const std::vector<int> bins = testing::RankHistogram(ranks, o.ranks, 10);
  std::string histogram;
  for (const int b : bins) histogram += std::to_string(b) + " ";
  const double p = testing::ChiSquareP(testing::ChiSquare(bins), 10);
  EXPECT_GT(p, 0.001) << "ranks in 10 bins: " << histogram;
  // And the posterior says something: both hardnesses are determined by
  // these observations, far narrower than the box (a posterior equal to
  // the prior would give 0.9).
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_LT(width[k] / kTwins, 0.5) << space.parameters()[k].label();
  RecordProperty("inside", inside);
  RecordProperty("rank_p", std::to_string(p));
}

}  // namespace
}  // namespace rockcal::calibrate
