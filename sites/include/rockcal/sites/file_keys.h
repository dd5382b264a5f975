// The keys each object of a site file accepts: the lists the site reader
// rejects every other key with, named by the object's JSON path as the file
// reference (docs/reference/site-file.md) heads its tables, so that
// tests/sites/file_keys_test.cc checks the reference against the reader.
#ifndef ROCKCAL_SITES_FILE_KEYS_H_
#define ROCKCAL_SITES_FILE_KEYS_H_

#include <string>
#include <vector>

namespace rockcal::sites {

// One kind of object of an input file and the keys its reader accepts.
struct FileObjectKeys {
  std::string path;               // "$", "$.surface", "$.materials[]", ...
  std::vector<const char*> keys;  // in the reader's order
};

// Every kind of object of a site file (a material's "calibrate" object takes
// the names of core::MaterialFields()).
const std::vector<FileObjectKeys>& SiteFileKeys();

// The keys of the object at `path` in `objects`; a programmer error
// (std::logic_error) for a path the list does not hold.
const std::vector<const char*>& KeysAt(const std::vector<FileObjectKeys>& objects,
                                       const std::string& path);

// KeysAt(SiteFileKeys(), path).
const std::vector<const char*>& SiteKeysAt(const std::string& path);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_FILE_KEYS_H_
