// Tracked trajectories as observations (tracks_file): the reader's bad
// inputs, and a twin experiment through the production recorder: tracks
// sampled from a simulation at known values give a small misfit at those
// values and a larger one away from them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../core/scene_fixtures.h"
#include "file_fixture.h"
#include "rockcal/core/error.h"
#include "rockcal/core/random.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"

namespace rockcal::observations {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// A 30 degree slope (z = -tan 30 x) with gentle bumps, 80 m x 40 m, one
// material of hardness `e`; group "a" releases spheres of 0.6-1.0 m from
// a 4 m x 10 m zone 1 m above the ground at the top.
core::Scene TwinScene(double e) {
  const double slope = std::tan(30.0 * 3.14159265358979323846 / 180.0);
  core::Scene scene = core::testing::GridScene(
      41, 21, 2.0,
      [slope](double x, double y) {
        return -slope * x + 0.4 * std::sin(0.7 * x) * std::cos(0.5 * y);
      },
      core::testing::SmoothMaterial(e, 0.005, 0.4, 0.05));
  core::RockGroup a = core::testing::PointGroup(core::Shape::kSphere, 0.6, 0, 0, 1.0, 8);
  a.id = "a";
  a.size_max = 1.0;
  a.release.zone = {Eigen::Vector2d(4, 15), Eigen::Vector2d(8, 15), Eigen::Vector2d(8, 25),
                    Eigen::Vector2d(4, 25)};
  scene.groups = {a};
  scene.options.max_time = 8.0;
  return scene;
}

class TracksTest : public testing::FileTest {
 protected:
  // The error LoadObservations gives for these tracks ("" when none), with
  // runs "a" and "b" of the flat scene below.
  std::string TracksError(const std::string& tracks_csv,
                          const std::string& error = R"({"runout": 2, "track": 0.02,
                              "impact_speed": 0.5})") const {
    Write("runs.csv", "id,group,stop_x,stop_y\na,g,50,20\nb,g,60,20\n");
    Write("tracks.csv", tracks_csv);
    try {
      LoadObservations(Write("obs.json", R"({"units": "si", "runs_file": "runs.csv",
                                 "tracks_file": "tracks.csv", "error": )" +
                                             error + "}"),
                       FlatScene());
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  static core::Scene FlatScene() {
    core::Scene scene = core::testing::FlatScene(core::testing::SmoothMaterial(0.5, 0.005, 0.4));
    scene.grid.spacing = 5.0;  // 100 m x 100 m
    core::RockGroup g = core::testing::PointGroup(core::Shape::kSphere, 1.0, 10, 20, 1.0);
    g.id = "g";
    scene.groups = {g};
    return scene;
  }
};

// Two flights of a point over level ground z = 0: 1 s each, 5 m/s along x,
// sampled at 20 Hz, as rows "run,t,x,y,z" of run `run`.
std::string Hops(const std::string& run) {
  std::ostringstream s;
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.05 * k, tau = t < 1.0 ? t : t - 1.0;
    s << run << "," << t << "," << 5.0 * t << ",20," << 0.5 + 4.9 * tau - 4.903325 * tau * tau
      << "\n";
  }
  return s.str();
}

TEST_F(TracksTest, ReadsTracksAndFindsTheirFlights) {
  Write("runs.csv", "id,group,stop_x,stop_y\na,g,50,20\nb,g,60,20\n");
  Write("tracks.csv", "run,t,x,y,z\n" + Hops("a") + Hops("b"));
  const Observations obs = LoadObservations(
      Write("obs.json", R"({"units": "si", "runs_file": "runs.csv", "tracks_file": "tracks.csv",
        "error": {"runout": 2, "track": 0.02, "impact_speed": 0.5}})"),
      FlatScene());
  ASSERT_TRUE(obs.tracks);
  ASSERT_EQ(obs.tracks->tracks.size(), 2u);
  EXPECT_NEAR(obs.tracks->sample_seconds, 0.05, 1e-12);
  EXPECT_EQ(obs.tracks->flight.noise, 0.02);
  for (const Track& t : obs.tracks->tracks) {
    // Each track: two flights of 5 m whose centres rise 1.224 m above 0.5 m
    // (v^2 / 2g for 4.9 m/s), one impact at 4.907 m/s down and 5 m/s along.
    ASSERT_EQ(t.jump_heights.size(), 2u) << t.run;
    EXPECT_NEAR(t.jump_heights[0], 0.5 + 4.9 * 4.9 / (2 * 9.80665), 0.01);
    EXPECT_NEAR(t.jump_lengths[0], 5.0, 0.01);
    ASSERT_EQ(t.impact_speeds.size(), 1u);
    EXPECT_NEAR(t.impact_speeds[0], std::hypot(5.0, 4.9 - 9.80665), 0.01);
  }
  EXPECT_EQ(obs.error.track, 0.02);
  EXPECT_EQ(obs.error.impact_speed, 0.5);
  // The tracked runs' groups are recorded, sampled as the tracks were.
  const core::RecordOptions record = RequiredRecording(obs, {});
  EXPECT_EQ(record.trajectory_groups, (std::vector<int>{0}));
  EXPECT_NEAR(record.sample_seconds, 0.05, 1e-12);
  // --holdout: a track goes with its run, into the fold that holds it out.
  const std::vector<Fold> folds = MakeFolds(obs, 2, 7);
  for (const Fold& fold : folds)
    for (const bool held_out : {false, true}) {
      const Observations part = Subset(obs, fold, held_out);
      ASSERT_TRUE(part.runout && part.tracks) << fold.index << " " << held_out;
      ASSERT_EQ(part.runout->run_ids.size(), 1u);
      ASSERT_EQ(part.tracks->tracks.size(), 1u);
      EXPECT_EQ(part.tracks->tracks[0].run, part.runout->run_ids[0]);
    }
}

