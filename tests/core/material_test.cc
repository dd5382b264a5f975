#include "rockcal/core/material.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rockcal/core/scene.h"

namespace rockcal::core {
namespace {

TEST(Material, RoughnessToVirtualSphereRadius) {
  const double s = 12 * kFoot;
  EXPECT_NEAR(VirtualSphereRadius(6 * kFoot, s) / kFoot, 6.0, 1e-12);
  const double r = VirtualSphereRadius(0.3 * kFoot, s) / kFoot;
  EXPECT_NEAR(r, 60.15, 1e-9) << "r = " << r;  // (0.09 + 36) / 0.6
  EXPECT_TRUE(std::isinf(VirtualSphereRadius(0.0, s)));
}

TEST(Material, SmallestRoughnessKeepsSpheresWithinTenGridSpacings) {
  const double s = 12 * kFoot;
  EXPECT_NEAR(MinRoughness(s) / kFoot, 0.15, 1e-12);
  const double r = VirtualSphereRadius(MinRoughness(s), s);
  EXPECT_NEAR(r / s, 10.00625, 1e-12) << "r = " << r / kFoot << " ft";
}

TEST(Material, ClampedRestitutionMatchesKnownValuesOfEq13) {
  // With the manual's eq. 13 damping and a force that never pulls, the
  // restitution comes out higher than asked (Schwager & Poeschel 2007).
  const double expected[][2] = {{0.2, 0.325}, {0.5, 0.550}, {0.8, 0.808}};
  for (const auto& row : expected) {
    const double ln_e = std::log(row[0]);
    const double zeta13 = -ln_e / std::sqrt(M_PI * M_PI + ln_e * ln_e);
    EXPECT_NEAR(ClampedRestitution(zeta13), row[1], 0.005) << "e = " << row[0];
  }
}

TEST(Material, DampingRatioInvertsClampedRestitution) {
  for (double e : {0.01, 0.05, 0.2, 0.5, 0.8, 0.99}) {
    const double zeta = DampingRatioForRestitution(e);
    EXPECT_NEAR(ClampedRestitution(zeta), e, 1e-10) << "e = " << e << " zeta = " << zeta;
  }
  EXPECT_GT(DampingRatioForRestitution(0.01), 1.0);  // overdamped branch
}

TEST(Material, HardnessModelDefaults) {
  Material m;
  m.hardness = 0.3;
  m.contact_time_s = 0.005;
  const ContactLaw law = DeriveContactLaw(m);
  EXPECT_DOUBLE_EQ(law.restitution, 0.3);
  EXPECT_NEAR(law.friction, 0.9 - 0.5 * 0.3, 1e-15);
  const double ln_e = std::log(0.3);
  EXPECT_NEAR(law.stiffness_per_mass, (M_PI * M_PI + ln_e * ln_e) / 25e-6, 1e-6);
  EXPECT_NEAR(law.damping_per_mass, 2 * law.damping_ratio * std::sqrt(law.stiffness_per_mass), 1e-9);
  EXPECT_GT(law.damping_ratio, law.eq13_damping_ratio);
  EXPECT_NEAR(law.tangential_ratio, 2.0 / 7.0, 1e-15);
}

TEST(Material, HardnessClampsAndOverrides) {
  Material m;
  m.hardness = 0.0;
  EXPECT_DOUBLE_EQ(DeriveContactLaw(m).restitution, 0.01);
  EXPECT_DOUBLE_EQ(DeriveContactLaw(m).friction, 0.9);
  m.hardness = 1.0;
  EXPECT_DOUBLE_EQ(DeriveContactLaw(m).restitution, 0.99);
  EXPECT_DOUBLE_EQ(DeriveContactLaw(m).friction, 0.4);
  m.restitution = 0.6;
  m.friction = 0.1;
  EXPECT_DOUBLE_EQ(DeriveContactLaw(m).restitution, 0.6);
  EXPECT_DOUBLE_EQ(DeriveContactLaw(m).friction, 0.1);
}

}  // namespace
}  // namespace rockcal::core
