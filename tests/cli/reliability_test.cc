// Nothing lost (issue 40): an output folder is none of the run's inputs for
// every command and every kind of input, a folder in use by another run is
// refused, a log two runs wrote at once is not resumed, special files and
// deep JSON are refused without blocking or crashing, and the exit classes.
//
// One workspace for the suite (one process per suite): a site whose data
// file, observations, observations' CSV file, an earlier calibration and a
// campaign each lie in a folder of their own, each folder holding rockcal's
// marker, so that --force would replace it were it not an input.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

std::string Examples() { return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples"; }

void Replace(std::string* text, const std::string& from, const std::string& to) {
  for (std::size_t at = text->find(from); at != std::string::npos;
       at = text->find(from, at + to.size()))
    text->replace(at, from.size(), to);
}

void Write(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

// Marks `dir` as a folder rockcal wrote: --force would replace it.
void Mark(const std::string& dir) {
  Write(dir + "/.rockcal-output", "{\"tool\": \"rockcal\", \"command\": \"simulate\"}\n");
}

class Reliability : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ws_ = ::testing::TempDir() + "/rockcal_reliability_" + std::to_string(::getpid());
    fs::remove_all(ws_);
    // The tutorial with its points file, observations and a heights CSV in
    // folders of their own.
    std::string site = ReadFile(Examples() + "/tutorial/site.json");
    Replace(&site, "\"points.csv\"", "\"../points/points.csv\"");
    Write(ws_ + "/site/site.json", site);
    fs::create_directories(ws_ + "/points");
    fs::copy_file(Examples() + "/tutorial/points.csv", ws_ + "/points/points.csv");
    nlohmann::json obs =
        nlohmann::json::parse(ReadFile(Examples() + "/tutorial/observations.json"));
    std::string heights = "height\n";
    for (const auto& h : obs["tree_scars"][0]["heights"]) heights += h.dump() + "\n";
    obs["tree_scars"][0].erase("heights");
    obs["tree_scars"][0]["heights_file"] = "../obscsv/heights.csv";
    Write(ws_ + "/obs/observations.json", obs.dump(1));
    Write(ws_ + "/obscsv/heights.csv", heights);
    // The twin campaign, copied.
    fs::copy(Examples() + "/twin_campaign", ws_ + "/camp", fs::copy_options::recursive);
    // Authume with its STL terrain and its inventory apart.
    std::string authume = ReadFile(Examples() + "/authume/site.json");
    Replace(&authume, "data/DTM_", "../stl/DTM_");
    Replace(&authume, "data/blocks_P1.csv", "../inventory/blocks_P1.csv");
    Write(ws_ + "/authume/site.json", authume);
    fs::create_directories(ws_ + "/stl");
    for (const char* zone : {"Gray", "Red", "Blue"})
      fs::copy_file(Examples() + "/authume/data/DTM_" + std::string(zone) + "_zone.stl",
                    ws_ + "/stl/DTM_" + zone + "_zone.stl");
    fs::create_directories(ws_ + "/inventory");
    fs::copy_file(Examples() + "/authume/data/blocks_P1.csv", ws_ + "/inventory/blocks_P1.csv");
    // Authume from GIS files: the raster and the zone file apart.
    std::string gis = ReadFile(Examples() + "/authume_gis/site.json");
    Replace(&gis, "\"dem.tif\"", "\"../raster/dem.tif\"");
    Replace(&gis, "\"zones.gpkg\"", "\"../zones/zones.gpkg\"");
    Replace(&gis, "../authume/data/blocks_P1.csv", "../inventory/blocks_P1.csv");
    Write(ws_ + "/gis/site.json", gis);
    fs::create_directories(ws_ + "/raster");
    fs::copy_file(Examples() + "/authume_gis/dem.tif", ws_ + "/raster/dem.tif");
    fs::create_directories(ws_ + "/zones");
    fs::copy_file(Examples() + "/authume_gis/zones.gpkg", ws_ + "/zones/zones.gpkg");
    // A site on an ESRI grid (10 m cells, 8 x 6).
    std::string grid =
        "ncols 8\nnrows 6\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n";
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 8; ++c) grid += (c == 0 ? "" : " ") + std::to_string(200 - 5 * c);
      grid += "\n";
    }
    Write(ws_ + "/grid/dem.asc", grid);
    const nlohmann::json grid_site = {
        {"name", "grid"},
        {"units", "si"},
        {"surface", {{"grid_file", "../grid/dem.asc"}, {"resolution", 10}, {"sphere_spacing", 10}}},
        {"materials",
         nlohmann::json::array({{{"id", "rock"}, {"hardness", 0.5}, {"roughness", 0.5}}})},
        {"rocks", nlohmann::json::array({{{"count", 1},
                                          {"shape", "sphere"},
                                          {"size", 1.0},
                                          {"unit_weight", 26},
                                          {"release", {{"point", {15, 35}}}}}})},
        {"simulation", {{"seed", 1}, {"max_time", 5}}}};
    Write(ws_ + "/gridsite/site.json", grid_site.dump(1));
    // An earlier calibration (2 evaluations at 4 rocks): the --parameters
    // file and folder, and the result folder of `table`.
    calibration_ = Rockcal("calibrate " + Site() + " --observations " + Obs() +
                           " --rocks 4 --max-evals 2 --reach 0 --quiet --out " + ws_ + "/cal");
    for (const char* dir : {"site", "points", "obs", "obscsv", "camp", "camp/fan", "authume", "stl",
                            "inventory", "gis", "raster", "zones", "grid", "gridsite"})
      Mark(ws_ + "/" + dir);
  }
  static void TearDownTestSuite() { fs::remove_all(ws_); }

  void SetUp() override { ASSERT_EQ(calibration_.status, 0) << calibration_.err; }

  static std::string Site() { return ws_ + "/site/site.json"; }
  static std::string Obs() { return ws_ + "/obs/observations.json"; }
  static std::string Cal() { return ws_ + "/cal"; }

  // Every file of the workspace with its text: nothing may change.
  static std::map<std::string, std::string> Snapshot() {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(ws_))
      if (e.is_regular_file() && e.path().filename() != ".rockcal-lock")
        files[e.path().string()] = ReadFile(e.path().string());
    return files;
  }

  static std::string ws_;
  static RunResult calibration_;
};

