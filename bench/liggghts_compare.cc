// rockcal against a general DEM engine (LIGGGHTS) on the benchmark slope of
// slope_scene.h, with an X partition at x = 60 m.
//
// 1. Runs rockcal at 1 and at 2 threads (median wall of `runs` runs each) and
//    records the bounce height of each rock crossing the partition and where
//    the stopped rocks came to rest.
// 2. Writes a LIGGGHTS input deck into a fresh temporary folder: the virtual
//    spheres of every grid node as frozen particles, the catch surface under
//    them as an STL mesh wall, and the rocks at rockcal's start points with
//    rockcal's sizes and masses, with the contact law as close to rockcal's as
//    LIGGGHTS allows (see WriteInput and bench/README.md).
// 3. Runs `liggghts` on one core (if it is on PATH), times it, reads its
//    trajectories (every 0.01 s) and final state, and prints both engines'
//    runout and bounce-height quantiles side by side, each with a Monte Carlo
//    standard error, and whether they agree within two combined errors.
//
//   liggghts_compare [rocks=200] [runs=5]
#include <stdlib.h>  // mkdtemp
#include <unistd.h>  // access

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rockcal/core/material.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "slope_scene.h"
#include "timing.h"

namespace {

using namespace rockcal;

constexpr double kPartitionX = 60.0;     // m, the X partition (on the slope, ~50 m below release)
constexpr double kSampleSeconds = 0.01;  // LIGGGHTS trajectory dump interval [s]
constexpr double kCheckSeconds = 0.5;    // LIGGGHTS runs in chunks of this, checking for rest
constexpr double kFrozenDensity =
    1e12;                          // kg/m^3: terrain particles heavy enough that m_eff = m_rock
constexpr double kSkin = 0.2;      // m, LIGGGHTS neighbour skin
constexpr double kLongRun = 30.0;  // s: LIGGGHTS runs longer than this are repeated 3 times at most
constexpr double kVeryLongRun = 300.0;  // s: ... and longer than this only once
// m past the partition where a gate-only run takes a rock out: beyond the
// reach of any virtual sphere (radius 6 m) a rock before the partition can
// touch, so the spheres there go too.
constexpr double kGateMargin = 15.0;

// What the comparison needs from either engine.
struct EngineResult {
  std::vector<double> runout;   // stop x of the stopped rocks [m]
  std::vector<double> heights;  // bounce heights at the partition [m]
  std::vector<double> speeds;   // speeds there [m/s] (LIGGGHTS: interpolated between frames)
  // Gate clearance at the partition: the normal distance of the rock's
  // lowest point above the plane through the slope's nodes (issue 36) [m].
  std::vector<double> clearances;
  int stopped = 0, left = 0,
      moving = 0;  // moving: rockcal's timeout; LIGGGHTS: still fast at the end
};

// The normal clearance of a sphere of radius a centred at c above the plane
// through the slope's nodes (slope_scene.h: z = (toe - x) tan theta).
double Clearance(const Eigen::Vector3d& c, double a) {
  const double th = bench::kSlopeDegrees * M_PI / 180.0;
  return (c.x() - bench::kSlopeToeX) * std::sin(th) + c.z() * std::cos(th) - a;
}

EngineResult FromRockcal(const core::SimulationResult& result) {
  EngineResult out;
  for (const core::RockRecord& r : result.rocks) {
    if (!r.crossings.empty() && r.crossings[0].crossed) {
      out.heights.push_back(r.crossings[0].height);
      out.speeds.push_back(r.crossings[0].speed);
      out.clearances.push_back(Clearance(r.crossings[0].point, 0.5 * r.size));
    }
    switch (r.outcome) {
      case core::Outcome::kStopped:
        ++out.stopped;
        out.runout.push_back(r.stop.x());
        break;
      case core::Outcome::kLeft:
        ++out.left;
        break;
      case core::Outcome::kTimeout:
        ++out.moving;
        break;
    }
  }
  return out;
}

bool FindOnPath(const std::string& name, std::string* found) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0 && !std::filesystem::is_directory(candidate)) {
      *found = candidate;
      return true;
    }
  }
  return false;
}

// ---- the LIGGGHTS deck -----------------------------------------------------

struct Deck {
  std::string dir;
  int terrain_atoms = 0;
  int rock_atoms = 0;
  int chunks = 0;  // at most this many runs of kCheckSeconds
  int chunk_steps = 0;
  double dt = 0.0;
  double time_limit = 0.0;  // s simulated at most
  // Gate only (issue 36): a rock is taken out of the run once it is
  // kGateMargin past the partition, and the run ends when none is left:
  // only the partition's figures are compared, at a fraction of the cost.
  bool gate_only = false;
  double kn_median = 0.0;  // N/m, normal stiffness of the median rock
};

