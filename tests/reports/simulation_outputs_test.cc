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

// barriers.csv by hand: a US site's barrier (3.048 m = 10 ft, 500 kJ) that
// two rocks reached, one over it by its lowest point and above its capacity,
// the other stopped by it; a second barrier no rock reached (empty
// percentiles). summary.json's "barriers" holds the same in SI.
TEST(SimulationOutputs, BarriersCsvInTheSitesUnits) {
  core::Scene scene;
  scene.name = "s";
  core::Partition plane;
  plane.id = "P";
  core::Partition net;
  net.id = "net";
  net.kind = core::Partition::Kind::kLine;
  net.line = {{0, 0}, {0, 10}};
  net.height = 3.048;
  net.capacity = 500e3;
  net.stops = true;
  core::Partition far = net;
  far.id = "far";
  far.stops = false;
  scene.partitions = {plane, net, far};
  core::SimulationResult result;
  result.rocks = {FiniteRock(0), FiniteRock(1)};
  for (core::RockRecord& r : result.rocks) {
    r.bounding_radius = 0.5;
    r.crossings.assign(3, core::Crossing{});
    r.crossings[1].crossed = true;
  }
  result.rocks[0].crossings[1].height = 0.3048 * 20 + 0.5;  // lowest point 20 ft
  result.rocks[0].crossings[1].energy = 600e3;
  result.rocks[1].crossings[1].height = 0.3048 * 4 + 0.5;  // lowest point 4 ft
  result.rocks[1].crossings[1].energy = 100e3;
  result.rocks[1].stopped_by = 1;
  const std::string csv = BarriersCsv(scene, result, sites::Units::kUS);
  // Type 7 over {4, 20} ft: p95 = 4 + 0.95 * 16 = 19.2, p99 = 19.84; the
  // centres 0.5 m = 1.64 ft higher; energies {100, 600} kJ: 575 and 595.
  EXPECT_EQ(csv,
            "id,height_ft,capacity_kj,stops,reaching,passing_over,centre_above,exceeding_capacity,"
            "stopped,lowest_point_p95_ft,lowest_point_p99_ft,centre_p95_ft,centre_p99_ft,"
            "energy_p95_kj,energy_p99_kj\n"
            "net,10,500,true,2,1,1,1,1,19.2,19.84,20.84041995,21.48041995,575,595\n"
            "far,10,500,false,0,0,0,0,0,,,,,,\n");
  const nlohmann::json summary = SummaryJson(scene, result);
  ASSERT_EQ(summary["barriers"].size(), 2u);
  EXPECT_EQ(summary["barriers"][0]["stopped"], 1);
  EXPECT_NEAR(summary["barriers"][0]["energy_kj"]["p95"].get<double>(), 575.0, 1e-9);
  EXPECT_TRUE(summary["barriers"][1]["energy_kj"]["p95"].is_null());
  // A scene without barriers keeps summary.json as it was.
  scene.partitions = {plane};
  EXPECT_FALSE(SummaryJson(scene, result).contains("barriers"));
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