std::string Reliability::ws_;
RunResult Reliability::calibration_;

// Every command x every kind of input it reads: an output that is the
// input, holds it or lies inside it is refused with exit 2 naming both, and
// nothing in the workspace changes, although every folder holds the marker
// and --force is given. (Issue 40: `simulate --parameters c1 --force --out c1`
// removed c1's parameters; `score` and `study reach` checked no input.)
TEST_F(Reliability, OutputIsNoInputOfTheRunForEveryCommandAndInputKind) {
  const std::string site = Site(), obs = Obs(), cal = Cal();
  const std::string site_dir = ws_ + "/site", points = ws_ + "/points", obs_dir = ws_ + "/obs",
                    csv = ws_ + "/obscsv";
  struct Case {
    std::string command;  // without --out
    std::string kind;
    std::string out;
    std::string input;  // the input the message names
  };
  std::vector<Case> cases;
  // Commands reading a site (and observations, where they take them).
  const std::string fast = " --rocks 2 --force --quiet";
  const std::vector<std::pair<std::string, bool>> site_commands = {
      {"simulate " + site + fast, false},
      {"calibrate " + site + " --observations " + obs + " --max-evals 2 --reach 0" + fast, true},
      {"score " + site + " --observations " + obs + fast, true},
      {"sensitivity " + site + " --observations " + obs + " --samples 2" + fast, true},
      {"study stability " + site + fast, false},
      {"study convergence " + site + " --force --quiet", false},
      {"study reach " + site + " --observations " + obs + " --points 2" + fast, true}};
  for (const auto& [command, observations] : site_commands) {
    cases.push_back({command, "site file (is)", site, site});
    cases.push_back({command, "site file (holds)", site_dir, site});
    cases.push_back({command, "points_file (holds)", points, ws_ + "/points/points.csv"});
    if (observations) {
      cases.push_back({command, "observations (holds)", obs_dir, obs});
      cases.push_back({command, "observations CSV (holds)", csv, ws_ + "/obscsv/heights.csv"});
    }
  }
  // --parameters, a folder or its file.
  for (const std::string& command :
       {"simulate " + site + fast, "score " + site + " --observations " + obs + fast}) {
    cases.push_back({command + " --parameters " + cal, "parameters folder (is)", cal, cal});
    cases.push_back(
        {command + " --parameters " + cal, "parameters folder (inside)", cal + "/sub", cal});
    cases.push_back({command + " --parameters " + cal + "/parameters.json",
                     "parameters file (holds)", cal, cal + "/parameters.json"});
  }
  // The data files of each kind a site names (the same collection serves
  // every command: simulate stands for them).
  for (const auto& [site_file, dir, file] :
       std::vector<std::array<std::string, 3>>{{"authume", "stl", "DTM_Gray_zone.stl"},
                                               {"authume", "inventory", "blocks_P1.csv"},
                                               {"gis", "raster", "dem.tif"},
                                               {"gis", "zones", "zones.gpkg"},
                                               {"gridsite", "grid", "dem.asc"}})
    cases.push_back({"simulate " + ws_ + "/" + site_file + "/site.json" + fast, dir + " (holds)",
                     ws_ + "/" + dir, ws_ + "/" + dir + "/" + file});
  // Campaign: the campaign file and its members.
  const std::string campaign =
      "campaign " + ws_ + "/camp/campaign.json --rocks 2 --max-evals 2 --force --quiet";
  cases.push_back({campaign, "campaign file (holds)", ws_ + "/camp", ws_ + "/camp/campaign.json"});
  cases.push_back(
      {campaign, "campaign member (holds)", ws_ + "/camp/fan", ws_ + "/camp/fan/site.json"});
  // Table: its result folders.
  const std::string table = "table " + cal + " --force --quiet";
  cases.push_back({table, "result folder (is)", cal, cal});
  cases.push_back({table, "result folder (inside)", cal + "/sub", cal});
  cases.push_back({table, "result folder (holds)", ws_, cal});

  const std::map<std::string, std::string> before = Snapshot();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.kind + ": rockcal " + c.command + " --out " + c.out);
    const RunResult run = Rockcal(c.command + " --out " + c.out);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr("rockcal: error: " + c.out + ": "));
    EXPECT_THAT(run.err, HasSubstr("an input of this run"));
    EXPECT_THAT(run.err, HasSubstr(fs::path(c.input).filename().string())) << "names the input";
    EXPECT_FALSE(fs::exists(cal + "/sub"));
  }
  EXPECT_TRUE(Snapshot() == before) << "the workspace changed";
}

