#include "rockcal/sites/site.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/sites/surface.h"
#include "test_files.h"

namespace rockcal::sites {
namespace site_test {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;
using Json = nlohmann::json;

// A valid US site: a 200 ft x 100 ft plane from 100 ft down to 0, grid of 10 ft.
Json BaseSite() {
  return Json::parse(R"({
    "name": "test slope",
    "units": "us",
    "surface": {"resolution": 10, "sphere_spacing": 10,
                "points": [[0, 0, 100], [200, 0, 0], [0, 100, 100], [200, 100, 0]]},
    "materials": [
      {"id": "rock", "hardness": 0.6, "roughness": 1.0},
      {"id": "talus", "hardness": 0.3, "roughness": 2.0, "contact_time": 0.004,
       "zone": [[100, -5], [205, -5], [205, 105], [100, 105]],
       "calibrate": {"hardness": [0.1, 0.6], "roughness": [0.5, 5.0],
                     "contact_time": [0.002, 0.01]}}
    ],
    "partitions": [{"id": "BP-1", "x": 150}, {"id": "BP-2", "z": 40}],
    "rocks": [
      {"count": 10, "shape": "sphere", "size": [1, 3], "unit_weight": 165,
       "release": {"zone": [[10, 40], [30, 40], [30, 60], [10, 60]], "height": 1,
                   "velocity": [1, 0, -2]}},
      {"count": 5, "shape": "cube", "size": 2, "unit_weight": 150,
       "release": {"point": [20, 50]}}
    ],
    "simulation": {"seed": 7, "max_time": 30, "stop_speed": 0.5}
  })");
}

std::string WriteSite(const TempDir& dir, const Json& site) {
  return dir.Write("site.json", site.dump(2));
}

// The error of loading BaseSite() changed by `edit`.
std::string LoadError(const std::function<void(Json&)>& edit) {
  TempDir dir;
  Json site = BaseSite();
  edit(site);
  const std::string path = WriteSite(dir, site);
  const std::string msg = ErrorOf([&] { LoadSite(path); });
  EXPECT_THAT(msg, HasSubstr(path + ": ")) << "the message must name the site file";
  return msg;
}

// Issue 14: values outside physically sensible ranges are bad input, named
// with their JSON path, value and range (not a silently meaningless run).
TEST(LoadSite, RefusesPhysicallyMeaninglessValues) {
  std::string msg = LoadError([](Json& s) { s["rocks"][1]["size"] = 400; });  // ft: 122 m
  EXPECT_THAT(msg, HasSubstr("$.rocks[1].size: rock size 400 ft is outside the physically "
                             "sensible range; expected [0, 328.0839895] ft"));
  msg = LoadError([](Json& s) { s["rocks"][0]["size"] = Json::array({1, 1000}); });
  EXPECT_THAT(msg, HasSubstr("$.rocks[0].size: rock size 1000 ft"));
  msg = LoadError([](Json& s) { s["rocks"][0]["unit_weight"] = 0.5; });
  EXPECT_THAT(msg, HasSubstr("$.rocks[0].unit_weight: unit weight 0.5 lbf/ft^3"));
  msg = LoadError([](Json& s) {
    s["units"] = "si";
    s["surface"]["resolution"] = 10;
    s["surface"]["sphere_spacing"] = 10;
    s["rocks"][1]["unit_weight"] = 2500;  // a density typed as a unit weight
  });
  EXPECT_THAT(msg, HasSubstr("$.rocks[1].unit_weight: unit weight 2500 kN/m^3"));
  EXPECT_THAT(msg, HasSubstr("expected [1, 200] kN/m^3"));
  msg = LoadError([](Json& s) { s["rocks"][0]["release"]["velocity"] = Json::array({1e4, 0, 0}); });
  EXPECT_THAT(msg, HasSubstr("$.rocks[0].release.velocity: release speed 10000 ft/s"));
  msg = LoadError([](Json& s) { s["rocks"][0]["release"]["height"] = 1e9; });
  EXPECT_THAT(msg, HasSubstr("$.rocks[0].release.height: release height"));
  msg = LoadError([](Json& s) { s["materials"][1]["zone"][2][0] = 1e12; });
  EXPECT_THAT(msg, HasSubstr("$.materials[1].zone[2][0]: coordinate 1e+12 ft"));
  msg = LoadError([](Json& s) { s["surface"]["points"][3][1] = -4e7; });
  EXPECT_THAT(msg, HasSubstr("surface point 4"));
}

TEST(LoadSite, RefusesASelfIntersectingZone) {
  // A figure eight: its signed area is the difference of its lobes.
  const std::string msg = LoadError([](Json& s) {
    s["materials"][1]["zone"] = Json::parse("[[100, -5], [205, 105], [205, 50], [100, 105]]");
  });
  EXPECT_THAT(msg, HasSubstr("$.materials[1].zone: self-intersecting polygon"));
  // The first vertex repeated at the end closes the ring; it is no crossing.
  TempDir dir;
  Json site = BaseSite();
  site["materials"][1]["zone"] =
      Json::parse("[[100, -5], [205, -5], [205, 105], [100, 105], [100, -5]]");
  EXPECT_NO_THROW(LoadSite(WriteSite(dir, site)));
}

// Issue 14: contact_time 1e-12 s never finished.
TEST(LoadSite, RefusesAContactTimeOrARunThatCannotFinish) {
  std::string msg = LoadError([](Json& s) { s["materials"][1]["contact_time"] = 1e-12; });
  EXPECT_THAT(msg, HasSubstr("$.materials[1].contact_time: contact time"));
  EXPECT_THAT(msg, HasSubstr("expected [1e-05, 1] s"));
  msg = LoadError([](Json& s) {
    s["materials"][1]["calibrate"]["contact_time"] = Json::array({1e-9, 0.01});
  });
  EXPECT_THAT(msg, HasSubstr("$.materials[1].calibrate.contact_time"));
  // A legal contact time, but a max_time that makes the run endless.
  msg = LoadError([](Json& s) { s["simulation"]["max_time"] = 1e12; });
  EXPECT_THAT(msg, HasSubstr("$.simulation: the run would take up to"));
  EXPECT_THAT(msg, HasSubstr("steps"));
  msg = LoadError([](Json& s) {
    s["rocks"][0]["count"] = 9'000'000;
    s["rocks"][1]["count"] = 9'000'000;
  });
  EXPECT_THAT(msg, HasSubstr("$.rocks: the rock groups hold 18000000 rocks; expected at most"));
}

TEST(ApplySetting, RefusesAContactTimeThatCannotFinish) {
  TempDir dir;
  Site site = LoadSite(WriteSite(dir, BaseSite()));
  EXPECT_THAT(ErrorOf([&] { ApplySetting("material.rock.contact_time=1e-12", &site); }),
              HasSubstr("expected a contact time in seconds in [1e-05, 1]"));
}

TEST(LoadSite, BuildsTheSceneInSIUnits) {
  TempDir dir;
  const Site site = LoadSite(WriteSite(dir, BaseSite()));
  const core::Scene& s = site.scene;
  EXPECT_EQ(site.units, Units::kUS);
  EXPECT_EQ(s.name, "test slope");
  EXPECT_DOUBLE_EQ(s.grid.spacing, 3.048);
  ASSERT_EQ(s.grid.nx, 21);
  ASSERT_EQ(s.grid.ny, 11);
  EXPECT_NEAR(s.grid.z[s.grid.index(5, 3)], 0.3048 * 75.0, 1e-9);
  // Nodes at x >= 100 ft are talus.
  int talus = 0;
  for (int m : s.grid.material) talus += m == 1;
  EXPECT_EQ(talus, 11 * 11);
  EXPECT_EQ(s.grid.material[s.grid.index(9, 4)], 0);
  EXPECT_EQ(s.grid.material[s.grid.index(10, 4)], 1);

  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].id, "rock");
  EXPECT_DOUBLE_EQ(s.materials[0].roughness_m, 0.3048);
  EXPECT_DOUBLE_EQ(s.materials[0].contact_time_s, 0.005);
  EXPECT_DOUBLE_EQ(s.materials[1].contact_time_s, 0.004);
  EXPECT_FALSE(s.materials[0].restitution.has_value());

  ASSERT_EQ(s.partitions.size(), 2u);
  EXPECT_EQ(s.partitions[0].kind, core::Partition::Kind::kX);
  EXPECT_DOUBLE_EQ(s.partitions[0].value, 45.72);
  EXPECT_EQ(s.partitions[1].kind, core::Partition::Kind::kZ);
  EXPECT_DOUBLE_EQ(s.partitions[1].value, 12.192);

  ASSERT_EQ(s.groups.size(), 2u);
  const core::RockGroup& g = s.groups[0];
  EXPECT_EQ(g.count, 10);
  EXPECT_EQ(g.shape, core::Shape::kSphere);
  EXPECT_DOUBLE_EQ(g.size_min, 0.3048);
  EXPECT_DOUBLE_EQ(g.size_max, 0.9144);
  EXPECT_NEAR(g.unit_weight, 25919.43, 0.01);
  ASSERT_EQ(g.release.zone.size(), 4u);
  EXPECT_DOUBLE_EQ(g.release.zone[1].x(), 9.144);
  EXPECT_DOUBLE_EQ(g.release.height, 0.3048);
  EXPECT_DOUBLE_EQ(g.release.velocity.z(), -0.6096);
  EXPECT_EQ(s.groups[1].shape, core::Shape::kCube);
  EXPECT_DOUBLE_EQ(s.groups[1].size_min, 0.6096);
  EXPECT_DOUBLE_EQ(s.groups[1].size_max, 0.6096);
  EXPECT_TRUE(s.groups[1].release.zone.empty());
  EXPECT_DOUBLE_EQ(s.groups[1].release.point.y(), 15.24);
  EXPECT_EQ(s.total_rocks(), 15);

  EXPECT_EQ(s.options.seed, 7u);
  EXPECT_DOUBLE_EQ(s.options.max_time, 30.0);
  EXPECT_DOUBLE_EQ(s.options.stop_speed, 0.1524);
  EXPECT_EQ(s.options.steps_per_contact, core::SimulationOptions().steps_per_contact);

  ASSERT_EQ(site.calibrate.size(), 3u);
  EXPECT_EQ(site.calibrate[0].material, "talus");
  EXPECT_EQ(site.calibrate[0].name, "hardness");
  EXPECT_EQ(site.calibrate[1].name, "roughness");
  EXPECT_DOUBLE_EQ(site.calibrate[1].lower, 0.1524);
  EXPECT_DOUBLE_EQ(site.calibrate[1].upper, 1.524);
  EXPECT_EQ(site.calibrate[2].name, "contact_time");
  EXPECT_DOUBLE_EQ(site.calibrate[2].upper, 0.01);

  std::string notes;
  for (const std::string& n : site.notes) notes += n + "\n";
  // In the site's units (a "us" file: feet).
  EXPECT_THAT(notes, HasSubstr("grid: 21 x 11 nodes at 10 ft spacing, x 0 to 200 ft, y 0 to 100 "
                               "ft, elevation 0 to 100 ft"));
  EXPECT_THAT(notes, HasSubstr("material talus: 121 nodes"));
  EXPECT_THAT(notes, HasSubstr("holes: 0 of 231 nodes"));
  EXPECT_THAT(notes, HasSubstr("partition BP-2: z = 40 ft"));
  EXPECT_THAT(notes, HasSubstr("rock group 1: 10 sphere, size 1-3 ft, unit weight 165 lbf/ft^3, "
                               "release zone of 4 vertices, area 400 ft^2"));
  EXPECT_THAT(notes, HasSubstr("rock group 2: 5 cube, size 2 ft"));
}