// Atom types: 1 = the virtual spheres, 2 = the catch surface mesh, 3 + k = rock
// k (one type per rock, so that its stiffness can follow its mass).
constexpr int kTerrainType = 1;
constexpr int kCatchType = 2;
constexpr int kFirstRockType = 3;

void WriteData(const Deck& deck, const core::Scene& scene, const core::Terrain& terrain,
               const core::SimulationResult& result) {
  const double density = scene.groups[0].unit_weight / scene.gravity;
  double xlo = terrain.xmin() - 1.0, xhi = terrain.xmax() + 1.0;
  double ylo = terrain.ymin() - 1.0, yhi = terrain.ymax() + 1.0;
  double zlo = 0.0, zhi = 0.0;
  const int nodes = scene.grid.nx * scene.grid.ny;
  for (int n = 0; n < nodes; ++n) {
    const Eigen::Vector3d& c = terrain.sphere_centre(n);
    const double r = terrain.sphere_radius(n);
    xlo = std::min(xlo, c.x() - r - 1.0);
    xhi = std::max(xhi, c.x() + r + 1.0);
    ylo = std::min(ylo, c.y() - r - 1.0);
    yhi = std::max(yhi, c.y() + r + 1.0);
    zlo = std::min(zlo, c.z() - r - 1.0);
    zhi = std::max(zhi, c.z() + r);
  }
  for (const core::RockRecord& r : result.rocks) zhi = std::max(zhi, r.start.z());
  zhi += 40.0;  // room to bounce; a rock above it would be lost
  std::ofstream f(deck.dir + "/data.slope");
  f.precision(10);
  f << "rockcal bench/liggghts_compare: virtual spheres (type 1) and rocks (types 3..)\n\n"
    << deck.terrain_atoms + deck.rock_atoms << " atoms\n"
    << kFirstRockType - 1 + deck.rock_atoms << " atom types\n\n"
    << xlo << " " << xhi << " xlo xhi\n"
    << ylo << " " << yhi << " ylo yhi\n"
    << zlo << " " << zhi << " zlo zhi\n\nAtoms\n\n";
  // atom-ID atom-type diameter density x y z
  for (int n = 0; n < nodes; ++n) {
    const Eigen::Vector3d& c = terrain.sphere_centre(n);
    f << n + 1 << " " << kTerrainType << " " << 2.0 * terrain.sphere_radius(n) << " "
      << kFrozenDensity << " " << c.x() << " " << c.y() << " " << c.z() << "\n";
  }
  for (std::size_t k = 0; k < result.rocks.size(); ++k) {
    const core::RockRecord& r = result.rocks[k];
    f << deck.terrain_atoms + static_cast<int>(k) + 1 << " " << kFirstRockType + static_cast<int>(k)
      << " " << r.size << " " << density << " " << r.start.x() << " " << r.start.y() << " "
      << r.start.z() << "\n";
  }
}

// The catch surface (core/terrain.cc): the grid's triangulation with each node
// lowered to Terrain::FloorHeight, split along the (i, j)-(i+1, j+1) diagonal
// like the terrain, as an ASCII STL. LIGGGHTS' cost per mesh contact grows with
// the triangles around it, so where the surface does not vary across y (an
// extruded profile, like the benchmark slope) runs of collinear profile
// segments are merged into one rectangle each: the same surface, exactly, in
// far fewer triangles. Returns the number of triangles.
int WriteCatchStl(const Deck& deck, const core::Terrain& terrain) {
  const core::HeightGrid& g = terrain.grid();
  std::vector<double> h(static_cast<std::size_t>(g.nx) * g.ny);
  // The last row and column are queried a nanometre inside the grid: at
  // their exact coordinates (x - x0) / spacing may round above nx - 1 (at
  // 2.4575 m, 34 * s / s > 34), which Terrain takes for off the slope
  // (-inf). The facets are planar, so the height moves by about 1e-9 m.
  constexpr double kInside = 1e-9;  // m
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      h[g.index(i, j)] = terrain.FloorHeight(g.x(i) - (i == g.nx - 1 ? kInside : 0.0),
                                             g.y(j) - (j == g.ny - 1 ? kInside : 0.0));
  constexpr double kTolerance = 1e-9;  // m
  bool profile = true;
  for (int j = 1; j < g.ny && profile; ++j)
    for (int i = 0; i < g.nx && profile; ++i)
      profile = std::abs(h[g.index(i, j)] - h[g.index(i, 0)]) <= kTolerance;

  std::ofstream f(deck.dir + "/catch.stl");
  f.precision(12);
  f << "solid catch\n";
  int triangles = 0;
  auto facet = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    f << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\nouter loop\n";
    for (const Eigen::Vector3d* p : {&a, &b, &c})
      f << "vertex " << p->x() << " " << p->y() << " " << p->z() << "\n";
    f << "endloop\nendfacet\n";
    ++triangles;
  };
  auto node = [&](int i, int j) { return Eigen::Vector3d(g.x(i), g.y(j), h[g.index(i, j)]); };
  if (profile) {
    const double y0 = g.y(0), y1 = g.y(g.ny - 1);
    int i0 = 0;
    for (int i1 = 1; i1 < g.nx; ++i1) {
      // Extend the segment [i0, i1] while the next node stays on its line.
      if (i1 + 1 < g.nx) {
        const double slope = (h[g.index(i1, 0)] - h[g.index(i0, 0)]) / (g.x(i1) - g.x(i0));
        const double predicted = h[g.index(i1, 0)] + slope * (g.x(i1 + 1) - g.x(i1));
        if (std::abs(predicted - h[g.index(i1 + 1, 0)]) <= kTolerance) continue;
      }
      const Eigen::Vector3d a(g.x(i0), y0, h[g.index(i0, 0)]), b(g.x(i1), y0, h[g.index(i1, 0)]);
      const Eigen::Vector3d c(g.x(i1), y1, h[g.index(i1, 0)]), d(g.x(i0), y1, h[g.index(i0, 0)]);
      facet(a, b, c);
      facet(a, c, d);
      i0 = i1;
    }
  } else {
    for (int j = 0; j + 1 < g.ny; ++j)
      for (int i = 0; i + 1 < g.nx; ++i) {
        facet(node(i, j), node(i + 1, j), node(i + 1, j + 1));
        facet(node(i, j), node(i + 1, j + 1), node(i, j + 1));
      }
  }
  f << "endsolid catch\n";
  return triangles;
}

