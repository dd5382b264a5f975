#include "rockcal/reports/simulation_outputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

namespace rockcal::reports {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

core::RockRecord FiniteRock(int index) {
  core::RockRecord r;
  r.rock = index;
  r.size = 1.0;
  r.mass = 1000.0;
  r.outcome = core::Outcome::kStopped;
  r.stop = Eigen::Vector3d(10.0 + index, 0.0, 1.0);
  return r;
}

std::string MessageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a std::runtime_error";
  return "";
}

TEST(SimulationOutputs, ANonFiniteValueIsAnInternalFailureNeverWritten) {
  core::Scene scene;
  scene.name = "s";
  core::SimulationResult result;
  result.rocks = {FiniteRock(0), FiniteRock(1)};
  result.rocks[1].stop.x() = INFINITY;
  const std::string msg = MessageOf([&] { RocksCsv(scene, result); });
  EXPECT_THAT(msg, HasSubstr("internal failure: rocks.csv rock 1 column stop_x is inf"));

  const std::string folder =
      ::testing::TempDir() + "/rockcal_simulation_outputs_" + std::to_string(::getpid());
  fs::remove_all(folder);
  fs::create_directories(folder);
  EXPECT_THAT(MessageOf([&] { WriteSimulationFiles(folder, scene, result); }),
              HasSubstr("not a finite number"));
  EXPECT_FALSE(fs::exists(folder + "/rocks.csv"));
  EXPECT_FALSE(fs::exists(folder + "/summary.json"));

  result.rocks[1].stop.x() = 11.0;
  result.figures.max_relative_energy_gain = NAN;
  EXPECT_THAT(MessageOf([&] { WriteSimulationFiles(folder, scene, result); }),
              HasSubstr("summary.json $.energy_check.max_relative_gain is nan"));
  EXPECT_FALSE(fs::exists(folder + "/summary.json"));
  fs::remove_all(folder);
}

}  // namespace
}  // namespace rockcal::reports