TEST(LoadSite, TheExampleOfDesignMdLoads) {
  TempDir dir;
  const std::string path = dir.Write("site.json", R"({
    "name": "Tutorial slope",
    "units": "us",
    "surface": {
      "resolution": 12,
      "points": [[0, 0, 300], [400, 0, 20], [0, 200, 300], [400, 200, 20]]
    },
    "materials": [
      {"id": "bedrock", "hardness": 0.6, "roughness": 1.0},
      {"id": "talus", "hardness": 0.3, "roughness": 2.0,
       "zone": [[250, 0], [400, 0], [400, 200], [250, 200]],
       "calibrate": {"hardness": [0.1, 0.6], "roughness": [0.3, 6.0]}}
    ],
    "partitions": [{"id": "BP-1", "x": 300}, {"id": "BP-2", "z": 40}],
    "rocks": [
      {"count": 100, "shape": "sphere", "size": [1.0, 4.5], "unit_weight": 165,
       "release": {"zone": [[0, 60], [30, 60], [30, 140], [0, 140]], "height": 0}}
    ],
    "simulation": {"seed": 1, "max_time": 60}
  })");
  const Site site = LoadSite(path);
  const core::HeightGrid& g = site.scene.grid;
  EXPECT_EQ(g.nx, 34);
  EXPECT_EQ(g.ny, 17);
  // The four corners define a plane; every node is on it, none is a hole.
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      EXPECT_NEAR(g.z[g.index(i, j)], 0.3048 * (300 - 0.7 * g.x(i) / 0.3048), 1e-9)
          << i << "," << j;
    }
  }
  EXPECT_EQ(site.calibrate.size(), 2u);
  EXPECT_EQ(site.scene.total_rocks(), 100);
}

