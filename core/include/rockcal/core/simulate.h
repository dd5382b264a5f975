// The simulation loop: every rock of a scene, independently, in parallel.
#ifndef ROCKCAL_CORE_SIMULATE_H_
#define ROCKCAL_CORE_SIMULATE_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/core/statistics.h"

namespace rockcal::core {

enum class Outcome { kStopped, kLeft, kTimeout };
const char* OutcomeName(Outcome outcome);

struct Crossing {
  bool crossed = false;
  double height = 0.0;  // m, rock centre above the ground below it
  double speed = 0.0;   // m/s, translational
  double energy = 0.0;  // J, translational + rotational kinetic
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

struct TrajectorySample {
  double t;
  Eigen::Vector3d x, v, w;
  Eigen::Vector4d q;  // orientation quaternion (w, x, y, z); identity for spheres
};

// What a rock did over one cell of the site grid (cell (i, j) centred on
// grid node (i, j), index j * nx + i): its largest kinetic energy, centre
// height above the ground and speed there, sampled at every small step and
// at least every quarter cell along a flight.
struct CellVisit {
  int cell = 0;
  double height = 0.0;  // m, as Crossing::height
  double energy = 0.0;  // J, as Crossing::energy
  double speed = 0.0;   // m/s, as Crossing::speed (the centre's)
};

// One strike of a rock on a stem of Scene::forest: from the step its first
// element touched the trunk to the step none touched it any more (or the
// stem broke).
struct TreeStrike {
  int tree = 0;                                     // index in Forest::stems
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // rock centre at the first touch
  double height = 0.0;    // m, the contact point above the stem's foot
  double speed = 0.0;     // m/s, the rock's at the first touch
  double energy = 0.0;    // J, the rock's kinetic energy at the first touch
  double absorbed = 0.0;  // J, work the trunk's force took from the rock over the strike
  bool broken = false;    // the stem broke (its capacity reached) in this strike
};

struct RockRecord {
  int rock = 0, group = 0;
  Shape shape = Shape::kSphere;
  double size = 0.0, mass = 0.0;
  double bounding_radius = 0.0;  // m, centre to the farthest point of the rock (RockBody)
  Outcome outcome = Outcome::kTimeout;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d stop = Eigen::Vector3d::Zero();  // final centre position
  double time = 0.0;        // simulated seconds
  long steps = 0;           // contact (small) steps
  long gentle_steps = 0;    // of which at the gentle-contact step
  long retried_steps = 0;   // gentle steps taken back and redone at dt
  long flights = 0;         // exact free-flight advances
  double dt = 0.0;          // the rock's contact time step [s]
  double max_relative_energy_gain = 0.0;
  double max_penetration = 0.0;  // deepest overlap / element radius
  // The barrier (index into Scene::partitions: a Partition::Kind::kLine
  // that stops rocks) that stopped the rock, at its crossing; -1: none.
  int stopped_by = -1;
  bool tunneled = false;    // centre stayed below Terrain::FloorHeight by more than its radius for 2 t_c
  std::vector<Crossing> crossings;  // per partition, scene order (empty if not recorded)
  std::vector<Crossing> trees;      // per RecordOptions::trees entry; height = rock centre above ground
  std::vector<CellVisit> cells;     // cells its centre passed over, by cell (RecordOptions::passages)
  std::vector<TreeStrike> strikes;  // in time order (RecordOptions::tree_strikes)
  std::vector<TrajectorySample> trajectory;
};

// The figures of a run that add up over its rocks: what the engine did
// (steps, flights, the steps it chose) and its health checks (energy,
// overlap, non-finite and tunneled rocks). One rock's are OfRock; a run's
// are its rocks' summed with +=, whether the rocks ran in one block or in
// several (JoinRockBlocks, the ranks of an MPI run).
struct RunFigures {
  int rocks = 0;                             // rocks counted
  long steps = 0, flights = 0;               // contact steps, exact flights
  long gentle_steps = 0, retried_steps = 0;  // see RockRecord
  double dt_min = 0.0, dt_max = 0.0;         // contact steps used (0 without rocks)
  // Rocks whose step was cut below t_c/N_c for stability.
  int dt_shrunk = 0;
  // The largest relative energy gain of a rock with a finite state, and the
  // deepest overlap / element radius.
  double max_relative_energy_gain = 0.0, max_penetration = 0.0;
  int non_finite = 0;  // rocks whose state became non-finite (must be 0)
  int tunneled = 0;    // rocks that fell through the terrain

