// The rock groups' readers (sites/src/rock_groups.cc, site_readers.h): a
// release's place, height and velocity, read from a JSON node on a grid.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "site_readers.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using Json = nlohmann::json;

// A flat grid 100 m x 50 m at 10 m, its ground at 20 m.
core::HeightGrid FlatGrid() {
  core::HeightGrid g;
  g.spacing = 10.0;
  g.nx = 11;
  g.ny = 6;
  g.z.assign(static_cast<std::size_t>(g.nx * g.ny), 20.0);
  g.material.assign(g.z.size(), 0);
  return g;
}

core::Release Read(const Json& json, Units units, std::string* note) {
  return ReadRelease(JsonNode(&json, "site.json", "$.rocks[0].release"), units, FlatGrid(), note);
}

TEST(ReadRelease, APointsSpreadIsADiscOf24Vertices) {
  const Json json = Json::parse(R"({"point": [40, 25], "position_spread": 2, "height": 1.5})");
  std::string note;
  const core::Release r = Read(json, Units::kSI, &note);
  EXPECT_EQ(r.point, Eigen::Vector2d(40.0, 25.0));
  ASSERT_EQ(r.zone.size(), 24u);
  for (const Eigen::Vector2d& v : r.zone)
    EXPECT_NEAR((v - r.point).norm(), 2.0, 1e-12) << "vertex " << v.transpose();
  EXPECT_EQ(r.height, 1.5);
  EXPECT_EQ(note, "point (40, 25) m within 2 m (uniform in the disc), ground 20 m");
}

TEST(ReadRelease, AZoneIsReadInTheSitesUnitsAndAVelocityToo) {
  const Json json = Json::parse(
      R"({"zone": [[0, 0], [100, 0], [100, 100], [0, 100]], "velocity": [10, 0, -5]})");
  std::string note;
  const core::Release r = Read(json, Units::kUS, &note);
  ASSERT_EQ(r.zone.size(), 4u);
  EXPECT_NEAR(r.zone[2].x(), 30.48, 1e-12);
  EXPECT_NEAR(r.velocity.x(), 3.048, 1e-12);
  EXPECT_NEAR(r.velocity.z(), -1.524, 1e-12);
  EXPECT_THAT(note, HasSubstr("zone of 4 vertices, area 10000 ft^2"));
}

TEST(ReadRelease, ADropBelowTheGroundNamesTheKeyAndTheGround) {
  const Json json = Json::parse(R"({"point": [40, 25], "elevation": 19})");
  std::string note;
  const std::string error = ErrorOf([&] { Read(json, Units::kSI, &note); });
  EXPECT_THAT(error, HasSubstr("$.rocks[0].release.elevation"));
  EXPECT_THAT(error, HasSubstr("the ground of the release reaches 20 m"));
}

TEST(ReadRelease, APointOffTheTerrainFails) {
  const Json json = Json::parse(R"({"point": [140, 25]})");
  std::string note;
  const std::string error = ErrorOf([&] { Read(json, Units::kSI, &note); });
  EXPECT_THAT(error, HasSubstr("$.rocks[0].release.point"));
  EXPECT_THAT(error, HasSubstr("the terrain spans x 0 to 100, y 0 to 50"));
}

}  // namespace
}  // namespace rockcal::sites