// Issue 16: the four corners of a 30-degree plane, 300 m x 40 m, SI, as the
// site file gives them.
Json FourCornerPlane(double friction) {
  Json site = Json::parse(R"({
    "name": "four corners", "units": "si",
    "surface": {"resolution": 1, "sphere_spacing": 1,
                "points": [[0, 0, 200], [300, 0, 26.8], [0, 40, 200], [300, 40, 26.8]]},
    "materials": [{"id": "smooth", "hardness": 0.3, "roughness": 0, "restitution": 0.3,
                   "contact_time": 0.005, "rolling_resistance": 0}],
    "rocks": [{"count": 1, "shape": "sphere", "size": 0.4, "unit_weight": 26,
               "release": {"point": [5, 20], "height": 0}}],
    "simulation": {"max_time": 3}
  })");
  site["materials"][0]["friction"] = friction;
  return site;
}

double FourCornerZ(double x) { return 200.0 - (200.0 - 26.8) * x / 300.0; }

TEST(LoadSite, FourCornerPlaneHasNoHolesInsideTheHullAndExactElevations) {
  TempDir dir;
  const Site site = LoadSite(WriteSite(dir, FourCornerPlane(1.0)));
  const core::HeightGrid& g = site.scene.grid;
  ASSERT_EQ(g.nx, 301);
  ASSERT_EQ(g.ny, 41);
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.z[g.index(i, j)];
      ASSERT_FALSE(std::isnan(z)) << "hole at node " << i << "," << j;
      EXPECT_NEAR(z, FourCornerZ(g.x(i)), 1e-9) << "node " << i << "," << j;
    }
  }
  EXPECT_THAT(site.notes[1],
              HasSubstr("12341 nodes interpolated, 0 holes outside the convex hull"));
}

// The downslope acceleration of the sphere released at rest on the four-corner
// plane, from its speed at 1 s and 2.5 s (a smooth incline's exact motion is
// uniformly accelerated once the first contact has settled).
double FourCornerAcceleration(double friction) {
  TempDir dir;
  Site site = LoadSite(WriteSite(dir, FourCornerPlane(friction)));
  site.scene.options.record.trajectories = 1;
  site.scene.options.record.sample_seconds = 0.5;
  const core::SimulationResult result = core::Simulate(site.scene);
  const auto& tr = result.rocks[0].trajectory;
  auto speed_at = [&](double t) {
    for (const auto& sample : tr)
      if (std::abs(sample.t - t) < 1e-9) return sample.v.norm();
    ADD_FAILURE() << "no trajectory sample at t = " << t;
    return 0.0;
  };
  return (speed_at(2.5) - speed_at(1.0)) / 1.5;
}

TEST(LoadSite, FourCornerPlaneRollsAndSlidesAsTheory) {
  const double theta = std::atan((200.0 - 26.8) / 300.0);  // 30 degrees to 5e-6
  const double g = core::kStandardGravity;
  const double rolling = 5.0 / 7.0 * g * std::sin(theta);
  double a = FourCornerAcceleration(1.0);
  EXPECT_NEAR(a / rolling, 1.0, 0.01) << "rolling: a = " << a << " m/s^2, exact " << rolling;
  const double mu = 0.1;
  const double sliding = g * (std::sin(theta) - mu * std::cos(theta));
  a = FourCornerAcceleration(mu);
  EXPECT_NEAR(a / sliding, 1.0, 0.01) << "sliding: a = " << a << " m/s^2, exact " << sliding;
}

TEST(LoadSite, ReportBarrier) {
  TempDir dir;
  const Site defaults = LoadSite(WriteSite(dir, BaseSite()));
  EXPECT_DOUBLE_EQ(defaults.barrier_height_m, 3.048);
  EXPECT_DOUBLE_EQ(defaults.barrier_energy_j, 500e3);
  Json json = BaseSite();
  json["report"] = Json::parse(R"({"barrier_height": 12, "barrier_energy_kj": 1000})");
  const Site site = LoadSite(WriteSite(dir, json));
  EXPECT_NEAR(site.barrier_height_m, 12 * 0.3048, 1e-12);  // feet in a US site
  EXPECT_DOUBLE_EQ(site.barrier_energy_j, 1e6);
  EXPECT_THAT(LoadError([](Json& j) { j["report"] = Json::parse(R"({"barrier_height": -1})"); }),
              HasSubstr("$.report.barrier_height"));
  EXPECT_THAT(LoadError([](Json& j) { j["report"] = Json::parse(R"({"fence": 3})"); }),
              HasSubstr("unknown key 'fence'"));
}

TEST(LoadSite, MaterialErrors) {
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["hardness"] = 1.5; }),
              HasSubstr("$.materials[0].hardness: expected a number in [0, 1] (found 1.5)"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["roughness"] = -1; }),
              HasSubstr("$.materials[0].roughness: expected a number >= 0 (found -1)"));
  EXPECT_THAT(
      LoadError([](Json& s) { s["materials"][0]["roughness"] = 6; }),
      HasSubstr("$.materials[0].roughness: roughness exceeds half the grid spacing (5 ft)"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["contact_time"] = 0; }),
              HasSubstr("$.materials[1].contact_time: expected a number > 0 (found 0)"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["contact_time"] = 5; }),
              HasSubstr("$.materials[1].contact_time: contact time 5 s is outside the physically "
                        "sensible range; expected [1e-05, 1] s"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["restitution"] = 1.0; }),
              HasSubstr("$.materials[1].restitution: expected a restitution in (0, 1)"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["id"] = "rock"; }),
              HasSubstr("$.materials[1].id: duplicate material id"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["id"] = "bed rock"; }),
              HasSubstr("$.materials[0].id: expected an id of letters, digits"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["colour"] = "red"; }),
              HasSubstr("$.materials[0].colour: unknown key 'colour' (allowed keys: id, hardness"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0].erase("hardness"); }),
              HasSubstr("$.materials[0]: missing required key 'hardness'"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"] = Json::array(); }),
              HasSubstr("$.materials: expected an array of at least 1 entries"));
}