// One peratomtypepair matrix, a row per line.
template <typename Value>
void WriteTypePairProperty(std::ofstream& f, const char* id, const char* name, int types,
                           Value value) {
  f << "fix " << id << " all property/global " << name << " peratomtypepair " << types << " &\n";
  for (int i = 1; i <= types; ++i) {
    for (int j = 1; j <= types; ++j) f << " " << value(i, j);
    f << (i < types ? " &\n" : "\n");
  }
}

void WriteInput(const Deck& deck, const core::Scene& scene, const core::Terrain& terrain,
                const core::SimulationResult& result, const core::ContactLaw& law) {
  const int types = kFirstRockType - 1 + deck.rock_atoms;
  const double sphere_r = terrain.sphere_radius(0);
  auto mass = [&](int type) {
    return result.rocks[static_cast<std::size_t>(type - kFirstRockType)].mass;
  };
  auto radius = [&](int type) {
    return 0.5 * result.rocks[static_cast<std::size_t>(type - kFirstRockType)].size;
  };
  auto is_rock = [](int type) { return type >= kFirstRockType; };
  // k_n = m (pi^2 + ln^2 e) / t_c^2 of the rock in the pair (rock-rock pairs are
  // excluded from the neighbour lists; they get a symmetric placeholder).
  auto kn = [&](int i, int j) {
    if (is_rock(i) && is_rock(j)) return law.stiffness_per_mass * std::sqrt(mass(i) * mass(j));
    if (is_rock(i)) return law.stiffness_per_mass * mass(i);
    if (is_rock(j)) return law.stiffness_per_mass * mass(j);
    return deck.kn_median;
  };
  // cdt's torque is mu_r k_n delta r_eff with r_eff = a r / (a + r) against a
  // particle and a against a wall; rockcal's is mu_r a N.
  auto rolling = [&](int i, int j) {
    const int rock = is_rock(i) ? i : j;
    const int other = is_rock(i) ? j : i;
    if (!is_rock(rock) || other != kTerrainType) return law.rolling_resistance;
    return law.rolling_resistance * (radius(rock) + sphere_r) / sphere_r;
  };

  std::ofstream f(deck.dir + "/in.slope");
  f.precision(10);
  f << "# Written by rockcal bench/liggghts_compare: " << scene.name << ", " << deck.rock_atoms
    << " sphere rocks.\n"
    << "# Virtual spheres: frozen particles of type 1; catch surface: mesh wall of type 2;\n"
    << "# rock k: type " << kFirstRockType << "+k. Linear spring-dashpot (hooke/stiffness) with\n"
    << "# k_n = m_rock (pi^2 + ln^2 e) / t_c^2 per rock type, damping gamma_n = C/m times m_eff\n"
    << "# (rockcal's damping for e = " << law.restitution << " with the force clamped at zero),\n"
    << "# tangential spring k_t = " << law.tangential_ratio
    << " k_n with Coulomb cap f = " << law.friction << ", no tangential damping,\n"
    << "# rolling resistance cdt with mu_r = " << law.rolling_resistance
    << " (scaled by (a + r) / r against the spheres).\n"
    << "atom_style granular\n"
    << "atom_modify map array\n"
    << "boundary f f f\n"
    << "newton off\n"
    << "communicate single vel yes\n"
    << "units si\n"
    << "read_data data.slope\n"
    << "group terrain type " << kTerrainType << "\n"
    << "group rocks subtract all terrain\n"
    << "neighbor " << kSkin << " bin\n"
    << "neigh_modify delay 0 every 1 check yes exclude group terrain terrain exclude group rocks "
       "rocks\n";
  WriteTypePairProperty(f, "kn", "kn", types, kn);
  WriteTypePairProperty(f, "kt", "kt", types,
                        [&](int i, int j) { return law.tangential_ratio * kn(i, j); });
  WriteTypePairProperty(f, "gn", "gamman", types, [&](int, int) { return law.damping_per_mass; });
  WriteTypePairProperty(f, "gt", "gammat", types, [](int, int) { return 0.0; });
  WriteTypePairProperty(f, "cof", "coefficientFriction", types,
                        [&](int, int) { return law.friction; });
  WriteTypePairProperty(f, "corf", "coefficientRollingFriction", types, rolling);
  // The same law for the spheres (pair) and the catch surface (wall); the
  // wall takes the model keywords after the mesh.
  const char* model = "model hooke/stiffness tangential history rolling_friction cdt";
  const char* keywords = "limitForce on tangential_damping off absolute_damping off";
  f << "pair_style gran " << model << " " << keywords << "\n"
    << "pair_coeff * *\n"
    << "fix catch all mesh/surface file catch.stl type " << kCatchType << "\n"
    << "fix catchwall rocks wall/gran " << model << " mesh n_meshes 1 meshes catch " << keywords
    << "\n"
    << "timestep " << deck.dt << "\n"
    << "fix gravity rocks gravity " << scene.gravity << " vector 0 0 -1\n"
    << "fix freeze terrain freeze\n"
    << "fix integrate rocks nve/sphere\n"
    << "variable speed atom sqrt(vx*vx+vy*vy+vz*vz)\n"
    << "compute vmax rocks reduce max v_speed\n"
    << "variable vmax equal c_vmax\n"
    << "thermo_style custom step atoms c_vmax\n"
    << "thermo " << deck.chunk_steps << "\n"
    << "thermo_modify lost ignore norm no\n"
    << "dump trajectories rocks custom " << std::lround(kSampleSeconds / deck.dt)
    << " traj.dump id x y z vx vy vz\n"
    // Runs in chunks; stops early once every rock is slower than the stop
    // speed at two chunk ends in a row (rockcal: 1 s below it).
    << "variable slow equal 0\n"
    << "region beyond block " << kPartitionX + kGateMargin << " INF INF INF INF INF units box\n"
    << "variable nrocks equal count(rocks)\n"
    << "variable chunk loop " << deck.chunks << "\n"
    << "label next_chunk\n"
    << "run " << deck.chunk_steps << "\n";
  if (deck.gate_only)
    f << "delete_atoms region beyond compress no\n"
      << "if \"${nrocks} == 0\" then \"jump SELF finish\"\n";
  f << "if \"${vmax} < " << scene.options.stop_speed
    << "\" then \"variable slow equal ${slow}+1\" else \"variable slow equal 0\"\n"
    << "if \"${slow} >= 2\" then \"jump SELF finish\"\n"
    << "next chunk\n"
    << "jump SELF next_chunk\n"
    << "label finish\n"
    << "write_dump rocks custom final.dump id x y z vx vy vz\n";
}

