// The distributed engine in one process: the codec the ranks exchange
// records with, and Map, OnRoot and Simulate as a single rank runs them.
// (Several ranks: tests/cli/mpi_test.cc runs rockcal under mpirun.)
#include "rockcal/parallel/parallel.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "rockcal/core/error.h"

namespace rockcal::parallel {
namespace {

core::SimulationResult SampleResult() {
  core::SimulationResult r;
  for (int k = 0; k < 3; ++k) {
    core::RockRecord rec;
    rec.rock = k;
    rec.group = k % 2;
    rec.shape = k == 2 ? core::Shape::kBox : core::Shape::kSphere;
    rec.size = 0.1 * k + 1.0 / 3.0;
    rec.mass = 1e3 + k;
    rec.bounding_radius = 0.25 + k / 3.0;
    rec.outcome = k == 1 ? core::Outcome::kLeft : core::Outcome::kStopped;
    rec.start = Eigen::Vector3d(1.0 / 7.0, 2, 3);
    rec.stop = Eigen::Vector3d(-0.0, 1e-300, 5e300);
    rec.time = 12.5;
    rec.steps = 123456789012L;
    rec.gentle_steps = 7;
    rec.retried_steps = 1;
    rec.flights = 42;
    rec.dt = 1e-5;
    rec.max_relative_energy_gain = -1e-12;
    rec.max_penetration = 0.01;
    rec.tunneled = k == 2;
    rec.stopped_by = k == 1 ? -1 : k + 3;
    rec.crossings.push_back({true, 1.5, 2.5, 3.5, Eigen::Vector3d(4, 5, 6)});
    rec.crossings.push_back({false, 0, 0, 0, Eigen::Vector3d::Zero()});
    if (k == 0) rec.trees.push_back({true, 0.7, 1, 2, Eigen::Vector3d(1, 1, 1)});
    rec.cells = {{3, 0.25, 100.0, 7.5}, {4, 0.5, 200.0 / 3.0, 1.0 / 3.0}};
    if (k == 1)
      rec.trajectory.push_back({0.05, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6),
                                Eigen::Vector3d(7, 8, 9), Eigen::Vector4d(1, 0, 0, 0)});
    r.rocks.push_back(rec);
  }
  r.figures.rocks = 3;
  r.figures.steps = 99;
  r.figures.flights = 98;
  r.figures.gentle_steps = 97;
  r.figures.retried_steps = 96;
  r.wall_seconds = 0.125;
  r.busy_seconds = 0.25;
  r.figures.dt_min = 1e-6;
  r.figures.dt_max = 2e-5;
  r.figures.dt_shrunk = 2;
  r.figures.max_relative_energy_gain = 3e-4;
  r.figures.max_penetration = 0.02;
  r.figures.non_finite = 0;
  r.cells_recorded = true;
  r.figures.tunneled = 1;
  core::ImpactRebound impact;
  impact.normal = Eigen::Vector3d(0.6, 0, 0.8);
  impact.velocity = {Eigen::Vector3d(1.0 / 3.0, 2, -0.0), Eigen::Vector3d(4, 5, 6)};
  impact.left = {1, 0};
  r.impacts = {impact, core::ImpactRebound{}};
  return r;
}

TEST(Codec, SimulationResultRoundTripsBitForBit) {
  const core::SimulationResult r = SampleResult();
  const std::string bytes = EncodeResult(r);
  const core::SimulationResult back = DecodeResult(bytes);
  EXPECT_EQ(EncodeResult(back), bytes);
  ASSERT_EQ(back.rocks.size(), 3u);
  EXPECT_EQ(back.rocks[2].shape, core::Shape::kBox);
  EXPECT_EQ(back.rocks[1].outcome, core::Outcome::kLeft);
  EXPECT_EQ(back.rocks[0].start.x(), 1.0 / 7.0);
  EXPECT_EQ(back.rocks[2].bounding_radius, 0.25 + 2 / 3.0);
  EXPECT_EQ(back.rocks[1].stopped_by, -1);
  EXPECT_EQ(back.rocks[2].stopped_by, 5);
  EXPECT_TRUE(std::signbit(back.rocks[0].stop.x()));
  EXPECT_EQ(back.rocks[0].steps, 123456789012L);
  EXPECT_EQ(back.rocks[0].trees.size(), 1u);
  EXPECT_EQ(back.rocks[1].trajectory.size(), 1u);
  EXPECT_EQ(back.rocks[2].cells[1].energy, 200.0 / 3.0);
  EXPECT_EQ(back.rocks[2].cells[1].speed, 1.0 / 3.0);
  EXPECT_TRUE(back.cells_recorded);
  EXPECT_EQ(back.figures.tunneled, 1);
  EXPECT_EQ(back.figures.rocks, 3);
  EXPECT_EQ(back.busy_seconds, 0.25);
  ASSERT_EQ(back.impacts.size(), 2u);
  EXPECT_EQ(back.impacts[0].normal, Eigen::Vector3d(0.6, 0, 0.8));
  EXPECT_EQ(back.impacts[0].velocity[0].x(), 1.0 / 3.0);
  EXPECT_EQ(back.impacts[0].left, (std::vector<char>{1, 0}));
  EXPECT_TRUE(back.impacts[1].velocity.empty());
}

TEST(Codec, ACutMessageIsAnError) {
  const std::string bytes = EncodeResult(SampleResult());
  EXPECT_THROW(DecodeResult(bytes.substr(0, bytes.size() / 2)), std::runtime_error);
  EXPECT_THROW(DecodeResult(bytes + "x"), std::runtime_error);
}

TEST(Codec, WriterAndReaderKeepPlainValues) {
  Writer w;
  w.Int(-5);
  w.Double(0.1);
  w.Doubles({1.0, 2.0 / 3.0});
  w.String(std::string("a\0b", 3));
  Reader r(w.bytes());
  EXPECT_EQ(r.Int(), -5);
  EXPECT_EQ(r.Double(), 0.1);
  EXPECT_EQ(r.Doubles(), (std::vector<double>{1.0, 2.0 / 3.0}));
  EXPECT_EQ(r.String(), std::string("a\0b", 3));
  EXPECT_TRUE(r.done());
  EXPECT_THROW(r.Int(), std::runtime_error);
}

TEST(SingleRank, MapRunsEveryTaskInOrder) {
  EXPECT_EQ(Size(), 1);
  EXPECT_TRUE(IsRoot());
  std::vector<int> seen;
  const std::vector<std::string> out = Map(
      4, [](int k) { return std::to_string(k * k); },
      [&](int k, const std::string& r) {
        seen.push_back(k);
        EXPECT_EQ(r, std::to_string(k * k));
      });
  EXPECT_EQ(out, (std::vector<std::string>{"0", "1", "4", "9"}));
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_TRUE(Map(0, [](int) { return std::string(); }).empty());
}

TEST(SingleRank, MapAndOnRootKeepTheKindOfError) {
  EXPECT_THROW(Map(3,
                   [](int k) -> std::string {
                     if (k == 1) throw InputError("file.json", "bad value");
                     return "";
                   }),
               InputError);
  EXPECT_THROW(OnRoot([] { throw std::runtime_error("disk full"); }), std::runtime_error);
  EXPECT_THROW(OnRoot([] { throw InputError("DIR", "exists"); }), InputError);
  bool ran = false;
  OnRoot([&] { ran = true; });
  EXPECT_TRUE(ran);
  EXPECT_TRUE(RootDecides(true));
  EXPECT_FALSE(RootDecides(false));
}

}  // namespace
}  // namespace rockcal::parallel