// Issue 13, finding 9: the virtual sphere radius r = (R^2 + (s/2)^2) / (2R)
// grows without bound as R -> 0. A roughness whose spheres would exceed ten
// grid spacings (R < 0.0125 s: 0.125 ft on this 10 ft grid) is refused;
// R = 0 (smooth facets) stays allowed.
TEST(LoadSite, RoughnessNearZeroIsRefused) {
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["roughness"] = 0.01; }),
              HasSubstr("$.materials[0].roughness: roughness 0.01 ft gives virtual spheres of "
                        "radius 1250 ft, more than 10 grid spacings (100 ft); expected 0 "
                        "(smooth) or a roughness in [0.125, 5] ft"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["roughness"] = 0.12; }),
              HasSubstr("expected 0 (smooth) or a roughness in [0.125, 5] ft"));
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["roughness"] = {0.05, 5};
      }),
      HasSubstr("$.materials[1].calibrate.roughness: expected bounds within [0.125, 5] ft"));
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["roughness"] = {0, 5};
      }),
      HasSubstr("$.materials[1].calibrate.roughness: expected bounds within [0.125, 5] ft"));
  for (double ok : {0.0, 0.13}) {
    TempDir dir;
    Json json = BaseSite();
    json["materials"][0]["roughness"] = ok;
    const Site site = LoadSite(WriteSite(dir, json));
    EXPECT_DOUBLE_EQ(site.scene.materials[0].roughness_m, ok * 0.3048);
  }
  TempDir dir;
  Site site = LoadSite(WriteSite(dir, BaseSite()));
  EXPECT_THAT(ErrorOf([&] { ApplySetting("material.rock.roughness=0.01", &site); }),
              HasSubstr("--set material.rock.roughness=0.01: expected 0 (smooth) or a roughness "
                        "in [0.125, 5] ft"));
  ApplySetting("material.rock.roughness=0", &site);
  EXPECT_EQ(site.scene.materials[0].roughness_m, 0.0);
  ApplySetting("material.rock.roughness=0.13", &site);
  EXPECT_DOUBLE_EQ(site.scene.materials[0].roughness_m, 0.13 * 0.3048);
}

TEST(LoadSite, MaterialClassDefaultsToTheId) {
  TempDir dir;
  Json json = BaseSite();
  json["materials"][1]["class"] = "scree";
  const Site site = LoadSite(WriteSite(dir, json));
  EXPECT_EQ(site.material_classes, (std::vector<std::string>{"rock", "scree"}));
  ASSERT_EQ(site.calibrate.size(), 3u);
  for (const ParameterBound& b : site.calibrate) {
    EXPECT_EQ(b.material, "talus");
    EXPECT_EQ(b.material_class, "scree") << b.name;
  }
  std::string notes;
  for (const std::string& n : site.notes) notes += n + "\n";
  EXPECT_THAT(notes, HasSubstr("material talus: 121 nodes, class scree,"));
  EXPECT_THAT(notes, HasSubstr("material rock: 110 nodes, class rock,"));
}

TEST(LoadSite, MaterialClassErrors) {
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["class"] = ""; }),
              HasSubstr("$.materials[1].class: expected a class name of letters, digits, '_' "
                        "and '-' (not empty) (found \"\")"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["class"] = "hard rock"; }),
              HasSubstr("$.materials[0].class: expected a class name"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["class"] = 3; }),
              HasSubstr("$.materials[0].class: expected a string (found 3)"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["class"] = Json(nullptr); }),
              HasSubstr("$.materials[0].class: expected a string (found null)"));
}

TEST(LoadSite, ZoneErrors) {
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][0]["zone"] = s["materials"][1]["zone"]; }),
              HasSubstr("$.materials[0].zone: the first material covers everything no zone "
                        "claims and takes no zone"));
  EXPECT_THAT(
      LoadError([](Json& s) { s["materials"][1]["zone"] = Json::parse("[[0, 0], [1, 1]]"); }),
      HasSubstr("$.materials[1].zone: expected a polygon: an array of at least 3 [x, y] "
                "vertices"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["zone"] = Json::parse("[[0, 0], [1, 1], [2, 2]]");
              }),
              HasSubstr("$.materials[1].zone: degenerate polygon"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["zone"] = Json::parse("[[0, 0], [1, 1], [\"a\", 2]]");
              }),
              HasSubstr("$.materials[1].zone[2][0]: expected a number"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["zone"] = Json::parse("[[300, 0], [400, 0], [400, 50]]");
              }),
              HasSubstr("$.materials[1].zone: the zone contains no grid node (the terrain spans x "
                        "0 to 200, y 0 to 100)"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["zone"] =
                    Json::parse("[[-10, -10], [210, -10], [210, 110], [-10, 110]]");
              }),
              HasSubstr("$.materials[0]: material 'rock' covers no terrain node"));
}

TEST(LoadSite, CalibrateErrors) {
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["hardness"] = {0.6, 0.1};
      }),
      HasSubstr("$.materials[1].calibrate.hardness: expected [lower, upper] with lower < upper"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["calibrate"]["hardness"] = {0.2, 1.2};
              }),
              HasSubstr("$.materials[1].calibrate.hardness: expected bounds within [0, 1]"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["calibrate"]["hardness"] = {0.4, 0.6};
              }),
              HasSubstr("the material's hardness 0.3 is outside its calibrate bounds"));
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["roughness"] = {0.5, 8};
      }),
      HasSubstr("$.materials[1].calibrate.roughness: expected bounds within [0.125, 5] ft"));
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["contact_time"] = {0, 0.01};
      }),
      HasSubstr("$.materials[1].calibrate.contact_time: expected bounds within [1e-05, 1] s"));
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["colour"] = {0, 1};
      }),
      HasSubstr("$.materials[1].calibrate.colour: unknown key 'colour' (allowed keys: "
                "hardness, roughness, contact_time, rolling_resistance, friction, vegetation)"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["restitution"] = 0.4;
                s["materials"][1]["friction"] = 0.6;
              }),
              HasSubstr("$.materials[1].calibrate.hardness: hardness has no effect"));
}

// Undergrowth in the file's stress unit: kPa in SI files, lbf/ft^2 in US ones.
TEST(LoadSite, VegetationInTheFilesStressUnit) {
  TempDir dir;
  Json us = BaseSite();
  us["materials"][1]["vegetation"] = 40;
  us["materials"][1]["calibrate"]["vegetation"] = {0, 60};
  const Site site = LoadSite(WriteSite(dir, us));
  EXPECT_NEAR(site.scene.materials[1].vegetation_pa, 40 * 47.88025898, 1e-6);
  EXPECT_EQ(site.scene.materials[0].vegetation_pa, 0.0);
  const auto bound = std::find_if(site.calibrate.begin(), site.calibrate.end(),
                                  [](const ParameterBound& b) { return b.name == "vegetation"; });
  ASSERT_NE(bound, site.calibrate.end());
  EXPECT_NEAR(bound->upper, 60 * 47.88025898, 1e-6);
  // Issue 55: the bounds are listed in the file's units, each with its unit.
  EXPECT_THAT(site.notes.back(),
              HasSubstr("calibrate: talus.hardness [0.1, 0.6], talus.roughness [0.5, 5] ft, "
                        "talus.contact_time [0.002, 0.01] s, talus.vegetation [0, 60] lbf/ft^2"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["vegetation"] = -1; }),
              HasSubstr("$.materials[1].vegetation: expected a number >= 0"));
  EXPECT_THAT(LoadError([](Json& s) { s["materials"][1]["vegetation"] = 5000; }),
              HasSubstr("$.materials[1].vegetation: vegetation resistance 5000 lbf/ft^2 is outside "
                        "the physically sensible range; expected [0, 2088.543423] lbf/ft^2"));
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["materials"][1]["calibrate"]["vegetation"] = {0, 3000};
      }),
      HasSubstr("$.materials[1].calibrate.vegetation: expected bounds within [0, 2088.543423] "
                "lbf/ft^2"));
}