// ---- running LIGGGHTS and reading its output -------------------------------

struct LiggghtsRun {
  bool ok = false;
  double wall = 0.0;       // s, process wall time
  double loop_time = 0.0;  // s, sum of LIGGGHTS' "Loop time"
  long steps = 0;
  double rock_steps = 0.0;  // sum over the chunks of steps x rock atoms left at the chunk end
};

LiggghtsRun RunLiggghts(const std::string& exe, const Deck& deck) {
  LiggghtsRun run;
  // The screen output goes to a file: LIGGGHTS 3.8 crashes reading a mesh
  // with "-screen none".
  const std::string command = "cd '" + deck.dir + "' && OMP_NUM_THREADS=1 '" + exe +
                              "' -in in.slope -log log.liggghts -nocite > screen.liggghts 2>&1";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0) return run;
  std::ifstream log(deck.dir + "/log.liggghts");
  std::string line;
  while (std::getline(log, line)) {
    // "Loop time of T on P procs for N steps with M atoms ..."
    double t = 0.0;
    int procs = 0;
    long steps = 0, atoms = 0;
    if (std::sscanf(line.c_str(), "Loop time of %lf on %d procs for %ld steps with %ld atoms", &t,
                    &procs, &steps, &atoms) == 4) {
      run.loop_time += t;
      run.steps += steps;
      run.rock_steps +=
          static_cast<double>(steps) * static_cast<double>(atoms - deck.terrain_atoms);
    }
  }
  run.ok = run.steps > 0;
  return run;
}

