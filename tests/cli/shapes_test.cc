// Scanned shapes in site files, end to end: a bad shape file is exit 2
// naming the file; a good one validates and simulates.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_fixture.h"

namespace rockcal::cli::testing {
namespace {

// A folder with a small SI site whose one rock group is `group` (JSON).
std::string WriteSite(const std::string& dir, const std::string& group) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/site.json")
      << "{\"name\": \"shapes\", \"units\": \"si\", \"surface\": {\"resolution\": 2, \"points\": "
         "[[0, 0, 40], [60, 0, 0], [0, 30, 40], [60, 30, 0]]}, \"materials\": [{\"id\": \"m\", "
         "\"hardness\": 0.5, \"roughness\": 0.1}], \"rocks\": ["
      << group << "], \"simulation\": {\"seed\": 1, \"max_time\": 20}}";
  return dir + "/site.json";
}

std::string Release() { return "\"release\": {\"point\": [5, 15], \"height\": 1}"; }

// A cloud of points on a 1 x 0.6 x 0.4 m box's surface.
std::string BoxCloud() {
  std::ostringstream s;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int k = 0; k <= 4; ++k)
        if (i == 0 || i == 4 || j == 0 || j == 4 || k == 0 || k == 4)
          s << i * 0.25 << " " << j * 0.15 << " " << k * 0.1 << "\n";
  return s.str();
}

TEST(Shapes, BadShapeFilesExitTwoNamingTheFile) {
  const std::string dir = FreshDir("bad");
  std::filesystem::create_directories(dir + "/lib");
  std::ofstream(dir + "/lib/few.xyz") << "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  std::ostringstream flat;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) flat << i << " " << j << " 0\n";
  std::ofstream(dir + "/lib/flat.xyz") << flat.str();
  std::ofstream(dir + "/lib/open.stl")
      << "solid o\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
         "endloop\nendfacet\nendsolid o\n";
  std::ofstream(dir + "/lib/text.xyz") << "a block\n1 2\n";
  struct Case {
    const char* file;
    const char* says;
  };
  for (const Case& c : {Case{"lib/missing.xyz", "missing.xyz"}, Case{"lib/few.xyz", "too few points"},
                        Case{"lib/flat.xyz", "degenerate"}, Case{"lib/open.stl", "not a closed surface"},
                        Case{"lib/text.xyz", "text.xyz:"}}) {
    const std::string site = WriteSite(dir, std::string("{\"count\": 2, \"shape_file\": \"") +
                                                c.file + "\", \"size\": 1, \"unit_weight\": 26, " +
                                                Release() + "}");
    const RunResult r = Rockcal("validate " + site);
    EXPECT_EQ(r.status, 2) << c.file << ": " << r.err;
    EXPECT_NE(r.err.find(c.file + 4), std::string::npos) << c.file << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.file << ": " << r.err;
  }
  // From an inventory row, through the shape library.
  std::ofstream(dir + "/blocks.csv") << "mass,L1,L2,L3,shape\n500,1.2,0.8,0.5,flat.xyz\n";
  const std::string site = WriteSite(
      dir, "{\"inventory\": \"blocks.csv\", \"shapes\": \"lib\", " + Release() + "}");
  const RunResult r = Rockcal("validate " + site);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("flat.xyz"), std::string::npos) << r.err;
  // A key that does not belong.
  const std::string wrong = WriteSite(
      dir, "{\"count\": 1, \"shape\": \"cube\", \"spheres\": 4, \"size\": 1, \"unit_weight\": 26, " +
               Release() + "}");
  const RunResult w = Rockcal("validate " + wrong);
  EXPECT_EQ(w.status, 2) << w.err;
  EXPECT_NE(w.err.find("spheres"), std::string::npos) << w.err;
}

TEST(Shapes, AShapeFileValidatesAndSimulates) {
  const std::string dir = FreshDir("good");
  std::filesystem::create_directories(dir + "/lib");
  std::ofstream(dir + "/lib/slab.xyz") << BoxCloud();
  std::ofstream(dir + "/blocks.csv") << "mass,L1,L2,L3,shape\n500,1.2,0.8,0.5,slab.xyz\n"
                                        "300,0.9,0.7,0.4,box\n";
  const std::string site = WriteSite(
      dir, "{\"inventory\": \"blocks.csv\", \"shapes\": \"lib\", \"spheres\": 6, " + Release() +
               "}, {\"count\": 2, \"shape_file\": \"lib/slab.xyz\", \"size\": [0.5, 1], "
               "\"unit_weight\": 26, " + Release() + "}");
  const RunResult v = Rockcal("validate " + site);
  EXPECT_EQ(v.status, 0) << v.err;
  EXPECT_NE(v.out.find("slab: 6 spheres"), std::string::npos) << v.out;
  const std::string out = FreshDir("out");
  const RunResult s = Rockcal("simulate " + site + " --out " + out + " --threads 1");
  EXPECT_EQ(s.status, 0) << s.err;
  const std::string csv = ReadFile(out + "/rocks.csv");
  EXPECT_NE(csv.find(",scanned,"), std::string::npos) << csv;
  const std::string html = ReadFile(out + "/report.html");
  EXPECT_NE(html.find("Scanned shapes"), std::string::npos);
  EXPECT_NE(html.find("slab: clump over hull"), std::string::npos);
}

}  // namespace
}  // namespace rockcal::cli::testing