TEST(LoadSite, PartitionErrors) {
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][0]["z"] = 40; }),
              HasSubstr("$.partitions[0]: expected exactly one of 'x' or 'z'"));
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][0].erase("x"); }),
              HasSubstr("$.partitions[0]: expected exactly one of 'x' or 'z'"));
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][0]["x"] = 500; }),
              HasSubstr("$.partitions[0].x: the X partition lies off the terrain; expected x in "
                        "[0, 200] (found 500)"));
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][1]["z"] = 150; }),
              HasSubstr("$.partitions[1].z: the Z partition is outside the terrain's elevations; "
                        "expected z in [0, 100]"));
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][1]["id"] = "BP-1"; }),
              HasSubstr("$.partitions[1].id: duplicate partition id"));
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][1]["x"] = "100"; }),
              HasSubstr("$.partitions[1]: expected exactly one of 'x' or 'z'"));
  EXPECT_THAT(LoadError([](Json& s) { s["partitions"][0]["x"] = "100"; }),
              HasSubstr("$.partitions[0].x: expected a number (found \"100\")"));
}

// Barriers drawn in plan: lines appended to the partitions, in SI (a US
// site: feet, kJ).
TEST(LoadSite, BarriersAreLinesInPlanAfterThePartitions) {
  TempDir dir;
  Json json = BaseSite();
  json["barriers"] = Json::parse(R"([
    {"id": "net-1", "line": [[120, 0], [130, 50], [120, 100]], "height": 10, "energy_kj": 500},
    {"id": "dam", "line": [[170, 10], [170, 90]], "height": 20, "energy_kj": 5000, "stops": true}
  ])");
  const Site site = LoadSite(WriteSite(dir, json));
  const std::vector<core::Partition>& parts = site.scene.partitions;
  ASSERT_EQ(parts.size(), 4u);
  EXPECT_EQ(parts[1].kind, core::Partition::Kind::kZ);
  const core::Partition& net = parts[2];
  EXPECT_EQ(net.id, "net-1");
  EXPECT_EQ(net.kind, core::Partition::Kind::kLine);
  ASSERT_EQ(net.line.size(), 3u);
  EXPECT_NEAR(net.line[1].x(), 130 * 0.3048, 1e-12);
  EXPECT_NEAR(net.line[1].y(), 50 * 0.3048, 1e-12);
  EXPECT_NEAR(net.height, 10 * 0.3048, 1e-12);
  EXPECT_DOUBLE_EQ(net.capacity, 500e3);
  EXPECT_FALSE(net.stops);
  EXPECT_EQ(parts[3].id, "dam");
  EXPECT_TRUE(parts[3].stops);
  EXPECT_DOUBLE_EQ(parts[3].capacity, 5e6);
}

// Bad barriers name their JSON path, value and what was expected.
TEST(LoadSite, BarrierErrors) {
  auto with = [](const char* barrier) {
    return [barrier](Json& s) { s["barriers"] = Json::array({Json::parse(barrier)}); };
  };
  EXPECT_THAT(LoadError(with(R"({"id": "a", "line": [[120, 0]], "height": 10, "energy_kj": 500})")),
              HasSubstr("$.barriers[0].line: expected a line: an array of at least 2 [x, y] "
                        "vertices"));
  EXPECT_THAT(
      LoadError(with(R"({"id": "a", "line": [[120, 0], [120]], "height": 10, "energy_kj": 500})")),
      HasSubstr("$.barriers[0].line[1]: expected an array of 2 numbers"));
  {  // a coordinate beyond any double, written in the file's text
    TempDir dir;
    Json json = BaseSite();
    with(R"({"id": "a", "line": [[120, 0], [123456, 5]], "height": 10, "energy_kj": 500})")(json);
    std::string text = json.dump(2);
    text.replace(text.find("123456"), 6, "1e999");
    const std::string path = dir.Write("site.json", text);
    EXPECT_THAT(ErrorOf([&] { LoadSite(path); }), HasSubstr("$.barriers[0].line[1][0]: "));
  }
  EXPECT_THAT(
      LoadError(with(R"({"id": "a", "line": [[120, 0], [120, 90]], "height": -3, "energy_kj": 500})")),
      HasSubstr("$.barriers[0].height: expected a number > 0 (found -3)"));
  EXPECT_THAT(
      LoadError(with(R"({"id": "a", "line": [[120, 0], [120, 90]], "height": 3, "energy_kj": 0})")),
      HasSubstr("$.barriers[0].energy_kj: expected a number > 0 (found 0)"));
  EXPECT_THAT(LoadError(with(R"({"id": "a", "line": [[120, 0], [120, 90]], "height": 3})")),
              HasSubstr("$.barriers[0]: missing required key 'energy_kj'"));
  EXPECT_THAT(LoadError(with(R"({"id": "a", "line": [[120, 0], [120, 90]], "height": 3,
                                  "energy_kj": 1, "stops": 1})")),
              HasSubstr("$.barriers[0].stops: expected true or false"));
  EXPECT_THAT(LoadError(with(R"({"id": "BP-1", "line": [[120, 0], [120, 90]], "height": 3,
                                  "energy_kj": 1})")),
              HasSubstr("$.barriers[0].id: the id 'BP-1' is also a partition's"));
  EXPECT_THAT(LoadError(with(R"({"id": "a", "line": [[120, 5], [120, 5]], "height": 3,
                                  "energy_kj": 1})")),
              HasSubstr("$.barriers[0].line: every vertex is the same point"));
  EXPECT_THAT(LoadError(with(R"({"id": "a", "line": [[300, 0], [320, 90]], "height": 3,
                                  "energy_kj": 1})")),
              HasSubstr("$.barriers[0].line: the line (x 300 to 320, y 0 to 90) lies off the "
                        "terrain; expected it over x 0 to 200, y 0 to 100"));
  EXPECT_THAT(LoadError(with(R"({"id": "a", "line": [[120, 0], [120, 90]], "height": 3,
                                  "energy_kj": 1, "capacity": 2})")),
              HasSubstr("$.barriers[0]"));
}

TEST(LoadSite, RockGroupErrors) {
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["count"] = 0; }),
              HasSubstr("$.rocks[0].count: expected a whole number in [1, 10000000] (found 0)"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["count"] = 2.5; }),
              HasSubstr("$.rocks[0].count: expected a whole number"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["size"] = {3, 1};
              }),
              HasSubstr("$.rocks[0].size: expected [min, max] with min <= max (found [3,1])"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["size"] = {0, 1};
              }),
              HasSubstr("$.rocks[0].size: expected [min, max] with 0 < min <= max"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][1]["size"] = -2; }),
              HasSubstr("$.rocks[1].size: expected a number > 0"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][1]["size"] = "big"; }),
              HasSubstr("$.rocks[1].size: expected a size > 0 or a range [min, max]"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["shape"] = "boulder"; }),
              HasSubstr("$.rocks[0].shape: unknown shape (allowed: sphere, cylinder, disc, "
                        "tetrahedron, cube, box) (found \"boulder\")"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["unit_weight"] = 0; }),
              HasSubstr("$.rocks[0].unit_weight: expected a number > 0"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"] = Json::array(); }),
              HasSubstr("$.rocks: expected an array of at least 1 entries"));
}