// Reads traj.dump (positions every kSampleSeconds) and final.dump. A rock has
// left when its centre was off the grid in any frame or it was lost; one at
// rest at the end (speed below the stop speed) has stopped; others are moving.
// The bounce height at the partition is the centre's height above the ground
// a rock touches (Terrain::GroundHeight, the top of the virtual spheres, as
// rockcal's crossings measure it) where the path between two frames first
// crosses it.
EngineResult ReadLiggghtsResult(const Deck& deck, const core::Scene& scene,
                                const core::Terrain& terrain,
                                const core::SimulationResult& result) {
  struct Track {
    bool seen = false, left = false, crossed = false;
    Eigen::Vector3d last = Eigen::Vector3d::Zero(), last_v = Eigen::Vector3d::Zero();
  };
  std::map<long, Track> tracks;
  std::ifstream traj(deck.dir + "/traj.dump");
  std::string line;
  long step = -1, last_step = -1;
  bool atoms = false, skip = false;
  EngineResult out;
  while (std::getline(traj, line)) {
    if (line.rfind("ITEM:", 0) == 0) {
      atoms = line.rfind("ITEM: ATOMS", 0) == 0;
      if (line.rfind("ITEM: TIMESTEP", 0) == 0 && std::getline(traj, line)) {
        step = std::atol(line.c_str());
        skip = step <= last_step;  // a run's first frame repeats the previous run's last
        if (!skip) last_step = step;
      }
      continue;
    }
    if (!atoms || skip) continue;
    long id = 0;
    double x, y, z, vx, vy, vz;
    if (std::sscanf(line.c_str(), "%ld %lf %lf %lf %lf %lf %lf", &id, &x, &y, &z, &vx, &vy, &vz) !=
        7)
      continue;
    Track& t = tracks[id];
    const Eigen::Vector3d p(x, y, z), v(vx, vy, vz);
    if (t.left) continue;
    if (!terrain.OnSlope(x, y)) {
      t.left = true;
      continue;
    }
    if (t.seen && !t.crossed && ((t.last.x() - kPartitionX < 0) != (x - kPartitionX < 0))) {
      const double f = (t.last.x() - kPartitionX) / (t.last.x() - x);
      const Eigen::Vector3d c = t.last + f * (p - t.last);
      double ground = c.z();
      terrain.GroundHeight(c.x(), c.y(), &ground);
      out.heights.push_back(c.z() - ground);
      out.speeds.push_back((t.last_v + f * (v - t.last_v)).norm());
      const long k = id - deck.terrain_atoms - 1;
      if (k >= 0 && k < static_cast<long>(result.rocks.size()))
        out.clearances.push_back(
            Clearance(c, 0.5 * result.rocks[static_cast<std::size_t>(k)].size));
      t.crossed = true;
    }
    t.seen = true;
    t.last = p;
    t.last_v = v;
  }
  std::map<long, Eigen::Vector3d> final_x, final_v;
  std::ifstream fin(deck.dir + "/final.dump");
  atoms = false;
  while (std::getline(fin, line)) {
    if (line.rfind("ITEM:", 0) == 0) {
      atoms = line.rfind("ITEM: ATOMS", 0) == 0;
      continue;
    }
    long id = 0;
    double x, y, z, vx, vy, vz;
    if (atoms && std::sscanf(line.c_str(), "%ld %lf %lf %lf %lf %lf %lf", &id, &x, &y, &z, &vx, &vy,
                             &vz) == 7) {
      final_x[id] = Eigen::Vector3d(x, y, z);
      final_v[id] = Eigen::Vector3d(vx, vy, vz);
    }
  }
  for (int k = 0; k < deck.rock_atoms; ++k) {
    const long id = deck.terrain_atoms + k + 1;
    const auto it = final_x.find(id);
    if (it == final_x.end() || tracks[id].left ||
        !terrain.OnSlope(it->second.x(), it->second.y())) {
      ++out.left;
    } else if (final_v[id].norm() < scene.options.stop_speed) {
      ++out.stopped;
      out.runout.push_back(it->second.x());
    } else {
      ++out.moving;
    }
  }
  return out;
}

// ---- printing ---------------------------------------------------------------

void PrintComparisonRow(const char* label, const std::vector<double>& a,
                        const std::vector<double>& b, double p) {
  const bench::QuantileEstimate qa = bench::EstimateQuantile(a, p),
                                qb = bench::EstimateQuantile(b, p);
  if (!qa.valid || !qb.valid) {
    std::printf("%-18s %22s %22s   (too few values)\n", label, "-", "-");
    return;
  }
  const double diff = qb.value - qa.value;
  const double tol = 2.0 * std::hypot(qa.se, qb.se);
  std::printf("%-18s %10.2f +- %-8.2f %10.2f +- %-8.2f %8.2f %8.2f  %s\n", label, qa.value, qa.se,
              qb.value, qb.se, diff, tol, std::abs(diff) <= tol ? "yes" : "NO");
}

// ---- the three parts of the comparison ---------------------------------------

