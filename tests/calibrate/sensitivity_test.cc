// The site study of sensitivity on a small synthetic site where one material
// lies where no rock goes (the estimators themselves:
// sensitivity_methods_test.cc).
#include "rockcal/calibrate/sensitivity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "rockcal/core/error.h"
#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

// ---- A site -------------------------------------------------------------------------

// The twin site with a third material at two corner nodes behind the
// release, where no rock can go; its hardness and roughness are calibrated
// with the slope's hardness.
sites::Site SiteWithAnUnreachedMaterial(int rocks) {
  sites::Site site = testing::TwinSite(rocks);
  core::Scene& scene = site.scene;
  core::Material corner = scene.materials[0];
  corner.id = "corner";
  scene.materials.push_back(corner);
  scene.grid.material[0] = 2;  // (0, 0)
  scene.grid.material[static_cast<std::size_t>((scene.grid.ny - 1) * scene.grid.nx)] =
      2;  // (0, 20)
  site.calibrate = {{"slope", "hardness", 0.2, 0.8, "slope"},
                    {"corner", "hardness", 0.1, 0.9, "corner"},
                    {"corner", "roughness", 0.1, 0.6, "corner"}};
  scene.options.max_time = 14.0;  // the rocks stop by then; bounds the cost under the sanitizers
  return site;
}

TEST(SensitivitySite, MorrisSeesTheSlopeAndNotAMaterialNoRockReaches) {
  const sites::Site site = SiteWithAnUnreachedMaterial(6);
  SensitivityOptions opt;
  opt.samples = 2;
  opt.bootstrap = 40;
  opt.threads = 2;
  int calls = 0;
  opt.progress = [&](int, int total, const std::string&) {
    ++calls;
    EXPECT_EQ(total, 2 * 4 + 1);
  };
  const SensitivityResult r = RunSensitivity(site, nullptr, opt);
  EXPECT_EQ(r.simulations, 2 * 4 + 1);
  EXPECT_EQ(calls, r.simulations);
  ASSERT_EQ(r.parameters.size(), 3u);
  // P and Q: height p50, p90, passing; runout p50, p90; stopped.
  ASSERT_EQ(r.outputs.size(), 3u * 2u + 3u);
  EXPECT_EQ(r.outputs[0].name, "P.height.p50");
  EXPECT_EQ(r.outputs[8].name, "stopped");
  for (int o = 0; o < static_cast<int>(r.outputs.size()); ++o) {
    EXPECT_TRUE(std::isfinite(r.outputs[static_cast<std::size_t>(o)].value))
        << r.outputs[static_cast<std::size_t>(o)].name << ": no value, the check below is void";
    for (int p : {1, 2}) {
      const MorrisIndex& e = r.at(p, o).morris;
      EXPECT_GE(e.effects, 1);  // some effect counted: the zero below is not void
      EXPECT_EQ(e.mu_star, 0.0) << r.parameters[static_cast<std::size_t>(p)].label() << " on "
                                << r.outputs[static_cast<std::size_t>(o)].name;
    }
  }
  // The slope's hardness changes how high rocks bounce on the slope.
  EXPECT_GT(r.at(0, 0).morris.mu_star + r.at(0, 1).morris.mu_star, 0.0);
  EXPECT_NE(r.summary.find("corner.hardness"), std::string::npos) << r.summary;
  EXPECT_TRUE(std::isfinite(r.outputs[0].noise) && r.outputs[0].noise > 0) << r.outputs[0].noise;
}

TEST(SensitivitySite, SobolWithObservationsHasTheMisfitAndIsRepeatable) {
  sites::Site site = SiteWithAnUnreachedMaterial(3);
  site.calibrate = {site.calibrate[0], site.calibrate[2]};  // slope hardness, corner roughness
  sites::Site observed = site;  // observations from more rocks (every set has values)
  observed.scene.SetTotalRocks(20);
  const observations::Observations obs = testing::TwinObservations(observed, {0.5, 0.3}, 11);
  SensitivityOptions opt;
  opt.method = SensitivityMethod::kSobol;
  opt.samples = 4;
  opt.bootstrap = 20;
  opt.threads = 1;
  const SensitivityResult a = RunSensitivity(site, &obs, opt);
  EXPECT_EQ(a.simulations, 4 * 4 + 1);
  ASSERT_EQ(a.outputs.back().name, "misfit");
  EXPECT_NE(a.outputs[6].description.find("observed runout direction"), std::string::npos);
  opt.threads = 2;  // results do not depend on the thread count
  const SensitivityResult b = RunSensitivity(site, &obs, opt);
  ASSERT_EQ(a.entries.size(), b.entries.size());
  for (std::size_t e = 0; e < a.entries.size(); ++e) {
    const SobolIndex &x = a.entries[e].sobol, &y = b.entries[e].sobol;
    EXPECT_TRUE(x.first == y.first || (std::isnan(x.first) && std::isnan(y.first))) << e;
    EXPECT_TRUE(x.total == y.total || (std::isnan(x.total) && std::isnan(y.total))) << e;
  }
  // The unreached corner: no share of any variance.
  for (int o = 0; o < static_cast<int>(a.outputs.size()); ++o) {
    if (std::isfinite(a.at(1, o).sobol.total)) {
      EXPECT_EQ(a.at(1, o).sobol.total, 0.0) << o;
    }
  }
  const nlohmann::json j = a;
  EXPECT_EQ(j["method"], "sobol");
  EXPECT_EQ(j["entries"].size(), 2u * a.outputs.size());
}

TEST(SensitivitySite, ASiteWithoutBoundsIsAnInputError) {
  sites::Site site = testing::TwinSite(2);
  site.calibrate.clear();
  EXPECT_THROW(RunSensitivity(site, nullptr, SensitivityOptions{}), InputError);
  SensitivityOptions opt;
  opt.samples = 1;
  std::string error;
  EXPECT_FALSE(opt.IsValid(&error));
  EXPECT_NE(error.find("sensitivity.samples = 1"), std::string::npos) << error;
}

}  // namespace
}  // namespace rockcal::calibrate
