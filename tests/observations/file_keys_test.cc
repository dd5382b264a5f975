// docs/reference/observations-file.md against the keys the observations
// reader accepts (observations/file_keys.h), both ways, with a type, unit,
// range, default and example for every key.
#include "rockcal/observations/file_keys.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "../sites/reference_tables.h"

namespace rockcal::observations {
namespace {

TEST(ObservationsFileKeys, TheReferenceListsEveryKeyTheReaderAcceptsAndNoOther) {
  rockcal::testing::ExpectReferenceMatches("docs/reference/observations-file.md",
                                           ObservationsFileKeys());
}

TEST(ObservationsFileKeys, AnUnknownPathIsAProgrammerError) {
  EXPECT_THROW(ObservationsKeysAt("$.no_such_object"), std::logic_error);
}

}  // namespace
}  // namespace rockcal::observations
