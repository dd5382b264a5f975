// Helpers of the sites tests: a private temporary folder for files written
// by a test, catching the message of an InputError, and the example sites.
#ifndef ROCKCAL_TESTS_SITES_TEST_FILES_H_
#define ROCKCAL_TESTS_SITES_TEST_FILES_H_

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "rockcal/core/error.h"

namespace rockcal::sites::testing {

// A fresh folder under the test temporary directory, removed at the end.
class TempDir final {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name =
        std::string("rockcal_sites_") +
        (info ? std::string(info->test_suite_name()) + "_" + info->name() : std::string("x")) +
        "_" + std::to_string(getpid()) + "_" + std::to_string(counter++);
    path_ = std::filesystem::path(::testing::TempDir()) / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string path() const { return path_.string(); }
  // Writes `text` to `name` inside the folder; returns the full path.
  std::string Write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << text;
    return p.string();
  }

 private:
  std::filesystem::path path_;
};

// The message of the InputError `f` throws; records a failure (and returns
// "") when it throws nothing.
inline std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

// The site file of the example `name` under sites/examples/.
inline std::string ExampleSite(const std::string& name) {
  return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/" + name + "/site.json";
}

}  // namespace rockcal::sites::testing

#endif  // ROCKCAL_TESTS_SITES_TEST_FILES_H_
