// The roughness test of issue 13 (finding 1) is a Monte Carlo experiment:
// 240 rocks, run in the optimised build with the other heavy tests.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/sites/site.h"
#include "rockcal/sites/surface.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

using ::testing::HasSubstr;
using testing::TempDir;
using Json = nlohmann::json;

// Issue 13, finding 1: one slope (35 degrees, 40 m, onto a flat apron), its
// elevations given every 10 m, gridded at `resolution` [m]; hardness 0.4,
// roughness 0.3 m; 120 spheres of 0.5-1.0 m and a partition 60 m down.
Json SlopeAtResolution(double resolution) {
  const double tan35 = std::tan(35.0 * std::acos(-1.0) / 180.0);
  Json points = Json::array();
  for (int y = 0; y <= 40; y += 10)
    for (int x = 0; x <= 120; x += 10) points.push_back({x, y, x < 40 ? (40 - x) * tan35 : 0.0});
  Json site = Json::parse(R"({
    "name": "slope and apron", "units": "si",
    "materials": [{"id": "ground", "hardness": 0.4, "roughness": 0.3}],
    "partitions": [{"id": "P60", "x": 60}],
    "rocks": [{"count": 120, "shape": "sphere", "size": [0.5, 1.0], "unit_weight": 26,
               "release": {"zone": [[3, 15], [6, 15], [6, 25], [3, 25]], "height": 0.5}}],
    "simulation": {"seed": 3, "max_time": 40}
  })");
  site["surface"] = {{"resolution", resolution}, {"points", points}};
  return site;
}

struct Distribution {
  std::vector<double> runout, height;  // stop x of stopped rocks; height at P60 of crossers
};

Distribution SimulateSlope(const Json& site_json) {
  TempDir dir;
  const Site site = LoadSite(dir.Write("site.json", site_json.dump(2)));
  const core::SimulationResult r = core::Simulate(site.scene);
  Distribution d;
  for (const core::RockRecord& rock : r.rocks) {
    if (rock.outcome == core::Outcome::kStopped) d.runout.push_back(rock.stop.x());
    if (rock.crossings.at(0).crossed) d.height.push_back(rock.crossings[0].height);
  }
  return d;
}

// Medians of two samples agree within two combined standard errors (the
// median's standard error from the sample's interquartile range,
// 1.2533 sigma / sqrt(n) with sigma = IQR / 1.349).
void ExpectSameMedian(std::vector<double> a, std::vector<double> b, const char* what) {
  ASSERT_GE(a.size(), 30u) << what;
  ASSERT_GE(b.size(), 30u) << what;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  auto se = [](const std::vector<double>& s) {
    const double iqr = core::Quantile(s, 0.75) - core::Quantile(s, 0.25);
    return 1.2533 * iqr / 1.349 / std::sqrt(static_cast<double>(s.size()));
  };
  const double ma = core::Quantile(a, 0.5), mb = core::Quantile(b, 0.5);
  EXPECT_LE(std::abs(ma - mb), 2.0 * std::hypot(se(a), se(b)))
      << what << ": median " << ma << " (n " << a.size() << ") against " << mb << " (n " << b.size()
      << ")";
}

TEST(LoadSite, RoughnessMeansOneGroundAtAnyResolution) {
  // The virtual spheres keep their own spacing (12 ft by default for
  // scattered points) whatever the resolution the data are gridded at: the same slope at 1 m and 2 m
  // makes the same sphere surface ...
  TempDir dir;
  const Site fine = LoadSite(dir.Write("site.json", SlopeAtResolution(1.0).dump(2)));
  const Site coarse = LoadSite(dir.Write("site.json", SlopeAtResolution(2.0).dump(2)));
  const core::HeightGrid& f = fine.scene.grid;
  const core::HeightGrid& c = coarse.scene.grid;
  EXPECT_DOUBLE_EQ(f.spacing, kDefaultSphereSpacingM);
  ASSERT_EQ(f.nx, c.nx);
  ASSERT_EQ(f.ny, c.ny);
  for (std::size_t k = 0; k < f.z.size(); ++k) ASSERT_NEAR(f.z[k], c.z[k], 1e-9) << "node " << k;
  EXPECT_THAT(fine.notes, ::testing::Contains(HasSubstr(
                              "resampled bilinearly to the virtual spheres' spacing 3.6576")));
  // ... and so the same runout and bounce heights, within Monte Carlo error
  // (with a sphere on every data node, R = 0.3 m gave runout medians 5x apart).
  const Distribution a = SimulateSlope(SlopeAtResolution(1.0));
  const Distribution b = SimulateSlope(SlopeAtResolution(2.0));
  ExpectSameMedian(a.runout, b.runout, "runout");
  ExpectSameMedian(a.height, b.height, "height at x = 60 m");
}

}  // namespace
}  // namespace rockcal::sites