TEST(LoadSite, ReleaseErrors) {
  EXPECT_THAT(
      LoadError([](Json& s) {
        s["rocks"][0]["release"]["zone"] = Json::parse("[[190, 40], [250, 40], [250, 60]]");
      }),
      HasSubstr("$.rocks[0].release.zone: release zone point (250, 40) is off the terrain "
                "(outside the grid or over a hole; the terrain spans x 0 to 200, y 0 to 100)"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][1]["release"]["point"] = {20, -1};
              }),
              HasSubstr("$.rocks[1].release.point: release point is off the terrain"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][1]["release"]["zone"] = s["rocks"][0]["release"]["zone"];
              }),
              HasSubstr("$.rocks[1].release: expected exactly one of 'zone' (plan polygon), "
                        "'zone_file' (a polygon of a GIS file) or 'point' ([x, y])"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][1]["release"].erase("point"); }),
              HasSubstr("$.rocks[1].release: expected exactly one of 'zone'"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["release"]["height"] = -1; }),
              HasSubstr("$.rocks[0].release.height: expected a number >= 0"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["release"]["velocity"] = {1, 2};
              }),
              HasSubstr("$.rocks[0].release.velocity: expected an array of 3 numbers"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["release"]["zone"] = Json::parse("[[10, 40], [30, 40]]");
              }),
              HasSubstr("$.rocks[0].release.zone: expected a polygon"));
}

TEST(LoadSite, ReleaseOverAHoleIsAnError) {
  TempDir dir;
  // 5 x 5 nodes of 10 m; the node (20, 20) is NODATA.
  dir.Write("g.asc",
            "ncols 5\nnrows 5\nxllcenter 0\nyllcenter 0\ncellsize 10\nNODATA_value -9999\n"
            "5 5 5 5 5\n5 5 5 5 5\n5 5 -9999 5 5\n5 5 5 5 5\n5 5 5 5 5\n");
  Json site = Json::parse(R"({
    "name": "holes", "units": "si", "surface": {"grid_file": "g.asc", "sphere_spacing": 10},
    "materials": [{"id": "m", "hardness": 0.5, "roughness": 0}],
    "rocks": [{"count": 1, "shape": "sphere", "size": 1, "unit_weight": 26,
               "release": {"point": [25, 25]}}]})");
  const std::string path = WriteSite(dir, site);
  EXPECT_THAT(ErrorOf([&] { LoadSite(path); }),
              HasSubstr(path + ": $.rocks[0].release.point: release point is off the terrain "
                               "(outside the grid or over a hole"));
  site["rocks"][0]["release"] = Json::parse(R"({"zone": [[5, 5], [35, 5], [35, 15], [5, 15]]})");
  WriteSite(dir, site);
  EXPECT_THAT(ErrorOf([&] { LoadSite(path); }),
              HasSubstr("$.rocks[0].release.zone: release zone point"));
  site["rocks"][0]["release"] = Json::parse(R"({"point": [35, 35]})");
  WriteSite(dir, site);
  const Site ok = LoadSite(path);
  EXPECT_DOUBLE_EQ(ok.scene.grid.spacing, 10.0);  // the grid's own cell size
  EXPECT_TRUE(ok.scene.partitions.empty());
}

TEST(LoadSite, TopLevelErrors) {
  EXPECT_THAT(LoadError([](Json& s) { s["units"] = "metric"; }),
              HasSubstr("$.units: unknown units (allowed: us, si) (found \"metric\")"));
  EXPECT_THAT(LoadError([](Json& s) { s.erase("units"); }),
              HasSubstr("$: missing required key 'units'"));
  EXPECT_THAT(LoadError([](Json& s) { s["colour"] = 1; }),
              HasSubstr("$.colour: unknown key 'colour' (allowed keys: name, description, units"));
  EXPECT_THAT(LoadError([](Json& s) { s.erase("rocks"); }),
              HasSubstr("$: missing required key 'rocks'"));
  EXPECT_THAT(LoadError([](Json& s) { s["name"] = 3; }), HasSubstr("$.name: expected a string"));
  EXPECT_THAT(LoadError([](Json& s) { s["simulation"]["max_time"] = -1; }),
              HasSubstr("$.simulation.max_time: expected a number > 0"));
  EXPECT_THAT(LoadError([](Json& s) { s["simulation"]["stop_duration"] = 40; }),
              HasSubstr("$.simulation.stop_duration: expected a number of seconds below max_time "
                        "(30 s) (found 40)"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["simulation"].erase("stop_duration");
                s["simulation"]["max_time"] = 0.5;
              }),
              HasSubstr("$.simulation.max_time: expected a number of seconds above stop_duration "
                        "(1 s, the default) (found 0.5)"));
  EXPECT_THAT(LoadError([](Json& s) { s["simulation"]["steps"] = 40; }),
              HasSubstr("$.simulation.steps: unknown key 'steps'"));
  EXPECT_THAT(LoadError([](Json& s) { s["simulation"]["seed"] = -1; }),
              HasSubstr("$.simulation.seed: expected a whole number"));
  EXPECT_THAT(LoadError([](Json& s) { s["simulation"]["gentle_safety"] = 0; }),
              HasSubstr("$.simulation.gentle_safety: expected a number in (0, 1]"));
  EXPECT_THAT(LoadError([](Json& s) { s["simulation"]["rest_window"] = -0.1; }),
              HasSubstr("$.simulation.rest_window: expected a number >= 0"));
}