// Holds the lock of `folder` as a run would, with a holder line.
class HeldLock final {
 public:
  explicit HeldLock(const std::string& folder) {
    fs::create_directories(folder);
    fd_ = ::open((folder + "/.rockcal-lock").c_str(), O_RDWR | O_CREAT, 0644);
    EXPECT_GE(fd_, 0);
    EXPECT_EQ(::flock(fd_, LOCK_EX | LOCK_NB), 0);
    const std::string holder = "pid 4242 on testhost: rockcal calibrate, since now\n";
    EXPECT_EQ(::write(fd_, holder.data(), holder.size()), static_cast<ssize_t>(holder.size()));
  }
  ~HeldLock() { ::close(fd_); }

 private:
  int fd_ = -1;
};

// Issue 40: two `calibrate --force --out conc` started together both wrote
// the folder. A folder another run holds is refused, with or without --force
// or --resume, naming the holder; so is a new folder another run is
// preparing (its temporary folder is locked).
TEST_F(Reliability, AFolderInUseIsRefusedNamingTheHolder) {
  const std::string held = ws_ + "/held";
  fs::copy(Cal(), held, fs::copy_options::recursive);
  fs::remove(held + "/calibration.json");  // a run in progress
  const std::map<std::string, std::string> before = Snapshot();
  {
    const HeldLock lock(held);
    const std::string calibrate = "calibrate " + Site() + " --observations " + Obs() +
                                  " --rocks 4 --max-evals 2 --reach 0 --quiet --out " + held;
    for (const std::string& command :
         {calibrate + " --force", calibrate + " --resume", calibrate,
          "simulate " + Site() + " --rocks 2 --quiet --force --out " + held}) {
      SCOPED_TRACE(command);
      const RunResult run = Rockcal(command);
      EXPECT_EQ(run.status, 2) << run.err;
      EXPECT_THAT(run.err, HasSubstr(held + ": is in use by another rockcal run (pid 4242 on "
                                            "testhost: rockcal calibrate, since now)"));
    }
  }
  EXPECT_TRUE(Snapshot() == before) << "the folder changed";
  {
    // A new folder: another run is building it under its temporary name.
    const std::string fresh = ws_ + "/fresh";
    const HeldLock lock(fresh + ".tmp-4242");
    const RunResult run = Rockcal("simulate " + Site() + " --rocks 2 --quiet --out " + fresh);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr(fresh + ": is in use by another rockcal run (pid 4242"));
    EXPECT_FALSE(fs::exists(fresh));
  }
  fs::remove_all(held);
  fs::remove_all(ws_ + "/fresh.tmp-4242");
}

