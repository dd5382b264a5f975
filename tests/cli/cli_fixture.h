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

// The tutorial slope with a stand of 600 stems/ha (DBH 30 +- 8 cm, half
// conifers) over its talus and soil, in a folder of its own named after the
// running test; returns its site file.
inline std::string ForestedTutorial() {
  const std::string dir = FreshDir("forested_site");
  std::filesystem::create_directories(dir);
  const std::string tutorial = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  std::filesystem::copy_file(tutorial + "/points.csv", dir + "/points.csv");
  const std::string site = ReadFile(tutorial + "/site.json");
  const std::string key = "\"simulation\":";
  const std::size_t at = site.find(key);
  if (at == std::string::npos) return "";
  std::ofstream(dir + "/site.json")
      << site.substr(0, at)
      << "\"forest\": {\"stands\": [{\"zone\": [[100, 40], [560, 40], [560, 160], [100, "
         "160]], \"stems_per_ha\": 600, \"dbh_mean_cm\": 30, \"dbh_sd_cm\": 8, "
         "\"conifer_percent\": 50}]},\n  "
      << site.substr(at);
  return dir + "/site.json";
}

}  // namespace rockcal::cli::testing

#endif  // ROCKCAL_TESTS_CLI_CLI_FIXTURE_H_