TEST(LoadSite, RelativePathsFromTheSiteFolder) {
  TempDir dir;
  dir.Write("site/data/p.csv", "x y z\n0 0 10\n20 0 0\n0 20 10\n20 20 0\n");
  Json site = Json::parse(R"({
    "name": "relative", "units": "si", "surface": {"resolution": 5, "sphere_spacing": 5, "points_file": "data/p.csv"},
    "materials": [{"id": "m", "hardness": 0.5, "roughness": 0.5}],
    "rocks": [{"count": 3, "shape": "disc", "size": [0.5, 1], "unit_weight": 26,
               "release": {"point": [2, 10]}}],
    "simulation": {"seed": 2, "max_time": 20, "stop_speed": 0.2, "stop_duration": 2,
                   "steps_per_contact": 80, "safety": 0.5, "gentle_safety": 0.8,
                   "rest_window": 0.25, "exact_flight": false, "threads": 1}})");
  const Site s = LoadSite(dir.Write("site/site.json", site.dump()));
  EXPECT_EQ(s.scene.grid.nx, 5);
  EXPECT_NEAR(s.scene.grid.z[s.scene.grid.index(2, 3)], 5.0, 1e-9);
  EXPECT_EQ(s.scene.options.steps_per_contact, 80);
  EXPECT_DOUBLE_EQ(s.scene.options.safety, 0.5);
  EXPECT_DOUBLE_EQ(s.scene.options.gentle_safety, 0.8);
  EXPECT_DOUBLE_EQ(s.scene.options.rest_window, 0.25);
  EXPECT_FALSE(s.scene.options.exact_flight);
  EXPECT_EQ(s.scene.options.threads, 1);
  EXPECT_DOUBLE_EQ(s.scene.options.stop_speed, 0.2);
  EXPECT_TRUE(s.calibrate.empty());
}

TEST(ApplySetting, OverridesInSiteUnits) {
  TempDir dir;
  Site site = LoadSite(WriteSite(dir, BaseSite()));
  ApplySetting("material.talus.hardness=0.45", &site);
  ApplySetting("material.talus.roughness=3", &site);
  ApplySetting("material.rock.contact_time=0.01", &site);
  ApplySetting("material.talus.vegetation=20", &site);  // lbf/ft^2
  EXPECT_NEAR(site.scene.materials[1].vegetation_pa, 957.6051796, 1e-6);
  EXPECT_DOUBLE_EQ(site.scene.materials[1].hardness, 0.45);
  EXPECT_DOUBLE_EQ(site.scene.materials[1].roughness_m, 0.9144);
  EXPECT_DOUBLE_EQ(site.scene.materials[0].contact_time_s, 0.01);
}

TEST(ApplySetting, Errors) {
  TempDir dir;
  Site site = LoadSite(WriteSite(dir, BaseSite()));
  auto error = [&](const std::string& kv) { return ErrorOf([&] { ApplySetting(kv, &site); }); };
  EXPECT_THAT(error("material.granite.hardness=0.4"),
              HasSubstr("--set material.granite.hardness=0.4: unknown material 'granite' "
                        "(materials: rock, talus)"));
  EXPECT_THAT(error("material.rock.colour=1"),
              HasSubstr("unknown field 'colour' (allowed: hardness, roughness, contact_time, "
                        "rolling_resistance, friction, vegetation)"));
  EXPECT_THAT(error("material.rock.vegetation=3000"),
              HasSubstr("expected a vegetation resistance in [0, 2088.543423] lbf/ft^2"));
  EXPECT_THAT(error("material.rock.hardness=high"), HasSubstr("'high' is not a number"));
  EXPECT_THAT(error("material.rock.hardness="), HasSubstr("'' is not a number"));
  EXPECT_THAT(error("material.rock.hardness=1.5"), HasSubstr("expected a hardness in [0, 1]"));
  EXPECT_THAT(error("material.rock.roughness=6"),
              HasSubstr("expected 0 (smooth) or a roughness in [0.125, 5] ft"));
  EXPECT_THAT(error("material.rock.contact_time=0"), HasSubstr("expected a contact time"));
  EXPECT_THAT(error("rock.hardness=0.3"), HasSubstr("expected material.<id>.<field>=VALUE"));
  EXPECT_THAT(error("material.rock.hardness"), HasSubstr("expected material.<id>.<field>=VALUE"));
  EXPECT_THAT(error("material.hardness=0.3"), HasSubstr("expected material.<id>.<field>=VALUE"));
  EXPECT_DOUBLE_EQ(site.scene.materials[0].hardness, 0.6);  // unchanged by the failures
}

}  // namespace site_test
}  // namespace rockcal::sites

namespace rockcal::sites {
namespace site_test {

// A block inventory: one rock per block (or `count` in turn), with the
// blocks' own masses and sides.
TEST(LoadSite, RocksFromABlockInventory) {
  TempDir dir;
  dir.Write("blocks.csv", "# three blocks\nmass,L1,L2,L3\n100,1,2,3\n200, 2, 1, 1\n\n300 3 2 1\n");
  Json json = BaseSite();
  json["rocks"] = Json::parse(
      R"([{"inventory": "blocks.csv", "release": {"point": [20, 50]}},
          {"inventory": "blocks.csv", "count": 7, "release": {"point": [20, 50]}}])");
  const Site site = LoadSite(WriteSite(dir, json));
  const core::RockGroup& g = site.scene.groups[0];
  ASSERT_EQ(g.inventory.size(), 3u);
  EXPECT_EQ(g.count, 3);
  EXPECT_EQ(site.scene.groups[1].count, 7);
  EXPECT_NEAR(g.inventory[0].mass, 100 * 0.45359237, 1e-9);  // lb in a US site
  EXPECT_NEAR(g.inventory[0].sides.x(), 3 * 0.3048, 1e-12);  // sorted, in m
  EXPECT_NEAR(g.inventory[0].sides.z(), 1 * 0.3048, 1e-12);
  EXPECT_EQ(g.inventory[2].shape, core::Shape::kBox);
  for (int k = 0; k < 7; ++k) {
    const core::RockBody b = core::GroupRockBody(site.scene.groups[1], k, 0.5, 9.81);
    EXPECT_NEAR(b.mass, g.inventory[static_cast<std::size_t>(k % 3)].mass, 1e-9);
  }
}

TEST(LoadSite, InventoryErrorsNameFileAndLine) {
  auto error = [](const std::string& csv) {
    TempDir dir;
    const std::string file = dir.Write("blocks.csv", csv);
    Json json = BaseSite();
    json["rocks"] = Json::parse(R"([{"inventory": "blocks.csv", "release": {"point": [20, 50]}}])");
    const std::string path = WriteSite(dir, json);
    const std::string msg = ErrorOf([&] { LoadSite(path); });
    EXPECT_THAT(msg, HasSubstr(file + ":")) << "the message must name the inventory file";
    return msg;
  };
  EXPECT_THAT(error("mass,L1,L2\n1,1,1\n"), HasSubstr(":1: missing column 'L3'"));
  EXPECT_THAT(error("mass,L1,L2,L3,colour\n"), HasSubstr(":1: unknown column 'colour'"));
  EXPECT_THAT(error("mass,L1,L2,L3\n1,1,1,1\n2,x,1,1\n"), HasSubstr(":3:"));
  EXPECT_THAT(error("mass,L1,L2,L3\n1,1,1\n"), HasSubstr(":2: 3 fields; expected 4"));
  EXPECT_THAT(error("mass,L1,L2,L3\n-1,1,1,1\n"), HasSubstr(":2: mass -1: expected a mass > 0"));
  EXPECT_THAT(error("mass,L1,L2,L3\n1,1,0,1\n"), HasSubstr(":2: L2 0: expected a side > 0"));
  EXPECT_THAT(error("mass,L1,L2,L3,shape\n1,1,1,1,blob\n"), HasSubstr(":2: shape 'blob'"));
  EXPECT_THAT(error("mass,L1,L2,L3\n"), HasSubstr("no blocks after the header"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0] = Json::parse(
                    R"({"inventory": "none.csv", "shape": "box", "release": {"point": [20, 50]}})");
              }),
              HasSubstr("$.rocks[0].shape: unknown key 'shape'"));
}