// rockcal at 1 and 2 threads, `runs` times each.
struct RockcalRuns {
  bench::TimedRuns timed[2];
  bool same = false;          // identical results at 1 and 2 threads
  double max_time = 0.0;      // s, the longest rock's simulated time
  double rock_seconds = 0.0;  // s, simulated time summed over the rocks
};

RockcalRuns RunRockcal(const core::Scene& scene, const core::Terrain& terrain, int runs) {
  RockcalRuns out;
  std::printf("rockcal (median of %d runs)\n", runs);
  std::printf("%-8s %10s %12s %9s %14s %18s %9s\n", "threads", "wall_s", "steps", "flights",
              "rock_steps/s", "fixed_dt_equiv/s", "speed-up");
  bench::TimedRuns* timed = out.timed;
  for (int k = 0; k < 2; ++k) {
    const int threads = k + 1;
    timed[k] = bench::TimeSimulation(scene, terrain, threads, runs);
    const core::SimulationResult& r = timed[k].result;
    const double w = timed[k].median_wall;
    char speedup[32] = "";
    if (k == 1) std::snprintf(speedup, sizeof speedup, "%.2fx", timed[0].median_wall / w);
    std::printf("%-8d %10.3f %12ld %9ld %14.3g %18.3g %9s\n", threads, w, r.figures.steps,
                r.figures.flights, r.figures.steps / w, bench::FixedStepRockSteps(r) / w, speedup);
    std::fflush(stdout);
  }
  const core::SimulationResult& result = timed[0].result;
  bool same = result.rocks.size() == timed[1].result.rocks.size();
  for (std::size_t k = 0; same && k < result.rocks.size(); ++k)
    same = result.rocks[k].stop == timed[1].result.rocks[k].stop &&
           result.rocks[k].outcome == timed[1].result.rocks[k].outcome;
  out.same = same;
  for (const core::RockRecord& r : result.rocks) {
    out.max_time = std::max(out.max_time, r.time);
    out.rock_seconds += r.time;
  }
  std::printf(
      "identical results at 1 and 2 threads: %s; contact step %.3g s; simulated rock time "
      "%.1f s in all, longest rock %.2f s\n\n",
      same ? "yes" : "NO", result.figures.dt_max, out.rock_seconds, out.max_time);
  return out;
}

// Writes the LIGGGHTS deck of rockcal's run `result` into a fresh temporary
// folder; false when the folder cannot be made.
bool MakeDeck(const core::Scene& scene, const core::Terrain& terrain,
              const core::SimulationResult& result, const core::ContactLaw& law, double max_time,
              int dt_divisor, bool gate_only, Deck* deck) {
  const std::string dir_name =
      (std::filesystem::temp_directory_path() / "rockcal_liggghts_XXXXXX").string();
  std::vector<char> dir_buffer(dir_name.begin(), dir_name.end());
  dir_buffer.push_back('\0');
  const char* made = ::mkdtemp(dir_buffer.data());
  if (made == nullptr) return false;
  deck->dir = made;
  deck->terrain_atoms = scene.grid.nx * scene.grid.ny;
  deck->gate_only = gate_only;
  deck->rock_atoms = static_cast<int>(result.rocks.size());
  deck->dt = result.figures.dt_max / dt_divisor;  // t_c / N_c for every rock of this scene, / K
  deck->chunk_steps = static_cast<int>(std::lround(kCheckSeconds / deck->dt));
  deck->chunks = static_cast<int>(std::ceil(max_time / kCheckSeconds - 1e-9));
  deck->time_limit = deck->chunks * deck->chunk_steps * deck->dt;
  {
    std::vector<double> masses;
    for (const core::RockRecord& r : result.rocks) masses.push_back(r.mass);
    deck->kn_median = law.stiffness_per_mass * bench::Median(masses);
  }
  WriteData(*deck, scene, terrain, result);
  const int triangles = WriteCatchStl(*deck, terrain);
  WriteInput(*deck, scene, terrain, result, law);
  std::printf(
      "LIGGGHTS deck: %s/in.slope (%d frozen virtual spheres, %d rocks, %d atom types: "
      "k_n per rock mass; catch surface mesh %d triangles);\n"
      "  dt %.3g s, at most %.2f s simulated (rockcal's longest rock), stopping early once "
      "every rock is below %.2g m/s at two checks %.2g s apart\n",
      deck->dir.c_str(), deck->terrain_atoms, deck->rock_atoms,
      kFirstRockType - 1 + deck->rock_atoms, triangles, deck->dt, deck->time_limit,
      scene.options.stop_speed, kCheckSeconds);
  std::fflush(stdout);
  return true;
}

// LIGGGHTS on the deck, `runs` times (fewer when a run is long).
struct LiggghtsRuns {
  bool ok = false;
  LiggghtsRun first;
  int planned = 0;
  double wall = 0.0, loop = 0.0;  // medians [s]
};

