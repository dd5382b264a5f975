// The emulator (calibrate/src/emulator.cc) against known functions.
#include "rockcal/calibrate/emulator.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rockcal/calibrate/reach.h"

namespace rockcal::calibrate {
namespace {

double Smooth(const std::vector<double>& u) { return std::sin(3.0 * u[0]) + 2.0 * u[1] * u[1]; }

TEST(Emulator, InterpolatesASmoothFunctionBetweenItsPoints) {
  const auto x = SpaceFillingDesign(DesignKind::kLatinHypercube, 30, 2, 7);
  std::vector<std::vector<double>> y;
  for (const auto& u : x) y.push_back({Smooth(u), -Smooth(u)});
  const Emulator e = Emulator::Fit(x, y);
  // At new points of the box, away from the design's.
  const auto test = SpaceFillingDesign(DesignKind::kHalton, 40, 2, 3);
  double worst = 0.0, worst_sd = 0.0;
  for (const auto& u : test) {
    Eigen::VectorXd mean, variance;
    e.Predict(Eigen::Vector2d(u[0], u[1]), &mean, &variance);
    worst = std::max(worst, std::abs(mean(0) - Smooth(u)));
    EXPECT_NEAR(mean(1), -mean(0), 1e-9) << "the outputs share the fit";
    worst_sd = std::max(worst_sd, std::sqrt(variance(0)));
  }
  // The function spans about 3; an emulator of 30 points is within 1 % of it.
  EXPECT_LT(worst, 0.03) << "largest error " << worst;
  EXPECT_LT(worst_sd, 0.05) << "largest predictive sd " << worst_sd;
  EXPECT_LT(e.nugget(), 1e-3) << "a noiseless function needs no nugget";
  // At a design point: the value itself, with (almost) no variance.
  Eigen::VectorXd mean, variance;
  e.Predict(Eigen::Vector2d(x[4][0], x[4][1]), &mean, &variance);
  EXPECT_NEAR(mean(0), Smooth(x[4]), 1e-3);
  EXPECT_LT(variance(0), 1e-4);
}

TEST(Emulator, ANoisyFunctionGetsANuggetAndIsSmoothed) {
  const auto x = SpaceFillingDesign(DesignKind::kLatinHypercube, 60, 2, 11);
  std::vector<std::vector<double>> y;
  // Deterministic "noise" of sd ~0.1 that varies fast against the trend.
  for (std::size_t k = 0; k < x.size(); ++k)
    y.push_back({Smooth(x[k]) + 0.1 * std::sqrt(2.0) * std::sin(1000.0 * static_cast<double>(k))});
  const Emulator e = Emulator::Fit(x, y);
  EXPECT_GT(e.nugget(), 1e-3) << "nugget " << e.nugget();
  double sq = 0.0;
  const auto test = SpaceFillingDesign(DesignKind::kHalton, 50, 2, 5);
  for (const auto& u : test) {
    Eigen::VectorXd mean;
    e.Predict(Eigen::Vector2d(u[0], u[1]), &mean, nullptr);
    sq += std::pow(mean(0) - Smooth(u), 2);
  }
  const double rms = std::sqrt(sq / static_cast<double>(test.size()));
  EXPECT_LT(rms, 0.07) << "rms error " << rms << " against the noise's 0.1";
}

TEST(Emulator, RejectsTooFewPoints) {
  EXPECT_THROW(Emulator::Fit({{0.1, 0.2}, {0.3, 0.4}}, {{1.0}, {2.0}}), std::invalid_argument);
  EXPECT_THROW(Emulator::Fit({{0.1}}, {{1.0}, {2.0}}), std::invalid_argument);
}

}  // namespace
}  // namespace rockcal::calibrate
