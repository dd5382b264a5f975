// GDAL's library is loaded at the first GIS file a run reads, not when
// rockcal starts (sites/src/gdal_library.cc): a site of scattered points
// (the tutorial) never loads it, a GeoTIFF site does. Each suite runs as a
// process of its own (cmake/gtest_suites.cmake), so each starts without it.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>

#include "rockcal/sites/site.h"
#include "test_files.h"

namespace rockcal::sites {
namespace {

// True when GDAL's library is in the process (RTLD_NOLOAD: never loads it).
bool GdalLoaded() {
  void* library = dlopen(ROCKCAL_GDAL_SONAME, RTLD_NOW | RTLD_NOLOAD);
  if (library) dlclose(library);
  return library != nullptr;
}

TEST(GdalNotLoaded, ByASiteOfScatteredPoints) {
  ASSERT_FALSE(GdalLoaded()) << "GDAL is loaded before any site: linked, not loaded at first use";
  const Site site = LoadSite(testing::ExampleSite("tutorial"));
  EXPECT_GT(site.scene.grid.nx, 0);
  EXPECT_FALSE(GdalLoaded());
}

TEST(GdalLoadedAtFirstUse, ByARasterSite) {
  ASSERT_FALSE(GdalLoaded());
  const Site site = LoadSite(testing::ExampleSite("authume_gis"));
  EXPECT_GT(site.scene.grid.nx, 0);
  EXPECT_TRUE(GdalLoaded());
}

}  // namespace
}  // namespace rockcal::sites
