// A twin of measured impacts (issue #53; bench/impacts_twin.py, whose
// figures are in bench/README.md): 20 impacts of a 2 ft sphere on the
// tutorial's talus, the "field" rebounds the replays' medians at hidden
// hardness, roughness and friction; a calibration from elsewhere with the
// global stage recovers all three within 5 % of their ranges (measured:
// 0.45, 2.00 ft and 0.589: 0.03, 0.05 and 1.8 %; all 20 impacts kept),
// and the posterior's 90 % intervals hold the hidden values (measured:
// [0.434, 0.469], [1.96, 2.05] ft and [0.517, 0.758]). 9 s of CPU in
// Release (14 s on a busy 2-core machine).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

constexpr double kFoot = 0.3048;

// The rows of a CSV file with a header, as column -> text.
std::vector<std::map<std::string, std::string>> ReadCsv(const std::string& path) {
  std::istringstream in(ReadFile(path));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
    if (header.empty()) {
      header = fields;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size() && k < fields.size(); ++k) row[header[k]] = fields[k];
    rows.push_back(row);
  }
  return rows;
}

TEST(ImpactsTwin, HardnessRoughnessAndFrictionAreRecoveredFrom20ReboundsAndCovered) {
  const std::string dir = FreshDir("twin");
  fs::create_directories(dir);
  const fs::path tutorial = fs::path(ROCKCAL_SOURCE_DIR) / "sites/examples/tutorial";
  std::map<std::pair<int, int>, double> z;
  for (const auto& r : ReadCsv((tutorial / "points.csv").string()))
    z[{static_cast<int>(std::stod(r.at("x"))), static_cast<int>(std::stod(r.at("y")))}] =
        std::stod(r.at("z"));
  nlohmann::json site = nlohmann::json::parse(ReadFile((tutorial / "site.json").string()));
  site["surface"]["points_file"] = (tutorial / "points.csv").string();
  site["rocks"] = nlohmann::json::parse(R"([{"id": "s1", "count": 4, "shape": "sphere",
      "size": [2.0, 2.0], "unit_weight": 165,
      "release": {"zone": [[10, 70], [40, 70], [40, 130], [10, 130]], "height": 0}}])");
  site["partitions"] = nlohmann::json::array();
  site.erase("report");
  const std::map<std::string, std::pair<double, double>> bounds = {
      {"hardness", {0.1, 0.8}}, {"roughness", {0.5, 4.0}}, {"friction", {0.3, 0.9}}};
  const std::map<std::string, double> hidden = {
      {"hardness", 0.45}, {"roughness", 2.0}, {"friction", 0.6}};
  site["materials"][1] = {
      {"id", "talus"},
      {"zone", {{90, -10}, {250, -10}, {250, 210}, {90, 210}}},
      {"calibrate",
       {{"hardness", {0.1, 0.8}}, {"roughness", {0.5, 4.0}}, {"friction", {0.3, 0.9}}}}};
  auto write_site = [&](const std::string& name, const std::map<std::string, double>& values) {
    nlohmann::json s = site;
    for (const auto& [k, v] : values) s["materials"][1][k] = v;
    std::ofstream(dir + "/" + name) << s.dump(1);
    return dir + "/" + name;
  };
  // 20 impacts at grid nodes of the talus, 2.5 ft above the surface points.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> across(8, 25), side(-4, 4), down(25, 40);
  std::ostringstream rows;
  int n = 0;
  for (int x = 110; x < 240 && n < 20; x += 10)
    for (int y : {40, 100, 160}) {
      if (n == 20) break;
      rows << "i" << n++ << ",s1," << x << ',' << y << ',' << z.at({x, y}) + 2.5 << ','
           << across(rng) << ',' << side(rng) << ',' << -down(rng);
      rows << "\n";
    }
  const std::string header = "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out\n";
  {
    std::istringstream in(rows.str());
    std::ofstream out(dir + "/impacts_in.csv");
    out << header;
    for (std::string line; std::getline(in, line);) out << line << ",5,0,5\n";
  }
  std::ofstream(dir + "/obs_in.json") << R"({"units": "us", "impacts_file": "impacts_in.csv"})";
  RunResult r = Rockcal("score " + write_site("hidden.json", hidden) + " --observations " + dir +
                        "/obs_in.json --rocks 4 --seed 5 --quiet --out " + dir + "/hidden");
  ASSERT_EQ(r.status, 0) << r.err;
  // The field: each impact's replays' median rebound, where most replays left the ground.
  std::map<std::string, std::map<std::string, std::string>> sim;
  for (const auto& s : ReadCsv(dir + "/hidden/impacts.csv")) sim[s.at("id")] = s;
  {
    std::istringstream in(rows.str());
    std::ofstream out(dir + "/impacts.csv");
    out << header;
    int kept = 0;
    for (std::string line; std::getline(in, line);) {
      const auto& s = sim.at(line.substr(0, line.find(',')));
      if (std::stoi(s.at("left")) < std::stoi(s.at("draws")) / 2 ||
          std::stod(s.at("normal_ratio_sim")) <= 0.05)
        continue;
      out << line << ',' << s.at("vx_sim") << ',' << s.at("vy_sim") << ',' << s.at("vz_sim")
          << "\n";
      ++kept;
    }
    EXPECT_GE(kept, 15) << "impacts kept";
  }
  std::ofstream(dir + "/obs.json")
      << R"({"units": "us", "impacts_file": "impacts.csv", "error": {"rebound": 0.05}})";
  const std::string start =
      write_site("start.json", {{"hardness", 0.3}, {"roughness", 1.0}, {"friction", 0.8}});
  r = Rockcal("calibrate " + start + " --observations " + dir +
              "/obs.json --rocks 4 --reach 60 --seed 5 --max-evals 150 --posterior --predictive 0 "
              "--quiet --out " +
              dir + "/cal");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json params =
      nlohmann::json::parse(ReadFile(dir + "/cal/parameters.json"))["parameters"];
  int checked = 0;
  for (const auto& p : params) {
    if (p["material"] != "talus") continue;
    const std::string name = p["name"];
    const double value = p["value"].get<double>() / (name == "roughness" ? kFoot : 1.0);
    const auto [lo, hi] = bounds.at(name);
    EXPECT_LT(std::abs(value - hidden.at(name)), 0.05 * (hi - lo))
        << name << ": recovered " << value << ", hidden " << hidden.at(name);
    // The posterior's 90 % interval holds the hidden value.
    ASSERT_TRUE(p.contains("posterior")) << p.dump();
    const double scale = name == "roughness" ? kFoot : 1.0;
    const double p05 = p["posterior"]["p05"].get<double>() / scale;
    const double p95 = p["posterior"]["p95"].get<double>() / scale;
    EXPECT_LE(p05, hidden.at(name)) << name << ": 90 % interval [" << p05 << ", " << p95 << "]";
    EXPECT_GE(p95, hidden.at(name)) << name << ": 90 % interval [" << p05 << ", " << p95 << "]";
    std::printf("%s: recovered %.4g, hidden %.4g, 90 %% interval [%.4g, %.4g]\n", name.c_str(),
                value, hidden.at(name), p05, p95);
    ++checked;
  }
  EXPECT_EQ(checked, 3);
}

}  // namespace
}  // namespace rockcal::cli