// Issue 40: a log holding evaluations 1-2 twice, interleaved (two runs at
// once), was accepted by --resume.
TEST_F(Reliability, ALogWithTwoRunsLinesIsNotResumed) {
  const std::string twice = ws_ + "/twice";
  fs::copy(Cal(), twice, fs::copy_options::recursive);
  fs::remove(twice + "/calibration.json");
  std::ifstream in(twice + "/evaluations.jsonl");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_GE(lines.size(), 3u) << "a header and two evaluations";
  std::ofstream(twice + "/evaluations.jsonl") << lines[0] << "\n"
                                              << lines[1] << "\n"
                                              << lines[1] << "\n"
                                              << lines[2] << "\n"
                                              << lines[2] << "\n";
  const RunResult run =
      Rockcal("calibrate " + Site() + " --observations " + Obs() +
              " --rocks 4 --max-evals 2 --reach 0 --quiet --resume --out " + twice);
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_THAT(run.err, HasSubstr(twice + "/evaluations.jsonl:3: "));
  EXPECT_THAT(run.err, HasSubstr("evaluation 1 after its evaluation 1 (line 2)"));
  EXPECT_THAT(run.err, HasSubstr("two runs"));
  fs::remove_all(twice);
}

// Every file of `dir` (the lock too) with its bytes.
std::map<std::string, std::string> FolderBytes(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().string()] = ReadFile(e.path().string());
  return files;
}

// Appends a line break to `path` (its hash changes, its content does not)
// for the life of this object.
class Touched {
 public:
  explicit Touched(std::string path) : path_(std::move(path)), text_(ReadFile(path_)) {
    std::ofstream(path_, std::ios::app) << "\n";
  }
  ~Touched() { std::ofstream(path_, std::ios::trunc) << text_; }

 private:
  std::string path_, text_;
};

