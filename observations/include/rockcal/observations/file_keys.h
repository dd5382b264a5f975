// The keys each object of an observations file accepts: the lists the
// observations reader rejects every other key with, named by the object's
// JSON path as docs/reference/observations-file.md heads its tables
// (tests/observations/file_keys_test.cc checks the two against each other).
#ifndef ROCKCAL_OBSERVATIONS_FILE_KEYS_H_
#define ROCKCAL_OBSERVATIONS_FILE_KEYS_H_

#include <string>
#include <vector>

#include "rockcal/sites/file_keys.h"

namespace rockcal::observations {

// Every kind of object of an observations file.
const std::vector<sites::FileObjectKeys>& ObservationsFileKeys();

// sites::KeysAt(ObservationsFileKeys(), path).
const std::vector<const char*>& ObservationsKeysAt(const std::string& path);

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_FILE_KEYS_H_