// The impacts the detector finds in the tracks, written as an impacts file:
// each hop's impact at t = 1 s, x = 5 m, z = 0.5 + 4.9 - g / 2 m, in at
// (5, 0, 4.9 - g) m/s and out at (5, 0, 4.9) m/s, in the file's units.
TEST_F(TracksTest, DetectedImpactsAreWrittenAsAnImpactsFile) {
  Write("runs.csv", "id,group,stop_x,stop_y\na,g,50,20\nb,g,60,20\n");
  Write("tracks.csv", "run,t,x,y,z\n" + Hops("a") + Hops("b"));
  for (const std::string units : {"si", "us"}) {
    const double unit = units == "si" ? 1.0 : 0.3048;  // m per file unit
    if (units == "us") {                               // the same hops in feet
      std::ostringstream ft;
      ft.precision(12);
      ft << "run,t,x,y,z\n";
      std::istringstream in(Hops("a") + Hops("b"));
      std::string line;
      while (std::getline(in, line)) {
        std::istringstream row(line);
        std::string run, t, x, y, z;
        std::getline(row, run, ',');
        std::getline(row, t, ',');
        std::getline(row, x, ',');
        std::getline(row, y, ',');
        std::getline(row, z, ',');
        ft << run << "," << t << "," << std::stod(x) / unit << "," << std::stod(y) / unit << ","
           << std::stod(z) / unit << "\n";
      }
      Write("tracks.csv", ft.str());
    }
    const Observations obs =
        LoadObservations(Write("obs.json", R"({"units": ")" + units + R"(", "runs_file": "runs.csv",
          "tracks_file": "tracks.csv", "error": {"runout": 2, "track": 0.02,
          "impact_speed": 0.5}})"),
                         FlatScene());
    std::istringstream csv(DetectedImpactsCsv(obs, FlatScene()));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out");
    const double expected[9] = {5, 20, 0.5 + 4.9 - 9.80665 / 2, 5, 0, 4.9 - 9.80665, 5, 0, 4.9};
    int rows = 0;
    while (std::getline(csv, line)) {
      std::istringstream row(line);
      std::string id, group, field;
      std::getline(row, id, ',');
      std::getline(row, group, ',');
      EXPECT_EQ(id, rows == 0 ? "a-1" : "b-1");
      EXPECT_EQ(group, "g");
      for (int k = 0; k < 9 && std::getline(row, field, ','); ++k)
        EXPECT_NEAR(std::stod(field) * unit, expected[k], k < 3 ? 0.01 : 0.05)
            << units << " row " << rows << " column " << k << ": " << line;
      ++rows;
    }
    EXPECT_EQ(rows, 2) << units;
  }
}

TEST_F(TracksTest, BadTracksNameTheFileLineAndColumn) {
  const std::string header = "run,t,x,y,z\n";
  EXPECT_THAT(TracksError(header + Hops("a") + "c,0,1,2,3\n"),
              AllOf(HasSubstr("tracks.csv:43"), HasSubstr("column 'run'"),
                    HasSubstr("'c' is not a run given"), HasSubstr("a, b")));
  EXPECT_THAT(
      TracksError(header + "a,0,1,20,1\na,0.1,2,20,1\na,0.1,3,20,1\n"),
      AllOf(HasSubstr("tracks.csv:4"), HasSubstr("column 't'"), HasSubstr("does not come after")));
  EXPECT_THAT(TracksError(header + Hops("a") + "a,nan,1,20,1\n"),
              AllOf(HasSubstr("tracks.csv:43"), HasSubstr("'t'")));
  EXPECT_THAT(TracksError(header + Hops("a") + "a,3,1,20,NaN\n"),
              AllOf(HasSubstr("tracks.csv:43"), HasSubstr("'z'")));
  EXPECT_THAT(TracksError(header + Hops("a") + "b,0,1,20,1\nb,0.1,2,20,1\n"),
              AllOf(HasSubstr("tracks.csv:43"), HasSubstr("run 'b' has 2 samples"),
                    HasSubstr("at least 4")));
  EXPECT_THAT(TracksError("run,time,x,y,z\n" + Hops("a")),
              AllOf(HasSubstr("tracks.csv:1"), HasSubstr("no column 't'")));
  EXPECT_THAT(TracksError(header + Hops("a") + "a,3,1,20\n"),
              AllOf(HasSubstr("tracks.csv:43"), HasSubstr("expected 5 values")));
  EXPECT_THAT(TracksError(header), HasSubstr("no data rows"));
  EXPECT_THAT(TracksError(header + Hops("a"), R"({"runout": 2, "track": 0.02})"),
              HasSubstr("missing required key 'impact_speed'"));
  // A track that never leaves the ground: no flight to compare.
  std::string rolling = header;
  for (int k = 0; k < 40; ++k) rolling += "a," + std::to_string(0.05 * k) + ",1,20,0.5\n";
  EXPECT_THAT(TracksError(rolling), AllOf(HasSubstr("tracks.csv"), HasSubstr("0 flights")));
  // Tracks without runs.
  Write("tracks.csv", header + Hops("a"));
  try {
    LoadObservations(Write("obs.json", R"({"units": "si", "runout": {"distances": [1, 2],
        "from": [0, 0], "direction": [1, 0]}, "tracks_file": "tracks.csv",
        "error": {"runout": 2, "track": 0.02, "impact_speed": 0.5}})"),
                     FlatScene());
    ADD_FAILURE() << "tracks without runs were accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("$.tracks_file"), HasSubstr("'runs' or 'runs_file'")));
  }
}