// Issue 56, cause 1: a refused --resume removed the finished result's
// calibration.json (campaign: summary.json), and a log with a duplicated
// line was refused only after the reach and noise checks were simulated
// again. Every refusal leaves the folder byte for byte as it was, before
// anything is simulated.
TEST_F(Reliability, ARefusedResumeChangesNothing) {
  const std::string calibrate = "calibrate " + Site() + " --observations " + Obs();
  const std::string done = ws_ + "/done";
  fs::copy(Cal(), done, fs::copy_options::recursive);
  ASSERT_TRUE(fs::exists(done + "/calibration.json"));
  const std::string resume =
      calibrate + " --rocks 4 --max-evals 2 --reach 0 --resume --out " + done;
  struct Case {
    std::string touched, extra, named;
  };
  for (const Case& c :
       std::vector<Case>{{"", " --seed 9", "changed since this log was written: seed"},
                         {ws_ + "/points/points.csv", "",
                          "changed since this log was written: site data "
                          "file ../points/points.csv"},
                         {ws_ + "/obscsv/heights.csv", "",
                          "changed since this log was written: observations "
                          "data file ../obscsv/heights.csv"}}) {
    SCOPED_TRACE(c.named);
    const std::map<std::string, std::string> before = FolderBytes(done);
    std::optional<Touched> touched;
    if (!c.touched.empty()) touched.emplace(c.touched);
    const RunResult run = Rockcal(resume + c.extra);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(
        run.err,
        HasSubstr(done + "/evaluations.jsonl:1: cannot resume: what determines the evaluations " +
                  c.named));
    EXPECT_TRUE(FolderBytes(done) == before) << "the refused resume changed " << done;
  }
  // The result is whole: table reads it.
  RunResult run = Rockcal("table " + done + " --out " + ws_ + "/done_table --quiet");
  EXPECT_EQ(run.status, 0) << run.err;
  fs::remove_all(ws_ + "/done_table");

  // Scanned shapes and an inventory (Authume): a changed shape file or
  // inventory is refused alike.
  const std::string ash = ws_ + "/ash";
  fs::copy(Examples() + "/authume", ash, fs::copy_options::recursive);
  Mark(ash);
  // Four of the 41 blocks (each fits its shape's clump when the site is
  // read, three reads here): the same files, a tenth of the work. `shape`:
  // the first block's shape file, an input of the run.
  std::string shape;
  {
    std::istringstream rows(ReadFile(ash + "/data/blocks_P1_shapes.csv"));
    std::string kept;
    int blocks = 0;
    for (std::string row; std::getline(rows, row) && blocks < 4;) {
      kept += row + "\n";
      if (row.empty() || !std::isdigit(static_cast<unsigned char>(row[0]))) continue;
      if (blocks++ == 0) shape = ash + "/data/shapes/" + row.substr(row.rfind(',') + 1);
    }
    Write(ash + "/data/blocks_P1_shapes.csv", kept);
  }
  ASSERT_TRUE(fs::exists(shape)) << shape;
  const std::string shapes = "calibrate " + ash + "/site_shapes.json --observations " + ash +
                             "/observations.json --rocks 4 --max-evals 2 --reach 0 --quiet --out " +
                             ws_ + "/ash_out";
  run = Rockcal(shapes);
  ASSERT_EQ(run.status, 0) << run.err;
  for (const std::string& file : {shape, ash + "/data/blocks_P1_shapes.csv"}) {
    SCOPED_TRACE(file);
    const std::map<std::string, std::string> before = FolderBytes(ws_ + "/ash_out");
    const Touched touched(file);
    run = Rockcal(shapes + " --resume");
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr("cannot resume: what determines the evaluations changed since "
                                   "this log was written: site data file data/" +
                                   fs::path(file).lexically_relative(ash + "/data").string()));
    EXPECT_TRUE(FolderBytes(ws_ + "/ash_out") == before) << "the refused resume changed it";
  }
  fs::remove_all(ash);
  fs::remove_all(ws_ + "/ash_out");

  // A log with a duplicated line, of a calibration with a reach and a noise
  // check: refused before either is simulated again (nothing printed).
  const std::string reach = ws_ + "/reach";
  run = Rockcal(calibrate + " --rocks 4 --max-evals 6 --quiet --out " + reach);
  ASSERT_EQ(run.status, 0) << run.err;
  std::vector<std::string> lines;
  {
    std::ifstream in(reach + "/evaluations.jsonl");
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_GE(lines.size(), 3u);
  {
    std::ofstream out(reach + "/evaluations.jsonl", std::ios::trunc);
    for (std::size_t k = 0; k < lines.size(); ++k)
      out << lines[k] << "\n" << (k == 2 ? lines[k] + "\n" : "");
  }
  std::map<std::string, std::string> before = FolderBytes(reach);
  run = Rockcal(calibrate + " --rocks 4 --max-evals 6 --resume --out " + reach);
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_THAT(run.err, HasSubstr(reach + "/evaluations.jsonl:4: "));
  EXPECT_THAT(run.err, HasSubstr("two runs"));
  EXPECT_EQ(run.out, "") << "nothing simulated before the refusal";
  EXPECT_TRUE(FolderBytes(reach) == before) << "the refused resume changed " << reach;
  fs::remove_all(reach);

  // A campaign whose member's observations changed keeps its summary.json.
  const std::string camp = ws_ + "/camp_out";
  const std::string campaign =
      "campaign " + ws_ + "/camp/campaign.json --rocks 2 --max-evals 2 --quiet --out " + camp;
  run = Rockcal(campaign);
  ASSERT_EQ(run.status, 0) << run.err;
  ASSERT_TRUE(fs::exists(camp + "/summary.json"));
  before = FolderBytes(camp);
  {
    const Touched touched(ws_ + "/camp/fan/observations.json");
    run = Rockcal(campaign + " --resume");
  }
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_THAT(run.err, HasSubstr("changed since this log was written: fan: observations file"));
  EXPECT_TRUE(FolderBytes(camp) == before) << "the refused resume changed " << camp;
  fs::remove_all(camp);
  fs::remove_all(done);
}

