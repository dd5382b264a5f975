// A fresh folder per test for the observations readers' tests, removed
// afterwards, and the files they write into it.
#ifndef ROCKCAL_TESTS_OBSERVATIONS_FILE_FIXTURE_H_
#define ROCKCAL_TESTS_OBSERVATIONS_FILE_FIXTURE_H_

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace rockcal::observations::testing {

class FileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("rockcal_observations_" + std::string(info->test_suite_name()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Writes `text` to `name` in the test's folder; returns its path.
  std::string Write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = dir_ / name;
    std::ofstream out(p, std::ios::binary);
    out << text;
    return p.string();
  }

  std::filesystem::path dir_;
};

}  // namespace rockcal::observations::testing

#endif  // ROCKCAL_TESTS_OBSERVATIONS_FILE_FIXTURE_H_