// A surveyed drop: the rock's lowest point at an absolute elevation, never
// below the ground; a velocity spread; a box of given proportions.
TEST(LoadSite, ReleaseAtAnElevationWithAVelocitySpread) {
  TempDir dir;
  Json json = BaseSite();
  json["rocks"][0]["release"].erase("height");
  json["rocks"][0]["release"]["elevation"] = 100;
  json["rocks"][0]["release"]["velocity_spread"] = {0.5, 0.5, 0};
  json["rocks"][1]["shape"] = "box";
  json["rocks"][1]["box"] = {3, 2, 1};
  const Site site = LoadSite(WriteSite(dir, json));
  ASSERT_TRUE(site.scene.groups[0].release.elevation.has_value());
  EXPECT_NEAR(*site.scene.groups[0].release.elevation, 100 * 0.3048, 1e-12);
  EXPECT_NEAR(site.scene.groups[0].release.velocity_spread.x(), 0.5 * 0.3048, 1e-12);
  EXPECT_EQ(site.scene.groups[1].shape, core::Shape::kBox);
  EXPECT_NEAR(site.scene.groups[1].box.x(), 3.0, 0.0);

  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["release"]["elevation"] = 90; }),
              HasSubstr("$.rocks[0].release: expected 'height' (above the ground) or 'elevation'"));
  // The zone's ground reaches 80 ft (x = 20 ft on the 100 ft to 0 plane).
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["release"].erase("height");
                s["rocks"][0]["release"]["elevation"] = 50;
              }),
              HasSubstr("$.rocks[0].release.elevation: the ground of the release reaches 95 ft; "
                        "expected a drop elevation at or above it"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["release"]["velocity_spread"] = {-1, 0, 0};
              }),
              HasSubstr("$.rocks[0].release.velocity_spread: expected three spreads >= 0"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][1]["box"] = {3, 2, 1};
              }),
              HasSubstr("$.rocks[1].box: 'box' goes with \"shape\": \"box\" only"));
}

// Issue 38: a tracked release known within an error, group ids, and the
// warning for groups whose rocks are identical copies.
TEST(LoadSite, ReleasePositionSpreadGroupIdsAndIdenticalCopies) {
  TempDir dir;
  Json json = BaseSite();
  json["rocks"][1]["id"] = "v004";
  json["rocks"][1]["release"]["position_spread"] = 2;  // ft
  Site site = LoadSite(WriteSite(dir, json));
  const core::Release& rel = site.scene.groups[1].release;
  EXPECT_EQ(site.scene.groups[1].id, "v004");
  ASSERT_EQ(rel.zone.size(), 24u);
  for (const Eigen::Vector2d& v : rel.zone)
    EXPECT_NEAR((v - rel.point).norm(), 2 * 0.3048, 1e-12) << v.transpose();
  // The disc is centred on the point (the runout's origin stays there).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& v : rel.zone) mean += v / 24.0;
  EXPECT_NEAR((mean - rel.point).norm(), 0.0, 1e-12);
  // Cubes at a point without spread: random orientations, so not copies; a
  // sphere of one size at a point without spread is.
  EXPECT_TRUE(IdenticalCopyWarnings(site.scene).empty());
  json["rocks"][1]["release"].erase("position_spread");
  json["rocks"][1]["shape"] = "sphere";
  site = LoadSite(WriteSite(dir, json));
  const std::vector<std::string> warnings = IdenticalCopyWarnings(site.scene);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("rock group 2 'v004': its 5 rocks are identical copies"));
  json["rocks"][1]["release"]["velocity_spread"] = {0.1, 0.1, 0};
  EXPECT_TRUE(IdenticalCopyWarnings(LoadSite(WriteSite(dir, json)).scene).empty());

  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][0]["release"]["position_spread"] = 1; }),
              HasSubstr("$.rocks[0].release.position_spread: goes with a release 'point' only"));
  EXPECT_THAT(LoadError([](Json& s) { s["rocks"][1]["release"]["position_spread"] = 30; }),
              HasSubstr("off the terrain"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["rocks"][0]["id"] = "a";
                s["rocks"][1]["id"] = "a";
              }),
              HasSubstr("$.rocks[1].id: group id 'a' is also rocks[0]'s"));
}

TEST(LoadSite, RollingResistanceIsCalibrated) {
  TempDir dir;
  Json json = BaseSite();
  json["materials"][1]["calibrate"]["rolling_resistance"] = {0.0, 0.6};
  const Site site = LoadSite(WriteSite(dir, json));
  EXPECT_EQ(site.calibrate.back().name, "rolling_resistance");
  // The hardness model's value (0.15 - 0.13 H = 0.111 at H = 0.3) must lie
  // within the bounds.
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["calibrate"]["rolling_resistance"] = {0.2, 0.6};
              }),
              HasSubstr("$.materials[1].calibrate.rolling_resistance: the material's "
                        "rolling_resistance 0.111 is outside its calibrate bounds"));
}

TEST(LoadSite, FrictionIsCalibratedAndSet) {
  TempDir dir;
  Json json = BaseSite();
  json["materials"][1]["calibrate"]["friction"] = {0.35, 0.9};
  Site site = LoadSite(WriteSite(dir, json));
  EXPECT_EQ(site.calibrate.back().name, "friction");
  EXPECT_DOUBLE_EQ(site.calibrate.back().lower, 0.35);
  // Without an explicit friction, the bounds hold the hardness model's
  // (0.9 - 0.5 H = 0.75 at H = 0.3).
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["calibrate"]["friction"] = {0.35, 0.7};
              }),
              HasSubstr("$.materials[1].calibrate.friction: the material's friction 0.75 is "
                        "outside its calibrate bounds"));
  EXPECT_THAT(LoadError([](Json& s) {
                s["materials"][1]["calibrate"]["friction"] = {0.5, 11};
              }),
              HasSubstr("$.materials[1].calibrate.friction: expected bounds within [0, 10]"));
  ApplySetting("material." + site.scene.materials[1].id + ".friction=0.42", &site);
  EXPECT_DOUBLE_EQ(core::DeriveContactLaw(site.scene.materials[1]).friction, 0.42);
  EXPECT_THROW(ApplySetting("material." + site.scene.materials[1].id + ".friction=-1", &site),
               InputError);
}

}  // namespace site_test
}  // namespace rockcal::sites
