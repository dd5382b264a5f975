#include "rockcal/calibrate/objective.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rockcal/observations/misfit.h"

namespace rockcal::calibrate {
namespace {

using observations::ObservationKind;
using observations::Residual;
using observations::ResidualId;
using observations::Statistic;

// The misfit a rank sends to rank 0 under mpirun reads back whole: the
// value, the penalty and its message, and every residual with its typed
// identity (kind, index, name, statistic, level, site) and numbers.
TEST(MisfitCodec, ReadsBackEveryResidualWithItsIdentity) {
  observations::Misfit m;
  m.value = 12.25;
  m.penalised = true;
  m.message = "runout distance: 1 simulated value (fewer than 2); penalty 1e+06 added.";
  std::vector<ResidualId> ids = {
      ResidualId::Of(ObservationKind::kTreeScars, 1, "tree_scars[1] trees")
          .With(Statistic::kQuantile, 0.025),
      ResidualId::Of(ObservationKind::kRunoutDistance).With(Statistic::kMax),
      ResidualId::Of(ObservationKind::kRunoutMassClass, 2, ">= 40").With(Statistic::kQuantile, 0.5),
      ResidualId::Of(ObservationKind::kRun, 3, "v083").With(Statistic::kRunout),
      ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] BP-2").With(Statistic::kFraction),
      ResidualId::Of(ObservationKind::kPrior, 0, "talus.hardness").With(Statistic::kOffset),
      ResidualId{}};
  ids[1].site = "a";
  ids[5].site = "b";
  for (std::size_t k = 0; k < ids.size(); ++k) {
    Residual r;
    r.id = ids[k];
    r.simulated = 40.0 + static_cast<double>(k);
    r.observed = 38.5;
    r.sigma = 0.1 * static_cast<double>(k + 1);
    r.value = -1.0 / 3.0 * static_cast<double>(k);
    m.residuals.push_back(r);
  }
  const observations::Misfit back = DecodeMisfit(EncodeMisfit(m));
  EXPECT_EQ(back.value, m.value);
  EXPECT_EQ(back.penalised, m.penalised);
  EXPECT_EQ(back.message, m.message);
  ASSERT_EQ(back.residuals.size(), m.residuals.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Residual& a = m.residuals[k];
    const Residual& b = back.residuals[k];
    EXPECT_EQ(b.id, a.id) << a.id.observation() << " " << a.id.quantity();
    EXPECT_EQ(b.id.observation(), a.id.observation());
    EXPECT_EQ(b.id.quantity(), a.id.quantity());
    EXPECT_EQ(b.simulated, a.simulated);
    EXPECT_EQ(b.observed, a.observed);
    EXPECT_EQ(b.sigma, a.sigma);
    EXPECT_EQ(b.value, a.value);
  }
  EXPECT_EQ(back.residuals[1].id.observation(), "a: runout distance");
  EXPECT_EQ(back.residuals[5].id.quantity(), "b:talus.hardness_offset");
}

}  // namespace
}  // namespace rockcal::calibrate