// Issue 40: a FIFO given as the site, the observations or a points_file
// blocked for ever; a folder given as a JSON file was "invalid JSON" at 1:1;
// 100,000 nested arrays crashed validate and simulate. Each is exit 2
// naming the file (`timeout` ends the run should it block again).
TEST_F(Reliability, SpecialFilesFoldersAndDeepJsonAreRefusedWithoutBlocking) {
  const std::string dir = ws_ + "/special";
  fs::create_directories(dir);
  const std::string fifo = dir + "/fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string site = ReadFile(Site());
  Replace(&site, "\"../points/points.csv\"", "\"" + fifo + "\"");
  Write(dir + "/fifo_points.json", site);
  const std::string deep = dir + "/deep.json";
  Write(deep, std::string(100000, '[') + std::string(100000, ']'));
  struct Case {
    std::string command, named, what;
  };
  const std::vector<Case> cases = {
      {"validate " + fifo, fifo, "is a FIFO (named pipe), expected a regular file"},
      {"validate " + Site() + " --observations " + fifo, fifo, "is a FIFO"},
      {"validate " + dir + "/fifo_points.json", fifo, "is a FIFO"},
      {"simulate " + Site() + " --parameters " + fifo + " --quiet --out " + dir + "/o", fifo,
       "is a FIFO"},
      {"validate /dev/zero", "/dev/zero", "is a character device"},
      {"validate " + dir, dir, "is a folder, expected a file"},
      {"validate " + Site() + " --observations " + ws_ + "/obs", ws_ + "/obs",
       "is a folder, expected a file"},
      {"validate " + deep, deep, "JSON nested 100000 levels deep"},
      {"simulate " + deep + " --quiet --out " + dir + "/o", deep, "JSON nested 100000 levels deep"},
      {"validate " + Site() + " --observations " + deep, deep, "JSON nested 100000 levels deep"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.command);
    const RunResult run =
        testing::Run("timeout --kill-after=5 20 " + std::string(ROCKCAL_EXE) + " " + c.command);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr(c.named + ": " + c.what));
  }
  EXPECT_FALSE(fs::exists(dir + "/o"));
  fs::remove_all(dir);
}