LiggghtsRuns RunLiggghtsRepeatedly(const std::string& exe, const Deck& deck, int runs) {
  LiggghtsRuns out;
  std::vector<double> walls, loops;
  out.planned = runs;
  for (int r = 0; r < out.planned; ++r) {
    const LiggghtsRun run = RunLiggghts(exe, deck);
    if (!run.ok) return out;
    if (r == 0) {
      out.first = run;
      if (run.wall > kVeryLongRun) {
        out.planned = 1;
      } else if (run.wall > kLongRun) {
        out.planned = std::min(runs, 3);
      }
    }
    walls.push_back(run.wall);
    loops.push_back(run.loop_time);
  }
  out.ok = true;
  out.wall = bench::Median(walls);
  out.loop = bench::Median(loops);
  return out;
}

void PrintSideBySide(const EngineResult& ours, const EngineResult& theirs) {
  std::printf("%-18s %22s %22s %8s %8s  %s\n", "", "rockcal", "LIGGGHTS", "diff", "2se", "agree");
  std::printf("%-18s %22d %22d\n", "rocks stopped", ours.stopped, theirs.stopped);
  std::printf("%-18s %22d %22d\n", "rocks left", ours.left, theirs.left);
  std::printf("%-18s %22d %22d\n", "timeout / moving", ours.moving, theirs.moving);
  std::printf("%-18s %22zu %22zu\n", "crossed X60", ours.heights.size(), theirs.heights.size());
  auto below = [](const std::vector<double>& h) {
    return std::count_if(h.begin(), h.end(), [](double v) { return v < 0.0; });
  };
  std::printf("%-18s %22ld %22ld\n", "  centre below gnd", static_cast<long>(below(ours.heights)),
              static_cast<long>(below(theirs.heights)));
  PrintComparisonRow("runout x p10 [m]", ours.runout, theirs.runout, 0.10);
  PrintComparisonRow("runout x p50 [m]", ours.runout, theirs.runout, 0.50);
  PrintComparisonRow("runout x p90 [m]", ours.runout, theirs.runout, 0.90);
  PrintComparisonRow("clearance p10 [m]", ours.clearances, theirs.clearances, 0.10);
  PrintComparisonRow("clearance p50 [m]", ours.clearances, theirs.clearances, 0.50);
  PrintComparisonRow("clearance p90 [m]", ours.clearances, theirs.clearances, 0.90);
  PrintComparisonRow("height p50 [m]", ours.heights, theirs.heights, 0.50);
  PrintComparisonRow("height p90 [m]", ours.heights, theirs.heights, 0.90);
  PrintComparisonRow("height p95 [m]", ours.heights, theirs.heights, 0.95);
  PrintComparisonRow("speed p50 [m/s]", ours.speeds, theirs.speeds, 0.50);
  PrintComparisonRow("speed p90 [m/s]", ours.speeds, theirs.speeds, 0.90);
}

}  // namespace

