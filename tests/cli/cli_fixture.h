// Running the rockcal executable from the command-line tests, as a user does.
#ifndef ROCKCAL_TESTS_CLI_CLI_FIXTURE_H_
#define ROCKCAL_TESTS_CLI_CLI_FIXTURE_H_

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rockcal::cli::testing {

struct RunResult {
  int status;
  std::string out, err;
};

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// "Suite.Test" of the running test, '/' (parameterised tests) made '_': a
// file name no other test shares (ctest runs tests in parallel).
inline std::string TestFileName() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (!info) {  // a suite's set-up
    const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
    return std::string(suite ? suite->name() : "rockcal") + ".SetUpTestSuite";
  }
  std::string name = std::string(info->test_suite_name()) + "." + info->name();
  for (char& ch : name)
    if (ch == '/') ch = '_';
  return name;
}

// Runs the shell command line `command`; stdout and stderr go to files named
// after the test.
inline RunResult Run(const std::string& command) {
  const std::string base = ::testing::TempDir() + "/rockcal_" + TestFileName();
  const std::string out_file = base + ".stdout", err_file = base + ".stderr";
  const int raw = std::system((command + " > " + out_file + " 2> " + err_file).c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, ReadFile(out_file), ReadFile(err_file)};
}

// Runs rockcal with `args`; stdout and stderr go to files named after the test.
inline RunResult Rockcal(const std::string& args) {
  return Run(std::string(ROCKCAL_EXE) + " " + args);
}

// The site file of a bundled example.
inline std::string Example(const std::string& name) {
  return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/" + name + "/site.json";
}

// An output folder under the test temp dir that does not exist yet, named
// after the running test and `name`.
inline std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/rockcal_" + TestFileName() + "_" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace rockcal::cli::testing

#endif  // ROCKCAL_TESTS_CLI_CLI_FIXTURE_H_
