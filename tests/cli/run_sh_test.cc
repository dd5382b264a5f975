// run.sh installs every Debian package whose headers the build includes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The words of run.sh's PACKAGES=( ... ) array.
std::set<std::string> RunShPackages() {
  const std::string text = Slurp(fs::path(ROCKCAL_SOURCE_DIR) / "run.sh");
  const auto begin = text.find("PACKAGES=(");
  EXPECT_NE(begin, std::string::npos) << "run.sh has no PACKAGES=(";
  const auto end = text.find(')', begin);
  std::istringstream words(text.substr(begin + 10, end - begin - 10));
  std::set<std::string> packages;
  for (std::string w; words >> w;) packages.insert(w);
  return packages;
}

// The Debian package of each third-party header (by its first path part).
const std::map<std::string, std::string>& HeaderPackages() {
  static const std::map<std::string, std::string> packages = {
      {"Eigen", "libeigen3-dev"},        {"ceres", "libceres-dev"},
      {"nlopt.hpp", "libnlopt-cxx-dev"}, {"nlohmann", "nlohmann-json3-dev"},
      {"gtest", "libgtest-dev"},         {"gmock", "libgmock-dev"},
      {"omp.h", "build-essential"},      {"mpi.h", "libopenmpi-dev"},
      {"libqhull_r", "libqhull-dev"}};
  return packages;
}

// GDAL's headers lie flat in its folder, named by module: gdal*, cpl_*, ogr_*.
bool IsGdalHeader(const std::string& header) {
  for (const char* prefix : {"gdal", "cpl_", "ogr_", "ogrsf_frmts"})
    if (header.rfind(prefix, 0) == 0 && header.find('/') == std::string::npos) return true;
  return false;
}

bool IsSystemHeader(const std::string& header) {
  static const std::set<std::string> posix = {"unistd.h", "stdlib.h", "signal.h",
                                              "fcntl.h",  "errno.h",  "dlfcn.h"};
  if (posix.count(header) || header.rfind("sys/", 0) == 0) return true;
  // The C++ standard headers have no extension and no folder.
  return header.find('.') == std::string::npos && header.find('/') == std::string::npos;
}

TEST(RunShTest, PackagesHoldEveryThirdPartyHeaderTheBuildIncludes) {
  const std::set<std::string> packages = RunShPackages();
  const std::regex include("^\\s*#\\s*include\\s*<([^>]+)>");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(ROCKCAL_SOURCE_DIR)) {
    const std::string rel = fs::relative(entry.path(), ROCKCAL_SOURCE_DIR).string();
    if (rel.rfind("build", 0) == 0 || rel.rfind(".git", 0) == 0) continue;
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".cc" && ext != ".h" && ext != ".hpp")) continue;
    ++files;
    std::istringstream lines(Slurp(entry.path()));
    for (std::string line; std::getline(lines, line);) {
      std::smatch m;
      if (!std::regex_search(line, m, include)) continue;
      const std::string header = m[1];
      if (IsSystemHeader(header)) continue;
      if (IsGdalHeader(header)) {
        EXPECT_TRUE(packages.count("libgdal-dev"))
            << rel << " includes <" << header << "> but run.sh's PACKAGES lacks libgdal-dev";
        continue;
      }
      const std::string root = header.substr(0, header.find('/'));
      const auto it = HeaderPackages().find(root);
      if (it == HeaderPackages().end()) {
        ADD_FAILURE() << rel << " includes <" << header << ">, of no known package";
        continue;
      }
      EXPECT_TRUE(packages.count(it->second))
          << rel << " includes <" << header << "> but run.sh's PACKAGES lacks " << it->second;
    }
  }
  EXPECT_GT(files, 50);
}

}  // namespace
}  // namespace rockcal::cli