// Issue 56, causes 4 and 5: a --out of 300 characters (or over 4096) was
// "contains .../site.json, an input of this run"; a folder, a FIFO or a
// device as an observations CSV was "cannot open CSV file", a campaign
// member's observations folder "no such file". Each is exit 2 with the real
// reason, naming the file.
TEST_F(Reliability, LongNamesAndSpecialCsvFilesGetTheirRealReason) {
  const std::string dir = ws_ + "/special56";
  fs::create_directories(dir);
  for (const std::size_t length : {300u, 5000u}) {
    SCOPED_TRACE(length);
    const std::string out = dir + "/" + std::string(length, 'o');
    const RunResult run = Rockcal("simulate " + Site() + " --rocks 1 --quiet --out " + out);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr("File name too long"));
    EXPECT_THAT(run.err, Not(HasSubstr("an input of this run")));
  }

  const std::string fifo = dir + "/fifo.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string obs = ReadFile(Obs());
  struct Case {
    std::string file, what;
  };
  for (const Case& c : std::vector<Case>{{ws_ + "/obscsv", "is a folder, expected a file"},
                                         {fifo, "is a FIFO (named pipe), expected a regular file"},
                                         {"/dev/zero", "is a character device"},
                                         {"/dev/null", "is a character device"}}) {
    SCOPED_TRACE(c.file);
    std::string text = obs;
    Replace(&text, "\"../obscsv/heights.csv\"", "\"" + c.file + "\"");
    Write(dir + "/obs.json", text);
    const RunResult run =
        testing::Run("timeout --kill-after=5 20 " + std::string(ROCKCAL_EXE) + " validate " +
                     Site() + " --observations " + dir + "/obs.json");
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr(dir + "/obs.json: $.tree_scars[0].heights_file: '" + c.file +
                                   "' " + c.what));
  }

  // A campaign member whose observations are a folder.
  nlohmann::json campaign = nlohmann::json::parse(ReadFile(ws_ + "/camp/campaign.json"));
  campaign["sites"][0]["site"] = ws_ + "/camp/fan/site.json";
  campaign["sites"][0]["observations"] = ws_ + "/obs";
  campaign["sites"][1]["site"] = ws_ + "/camp/gully/site.json";
  campaign["sites"][1]["observations"] = ws_ + "/camp/gully/observations.json";
  Write(dir + "/campaign.json", campaign.dump(1));
  const RunResult run = Rockcal("campaign " + dir +
                                "/campaign.json --rocks 2 --max-evals 2 "
                                "--quiet --out " +
                                dir + "/o");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_THAT(run.err, HasSubstr(dir + "/campaign.json: $.sites[0].observations: '" + ws_ +
                                 "/obs' is a folder, expected a file"));
  EXPECT_FALSE(fs::exists(dir + "/o"));

  // Cause 6: a NUL in the site's name reached report.html raw; any control
  // character in a string is refused at read time, naming the JSON path.
  nlohmann::json site = nlohmann::json::parse(ReadFile(Site()));
  site["name"] = std::string("mi\0ni", 5);
  Write(ws_ + "/site/nul.json", site.dump(1));
  const RunResult nul =
      Rockcal("simulate " + ws_ + "/site/nul.json --rocks 1 --quiet --out " + dir + "/o");
  fs::remove(ws_ + "/site/nul.json");
  EXPECT_EQ(nul.status, 2) << nul.err;
  EXPECT_THAT(nul.err, HasSubstr("nul.json: $.name: holds the control character U+0000 at "
                                 "character 3"));
  EXPECT_FALSE(fs::exists(dir + "/o"));
  fs::remove_all(dir);
}