  // The figures of one rock (`shrunk`: its step was cut below t_c/N_c).
  static RunFigures OfRock(const RockRecord& rock, bool shrunk);
  // Adds `other`'s rocks: counts summed, the steps' range and the largest
  // gain and overlap widened; a figure of no rocks changes nothing.
  RunFigures& operator+=(const RunFigures& other);
};

// The replays of one observed impact (RecordOptions::impacts; core/impact_replay.h).
struct ImpactRebound {
  // Unit normal of the ground at the impact, pointing out of it.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  // m/s, each draw's velocity when in flight again (ImpactReplay::draws).
  std::vector<Eigen::Vector3d> velocity;
  // Per draw: 1 when it left the ground, 0 when it was still touching at the
  // replay's time limit (its velocity then is the one kept).
  std::vector<char> left;
};

struct SimulationResult {
  std::vector<RockRecord> rocks;  // in rock order
  // Per RecordOptions::impacts entry, in order (replayed with the block
  // holding rock 0: a run split in blocks carries them in its first).
  std::vector<ImpactRebound> impacts;
  RunFigures figures;             // of `rocks`
  double wall_seconds = 0.0;
  // Wall time the threads spent inside rocks, summed over rocks: at T
  // threads busy_seconds / (T wall_seconds) is the share of the run the
  // schedule kept every thread busy (1: no thread waited for another).
  double busy_seconds = 0.0;
  bool cells_recorded = false;  // RecordOptions::passages was on: RockRecord::cells hold the paths
  bool strikes_recorded = false;  // RecordOptions::tree_strikes was on in a forest: RockRecord::strikes hold them
  int count(Outcome o) const;
};

// The contact time step of a rock of `body` on `law` (and the stable bound it
// honours); sets *shrunk when the stability bound is below t_c / N_c.
double ContactTimeStep(const RockBody& body, const ContactLaw& law, const SimulationOptions& opt,
                       bool* shrunk = nullptr);
// The smallest contact step (ContactTimeStep) of any rock `group` can release
// (its lightest and heaviest bodies) on any material of `scene` and on its
// trunks (a forest); sets *shrunk when a stability bound cut one below
// t_c / N_c. Infinite without materials.
double GroupContactStep(const Scene& scene, const RockGroup& group, bool* shrunk = nullptr);
// The smallest contact step of any rock of `scene`: GroupContactStep's least
// over the groups (infinite without groups or materials). The one place the
// scene's finest step is worked out (the run-length check, the studies'
// step caps, `rockcal validate`).
double SmallestContactStep(const Scene& scene);

// The step of gentle contact (every contact's normal speed below g t_c:
// rolling, sliding, resting): t_c / gentle_steps_per_contact within the
// stability bound at SimulationOptions::gentle_safety of the critical step; 0
// when SimulationOptions::gentle_steps_per_contact is 0.
double GentleTimeStep(const RockBody& body, const ContactLaw& law, const SimulationOptions& opt);

// Called after each rock with (rocks done, rocks in all), one call at a time.
using ProgressFn = std::function<void(int, int)>;

// Runs every rock of the scene. Deterministic for a seed at any thread count.
SimulationResult Simulate(const Scene& scene);
// Same, reusing a terrain built for this scene's roughness (calibration).
SimulationResult Simulate(const Scene& scene, const Terrain& terrain,
                          const ProgressFn& progress = nullptr);

// Only rocks [first, last) of the scene (0 <= first <= last <=
// total_rocks()), each exactly as in the whole run (same index, same random
// stream): `rocks` holds their records in rock order, the totals are theirs
// and `progress` counts them. A distributed run simulates one such block per
// process and joins the blocks with JoinRockBlocks.
SimulationResult SimulateRocks(const Scene& scene, const Terrain& terrain, int first, int last,
                               const ProgressFn& progress = nullptr);

// Only rocks offset, offset + stride, offset + 2 stride, ... of the scene
// (0 <= offset < stride), each exactly as in the whole run (same index, same
// random stream), in rock order: the rocks a run whose values change from
// rock to rock in `stride` turns gives to one set of values (rockcal
// simulate of a posterior, calibrate/posterior_draws.h).
SimulationResult SimulateEveryNthRock(const Scene& scene, const Terrain& terrain, int offset,
                                      int stride, const ProgressFn& progress = nullptr);

// The result of consecutive blocks of SimulateRocks (in rock order) as
// Simulate gives it for the whole run: records appended, totals summed or
// taken as min / max (wall_seconds: the largest block's; a caller timing
// the whole run sets it).
SimulationResult JoinRockBlocks(std::vector<SimulationResult> blocks);

// Builds the terrain for a scene (virtual spheres from material roughness).
Terrain BuildTerrain(const Scene& scene);

// Per-partition and runout statistics of a result.
struct PartitionStats {
  std::string id;
  int passed = 0;
  Stats height, velocity, energy;  // m, m/s, J
};
// The runout of one rock (docs/reference/outputs.md#runout): the distance
// in plan (x, y) from its centre at release to its centre where it stopped,
// or where it was last seen (a rock that left the terrain or was still
// moving at the time limit) [m]; and its travel angle, the energy-line
// angle atan(drop / plan distance) of the centre from release to that point
// [degrees; 90 for a rock that did not move in plan].
double RunoutDistance(const RockRecord& rock);
double TravelAngleDeg(const RockRecord& rock);

// The runout of every rock of a run. A rock that left the terrain went
// beyond its edge: it ranks past every rock that stayed (the longest
// distances, the lowest travel angles), and a figure that falls among those
// rocks is infinite (BeyondStats): +infinity for the distance, -infinity
// for the angle. Rocks still moving at the time limit count at their last
// point.
struct RunoutStats {
  int rocks = 0;                 // every rock of the run
  int beyond_edge = 0;           // of which left the terrain
  BeyondStats distance_m;        // RunoutDistance; beyond above
  BeyondStats travel_angle_deg;  // TravelAngleDeg; beyond below
};
RunoutStats ComputeRunout(const std::vector<RockRecord>& rocks);

// A fence of `height` [m] and energy `capacity` [J] checked where the rocks
// crossed one partition (docs/reference/outputs.md#barrier-check): a rock
// flies over it when its lowest point, its centre's height above the
// ground less its bounding radius (RockRecord::bounding_radius: the lowest
// any orientation of the rock could reach), is above the fence; it breaks
// through when its kinetic energy exceeds the capacity. Beside it, the
// counts by the centre (a partition's bounce height) and by the rock's top
// (centre plus bounding radius: a rock that reaches the fence's top edge,
// which a fence does not catch reliably; a designer's freeboard).
struct FenceCheck {
  int passed = 0;          // rocks that crossed the partition
  int over = 0;            // of which flew over the fence (by the lowest point)
  int over_by_centre = 0;  // of which had their centre above it (what CRSP compares)
  int over_by_top = 0;     // of which had their top above it
  int over_capacity = 0;   // of which carried more energy than the capacity
  int defeated = 0;        // over or over capacity
};
FenceCheck CheckFence(const SimulationResult& result, std::size_t partition, double height,
                      double capacity);

// What a barrier (a Partition::Kind::kLine, docs/reference/outputs.md#barrierscsv)
// met: the rocks that reached its line and, by its height and capacity,
// CheckFence's counts (passed: reaching; over: by the lowest point; over
// capacity), the rocks it stopped (a barrier that `stops`), and the 95th
// and 99th percentiles (type 7) of what the rocks carried at the crossing:
// the lowest point's height above the ground (centre height less bounding
// radius), the centre's and the kinetic energy. The percentiles are NaN
// when no rock reached it.
struct BarrierStats {
  std::size_t partition = 0;  // index into Scene::partitions
  FenceCheck check;
  int stopped = 0;
  double lowest_p95 = 0.0, lowest_p99 = 0.0;  // m
  double centre_p95 = 0.0, centre_p99 = 0.0;  // m
  double energy_p95 = 0.0, energy_p99 = 0.0;  // J
};
// One entry per barrier of the scene, in partition order (empty without).
std::vector<BarrierStats> ComputeBarriers(const Scene& scene, const SimulationResult& result);

struct ResultStats {
  std::vector<PartitionStats> partitions;
  Stats runout_x;      // m, stop x of stopped rocks only (a coordinate, not a distance)
  RunoutStats runout;  // every rock
};
ResultStats ComputeStats(const Scene& scene, const SimulationResult& result);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SIMULATE_H_