int main(int argc, char** argv) {
  const int rocks = argc > 1 ? std::atoi(argv[1]) : 200;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  // Variants of the scene (issue 13, finding 10): grid spacing [m], friction
  // and rolling resistance on both sides (negative: the hardness model's),
  // rockcal's steps per contact N_c, and LIGGGHTS' step as rockcal's / K.
  const double spacing = argc > 3 ? std::atof(argv[3]) : 12 * core::kFoot;
  const double friction = argc > 4 ? std::atof(argv[4]) : -1.0;
  const double rolling = argc > 5 ? std::atof(argv[5]) : -1.0;
  const int steps_per_contact = argc > 6 ? std::atoi(argv[6]) : 50;
  const int liggghts_divisor = argc > 7 ? std::atoi(argv[7]) : 1;
  const double max_time = argc > 8 ? std::atof(argv[8]) : 60.0;
  const bool reference_path = argc > 9 && std::string(argv[9]) == "reference";
  const double restitution = argc > 10 ? std::atof(argv[10]) : -1.0;
  const bool gate_only = argc > 11 && std::string(argv[11]) == "gate";
  if (rocks < 2 || runs < 1 || !(spacing > 0.5) || steps_per_contact < 10 || liggghts_divisor < 1 ||
      !(max_time > 0)) {
    std::fprintf(stderr,
                 "usage: liggghts_compare [rocks=200] [runs=5] [spacing_m=3.6576] "
                 "[friction=model] [rolling_resistance=model] [N_c=50] [liggghts_dt_divisor=1] "
                 "[max_time_s=60] [production|reference] [restitution=model] [all|gate]\n"
                 "(rocks >= 2, runs >= 1, spacing > 0.5, N_c >= 10, divisor >= 1, max_time > 0; "
                 "a negative friction or rolling resistance keeps the hardness model's)\n");
    return 2;
  }
  core::Scene scene = bench::SlopeScene(rocks, spacing);
  if (friction >= 0) scene.materials[0].friction = friction;
  if (rolling >= 0) scene.materials[0].rolling_resistance = rolling;
  if (restitution > 0) scene.materials[0].restitution = restitution;
  scene.options.steps_per_contact = steps_per_contact;
  scene.options.max_time = max_time;
  scene.options.reference_path = reference_path;
  scene.partitions.push_back({"X60", core::Partition::Kind::kX, kPartitionX});
  const core::Terrain terrain = core::BuildTerrain(scene);
  const core::ContactLaw law = core::DeriveContactLaw(scene.materials[0], scene.hardness_model);

  std::printf("liggghts_compare: %s, %d sphere rocks (0.6-1.2 m), partition X60 at x = %.0f m\n",
              scene.name.c_str(), rocks, kPartitionX);
  std::printf(
      "contact law: e %.3f  t_c %.4g s  k_n/m %.6g 1/s^2  C/m %.6g 1/s (zeta %.4f)  "
      "k_s/k_n %.4f  f %.3f  mu_r %.3f\n\n",
      law.restitution, law.contact_time, law.stiffness_per_mass, law.damping_per_mass,
      law.damping_ratio, law.tangential_ratio, law.friction, law.rolling_resistance);

  const RockcalRuns rockcal = RunRockcal(scene, terrain, runs);
  const core::SimulationResult& result = rockcal.timed[0].result;
  const EngineResult ours = FromRockcal(result);
  for (const double p : {0.5, 0.9, 0.95}) {
    const bench::QuantileEstimate q = bench::EstimateQuantile(ours.heights, p);
    if (q.valid)
      std::printf("rockcal height p%.0f at X60: %.2f +- %.2f m (%zu rocks crossed)\n", 100 * p,
                  q.value, q.se, ours.heights.size());
  }
  for (const double p : {0.1, 0.5, 0.9}) {
    const bench::QuantileEstimate q = bench::EstimateQuantile(ours.clearances, p);
    if (q.valid)
      std::printf("rockcal clearance p%.0f at X60: %.2f +- %.2f m\n", 100 * p, q.value, q.se);
  }

  std::string exe;
  if (!FindOnPath("liggghts", &exe)) {
    std::printf("liggghts is not on PATH: no comparison (rockcal figures above only).\n");
    return 0;
  }
  Deck deck;
  if (!MakeDeck(scene, terrain, result, law, rockcal.max_time, liggghts_divisor, gate_only,
                &deck)) {
    std::fprintf(stderr, "liggghts_compare: cannot create a temporary folder\n");
    return 1;
  }
  const LiggghtsRuns lig = RunLiggghtsRepeatedly(exe, deck, runs);
  if (!lig.ok) {
    std::printf("liggghts failed (see %s/log.liggghts): no comparison.\n", deck.dir.c_str());
    return 1;
  }
  const EngineResult theirs = ReadLiggghtsResult(deck, scene, terrain, result);
  std::filesystem::remove(deck.dir + "/traj.dump");
  if (lig.planned < runs)
    std::printf(
        "LIGGGHTS runs: %d instead of %d (the first took %.1f s; more than %.0f s gives "
        "at most 3 runs, more than %.0f s one)\n",
        lig.planned, runs, lig.first.wall, kLongRun, kVeryLongRun);
  if (deck.gate_only) {
    // Terrain atoms are deleted with the rocks: the atom count no longer
    // tells the rocks left.
    std::printf(
        "LIGGGHTS (1 core, median of %d runs, gate only): wall %.2f s (Loop time %.2f s), %ld "
        "steps (%.2f s simulated)\n",
        lig.planned, lig.wall, lig.loop, lig.first.steps, lig.first.steps * deck.dt);
  } else {
    std::printf(
        "LIGGGHTS (1 core, median of %d runs): wall %.2f s (Loop time %.2f s), %ld steps "
        "(%.2f s simulated) x rock atoms = %.4g rock-steps, %.3g rock-steps/s\n",
        lig.planned, lig.wall, lig.loop, lig.first.steps, lig.first.steps * deck.dt,
        lig.first.rock_steps, lig.first.rock_steps / lig.wall);
  }
  if (!deck.gate_only)
    std::printf(
        "simulated rock time: rockcal %.0f rock-s (each rock until it stops or leaves), "
        "LIGGGHTS %.0f rock-s (every rock for the whole run)\n",
        rockcal.rock_seconds, lig.first.rock_steps * deck.dt);
  std::printf("wall-time ratio LIGGGHTS / rockcal: %.1fx at 1 thread, %.1fx at 2 threads\n\n",
              lig.wall / rockcal.timed[0].median_wall, lig.wall / rockcal.timed[1].median_wall);
  PrintSideBySide(ours, theirs);
  std::printf(
      "se: order-statistic standard error (half the spread of the sample quantiles at p -/+ "
      "sqrt(p(1-p)/n));\nagree: |diff| <= 2 sqrt(se_rockcal^2 + se_LIGGGHTS^2). Deck and log "
      "kept in %s\n",
      deck.dir.c_str());
  return 0;
}