// The twin: "observed" tracks are the paths of 32 rocks simulated at
// hardness 0.45 (seed 11) through the production recorder, sampled at 25 Hz
// with 1 cm of noise added; the misfit simulates 128 other rocks (seed 5).
// At the true value every track residual lies within 3 sigma; at 0.25 and at
// 0.7 the tracks' misfit is at least twice as large (measured: 6.7 at 0.45,
// 18.1 at 0.25, 57.0 at 0.7).
TEST_F(TracksTest, TwinTracksFitAtTheTrueValueOnly) {
  constexpr double kTrue = 0.45, kNoise = 0.01;
  core::Scene truth = TwinScene(kTrue);
  truth.options.seed = 11;
  truth.groups[0].count = 32;
  truth.options.record.trajectory_groups = {0};
  truth.options.record.sample_seconds = 0.04;
  truth.options.record.partitions = false;
  const core::SimulationResult seen = core::Simulate(truth);
  std::ostringstream runs, tracks;
  tracks.precision(10);
  runs << "id,group,stop_x,stop_y\n";
  tracks << "run,t,x,y,z\n";
  core::RandomStream noise(3, 1);
  for (const core::RockRecord& rock : seen.rocks) {
    const std::string id = "r" + std::to_string(rock.rock);
    // On the terrain, for the reader (only the tracks are compared here).
    runs << id << ",a," << std::clamp(rock.stop.x(), 1.0, 79.0) << ","
         << std::clamp(rock.stop.y(), 1.0, 39.0) << "\n";
    for (const core::TrajectorySample& s : rock.trajectory)
      tracks << id << "," << s.t << "," << s.x.x() + kNoise * noise.Normal() << ","
             << s.x.y() + kNoise * noise.Normal() << "," << s.x.z() + kNoise * noise.Normal()
             << "\n";
  }
  Write("runs.csv", runs.str());
  Write("tracks.csv", tracks.str());
  const Observations obs = LoadObservations(
      Write("obs.json", R"({"units": "si", "runs_file": "runs.csv", "tracks_file": "tracks.csv",
        "error": {"runout": 1, "track": 0.01, "impact_speed": 0.3}})"),
      truth);
  ASSERT_TRUE(obs.tracks);
  auto misfit = [&](double e) {
    core::Scene scene = TwinScene(e);
    scene.groups[0].count = 128;
    scene.options.seed = 5;
    scene.options.record = RequiredRecording(obs, scene.options.record);
    MisfitOptions options;
    options.run_terms = RunTerms::kPooled;
    Misfit m = ComputeMisfit(obs, scene, core::Simulate(scene), options);
    // The tracks' part alone.
    double value = 0.0;
    for (const Residual& r : m.residuals)
      if (r.id.kind == ObservationKind::kTracks) value += 0.5 * r.value * r.value;
    m.value = value;
    return m;
  };
  const Misfit at_truth = misfit(kTrue);
  int compared = 0;
  for (const Residual& r : at_truth.residuals) {
    if (r.id.kind != ObservationKind::kTracks) continue;
    ++compared;
    EXPECT_LT(std::abs(r.value), 3.0)
        << r.id.observation() << " " << r.id.quantity() << ": " << r.simulated << " against "
        << r.observed << " (sigma " << r.sigma << ")";
  }
  EXPECT_EQ(compared, 9) << at_truth.Report();
  EXPECT_EQ(at_truth.tracks.tracks, 32);
  EXPECT_EQ(at_truth.tracks.rocks, 128);
  EXPECT_FALSE(at_truth.penalised) << at_truth.message;
  for (const double e : {0.25, 0.7}) {
    const Misfit off = misfit(e);
    EXPECT_GT(off.value, 2.0 * at_truth.value)
        << "hardness " << e << ": " << off.Report() << "\nat " << kTrue << ": " << at_truth.value;
  }
  EXPECT_THAT(TracksVerdictSentence(at_truth), HasSubstr("tracks: the jumps are reproduced"));
}

}  // namespace
}  // namespace rockcal::observations
