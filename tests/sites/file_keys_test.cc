// docs/reference/site-file.md against the keys the site reader accepts
// (sites/file_keys.h), both ways, with a type, unit, range, default and
// example for every key.
#include "rockcal/sites/file_keys.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "reference_tables.h"

namespace rockcal::sites {
namespace {

TEST(SiteFileKeys, TheReferenceListsEveryKeyTheReaderAcceptsAndNoOther) {
  rockcal::testing::ExpectReferenceMatches("docs/reference/site-file.md", SiteFileKeys());
}

TEST(SiteFileKeys, AnUnknownPathIsAProgrammerError) {
  EXPECT_THROW(SiteKeysAt("$.no_such_object"), std::logic_error);
  EXPECT_FALSE(SiteKeysAt("$.materials[].calibrate").empty());
}

}  // namespace
}  // namespace rockcal::sites