// Issue 40's smaller defects: --rocks with --refine was accepted; the site
// file allowed seeds to 2^63 - 1 but --seed only to 2^62; calibrate into a
// folder it cannot create exited 2 (bad input) where simulate exits 1; a
// failure to write the log did not say that --resume continues the folder.
TEST_F(Reliability, UsageSeedsAndExitClasses) {
  const std::string calibrate = "calibrate " + Site() + " --observations " + Obs() + " --quiet";
  RunResult run = Rockcal(calibrate + " --rocks 4 --refine 2 --out " + ws_ + "/r");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_THAT(run.err, HasSubstr("give --rocks N"));
  EXPECT_THAT(run.err, HasSubstr("or --refine F"));
  EXPECT_FALSE(fs::exists(ws_ + "/r"));
  // A method's name is parsed by the library's one table, before anything
  // runs; the error names the flag given.
  for (const auto& [flag, named] : std::vector<std::pair<std::string, std::string>>{
           {"--method nlopt:nope", "argument --method: unknown method 'nlopt:nope'"},
           {"--methods ceres,nope", "argument --methods: unknown method 'nope'"}}) {
    run = Rockcal(calibrate + " " + flag + " --out " + ws_ + "/r");
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_THAT(run.err, HasSubstr(named + " (allowed: nlopt:bobyqa, nlopt:sbplx, "));
    EXPECT_THAT(run.err, HasSubstr("nlopt:mlsl, ceres)"));
    EXPECT_FALSE(fs::exists(ws_ + "/r"));
  }

  const std::string out = ws_ + "/seed";
  run =
      Rockcal("simulate " + Site() + " --rocks 1 --seed 9223372036854775807 --quiet --out " + out);
  EXPECT_EQ(run.status, 0) << run.err;
  run = Rockcal("simulate " + Site() + " --rocks 1 --seed 9223372036854775808 --quiet --out " +
                out + "2");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_THAT(run.err, HasSubstr("'9223372036854775808' is not a whole number in [0, "
                                 "9223372036854775807]"));
  fs::remove_all(out);

  // /proc takes no folders: not bad input, a failure (exit 1) for both.
  for (const std::string& command : {calibrate + " --rocks 4 --max-evals 2 --reach 0",
                                     "simulate " + Site() + " --rocks 1 --quiet"}) {
    SCOPED_TRACE(command);
    run = Rockcal(command + " --out /proc/rockcal_reliability");
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_THAT(run.err, HasSubstr("rockcal: failed: cannot create the output folder "
                                   "/proc/rockcal_reliability"));
  }

  // A file size limit stops the log's writing half-way, as a full disk
  // would (SIGXFSZ ignored: the write fails with EFBIG). Issue 56: the
  // first failed append stops the run there (it went on to write the
  // results, and failed only at report.html); the lines before it stay.
  const std::string full = ws_ + "/full";
  run = testing::Run("/bin/sh -c \"trap '' XFSZ; ulimit -f 8; exec " + std::string(ROCKCAL_EXE) +
                     " " + calibrate + " --rocks 4 --max-evals 40 --reach 0 --out " + full + "\"");
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_THAT(run.err, HasSubstr("rockcal: failed: cannot write the evaluation log " + full +
                                 "/evaluations.jsonl: File too large; " + full +
                                 " keeps the evaluations logged so far"));
  EXPECT_THAT(run.err, HasSubstr("--resume"));
  EXPECT_FALSE(fs::exists(full + "/parameters.json"));
  EXPECT_FALSE(fs::exists(full + "/calibration.json"));
  {
    std::ifstream log(full + "/evaluations.jsonl");
    std::string line;
    int whole = 0;
    while (std::getline(log, line) && !log.eof()) ++whole;
    EXPECT_GE(whole, 3) << "the header and the evaluations before the failed write";
  }
  fs::remove_all(full);
}

}  // namespace
}  // namespace rockcal::cli
