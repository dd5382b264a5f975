// A scene: everything the simulator needs, in SI units. Built by sites/.
#ifndef ROCKCAL_CORE_SCENE_H_
#define ROCKCAL_CORE_SCENE_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/core/clump.h"
#include "rockcal/core/forest.h"
#include "rockcal/core/material.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

constexpr double kStandardGravity = 9.80665;  // m/s^2
constexpr double kFoot = 0.3048;              // m

// An X partition is the vertical plane x = value; a Z partition is the line
// where the ground elevation equals value; a Line partition is a barrier
// drawn in plan (docs/reference/site-file.md#barriers): a polyline of
// `line`, crossed where the rock centre's plan path meets one of its
// segments, with the barrier's height and energy capacity. A barrier that
// `stops` ends the run of a rock that reaches it below its height (by the
// rock's lowest point: centre height less bounding radius) and at or below
// its capacity, at the crossing (docs/physics.md#barriers).
struct Partition {
  enum class Kind { kX, kZ, kLine };
  std::string id;
  Kind kind = Kind::kX;
  double value = 0.0;  // m (kX: x; kZ: elevation)
  // kLine only:
  std::vector<Eigen::Vector2d> line = {};  // m, plan vertices (at least 2)
  double height = 0.0;                     // m, above the ground
  double capacity = 0.0;                   // J, kinetic energy it withstands
  bool stops = false;                      // stops the rocks it catches
};

// Where the plan segment p0 -> p1 first meets the polyline `line` (at least
// 2 vertices): true and *f, the fraction along p0 -> p1 in (0, 1], when it
// does. A path that touches the line only at p0 (f = 0) does not cross it.
bool CrossesLine(const std::vector<Eigen::Vector2d>& line, const Eigen::Vector2d& p0,
                 const Eigen::Vector2d& p1, double* f);

struct Release {
  std::vector<Eigen::Vector2d> zone;  // plan polygon; empty means `point`
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  double height = 0.0;  // m, of the rock's lowest point above the ground
  // m, absolute elevation of the rock's lowest point (a surveyed drop), used
  // instead of `height` when set; a rock is never placed below the ground.
  std::optional<double> elevation;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // m/s, mean
  // m/s, one-sigma spread of each velocity component (normal draws); 0: none.
  Eigen::Vector3d velocity_spread = Eigen::Vector3d::Zero();
  // rad/s, angular velocity at release (world axes). Not a site file key:
  // code only (the oblique-impact tests release spinning rocks).
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  // Orientation of a cluster at release (body axes to world); unset: uniformly
  // random. Its draws are made either way, so setting it moves no other draw.
  std::optional<Eigen::Quaterniond> orientation;
};

// One block of a field inventory: its shape (a box of its measured sides, or
// a named shape of size L1) and its mass.
struct Block {
  Shape shape = Shape::kBox;
  Eigen::Vector3d sides = Eigen::Vector3d::Ones();  // m, L1 >= L2 >= L3
  double mass = 0.0;                                // kg
  // Shape::kScanned: the shape, already fitted at the block's size (its
  // body is ScannedBody(*scanned, 1, mass)).
  std::shared_ptr<const ScannedShape> scanned = nullptr;
};

struct RockGroup {
  // The group's name in the site file ("id"; empty when not given): what a
  // per-run observation names to tie its stop point to this release.
  std::string id;
  int count = 1;
  Shape shape = Shape::kSphere;
  double size_min = 1.0, size_max = 1.0;  // m, uniform in range
  double unit_weight = 25.9e3;            // N/m^3
  // Shape::kBox: the sides' proportions L1 : L2 : L3 (size is L1).
  Eigen::Vector3d box = Eigen::Vector3d::Ones();
  // A field inventory: when not empty, the group's rocks are these blocks in
  // turn (rock k of the group is block k mod the inventory's size), so a
  // count equal to the inventory's size releases each block once, and a
  // multiple of it each block as often.
  std::vector<Block> inventory;
  // Shape::kScanned without an inventory: the shape at scale 1; a rock of
  // size s (its L1) is the shape scaled by s / its L1, mass from unit_weight.
  std::shared_ptr<const ScannedShape> scanned = nullptr;
  Release release;
};

// The body of the rock with index `index` within `group`, whose size draw is
// u in [0, 1) (a size in the range; an inventory's block is set by index).
RockBody GroupRockBody(const RockGroup& group, int index, double u, double gravity);
// The smallest and the largest element radius and mass a group can release.
struct GroupExtent {
  RockBody lightest, heaviest;
  double max_element_radius = 0.0;
};
GroupExtent GroupBodies(const RockGroup& group, double gravity);

// The scanned shapes of a scene, one entry per shape name (file stem), in
// name order: how many rocks' bodies use it (a group of a size range
// counts once) and the worst fit of its clumps.
struct ShapeUse {
  std::string name, file;
  const ScannedShape* first = nullptr;  // the first fit met (for drawings)
  int uses = 0;
  int spheres = 0;
  double volume_error = 0.0, moment_error = 0.0, side_error = 0.0;  // worst (absolute)
  double min_volume = 0.0, max_volume = 0.0;                        // hull volumes, m^3
};
// A tree (vertical trunk) where scar heights were measured: a rock whose
// bounding sphere first reaches the trunk records its height there.
struct TreeProbe {
  double x = 0.0, y = 0.0;  // m
  double radius = 0.0;      // trunk radius [m]
};

// One observed impact to replay (RecordOptions::impacts; core/impact_replay.h,
// docs/physics.md "Replayed impacts"): a rock of `group` at `centre` arriving
// at `velocity_in`, replayed `draws` times with drawn orientations (and spins,
// unless `spin` is set).
struct ImpactReplay {
  int group = 0;                                          // index into Scene::groups
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();       // m, rock centre at the impact
  Eigen::Vector3d velocity_in = Eigen::Vector3d::Zero();  // m/s, incoming
  std::optional<Eigen::Vector3d> spin;                    // rad/s, measured incoming spin
  int draws = 16;                                         // replays, 1 to kMaxImpactDraws
};
constexpr int kMaxImpactDraws = 1000;

// What the simulation records; the misfit and reports ask only for what they use.
struct RecordOptions {
  bool partitions = true;    // crossings at partitions
  bool energy_check = true;  // track the largest relative energy gain
  std::vector<TreeProbe> trees;  // record passages at these trees
  bool passages = false;     // the cells each rock passed over (RockRecord::cells; core/rasters.h)
  bool tree_strikes = false;  // each strike on a stem of Scene::forest (RockRecord::strikes)
  int trajectories = 0;      // record the path of the first N rocks
  // and the paths of these rocks (indices in the run, ascending): a sample
  // of every group for a report's profile (SpreadOverGroups)
  std::vector<int> trajectory_rocks;
  // and the paths of every rock of these groups (indices into
  // Scene::groups, ascending): the tracked runs' rocks, for the tracks'
  // misfit (docs/field-campaigns.md, section 6), whatever the rock count
  std::vector<int> trajectory_groups;
  double sample_seconds = 0.05;  // trajectory sampling interval
  // Observed impacts replayed after the rocks (SimulationResult::impacts).
  std::vector<ImpactReplay> impacts;
};

struct SimulationOptions {
  std::uint64_t seed = 1;
  double max_time = 60.0;        // s of simulated time per rock
  double stop_speed = 0.1;       // m/s
  double stop_duration = 1.0;    // s below stop_speed to count as stopped
  int steps_per_contact = 50;    // N_c: dt <= t_c / N_c
  // Gentle contact (every contact's normal speed below g t_c: rolling,
  // sliding, resting; most contact steps of a run) needs no impact
  // resolution: it steps at t_c / this (within the same stability bound). A
  // long step that meets a contact that is not gentle is taken back and redone
  // at dt. 0 turns it off (every contact step t_c / N_c). 10 is as close to
  // the fine reference as 20 was on every example (bench/README.md).
  int gentle_steps_per_contact = 10;
  double safety = 0.2;  // fraction of the critical step 2 / omega
  // The same for the gentle step, which needs stability only, not the
  // resolution of an impact (a box landing flat on 16 elements rebounds 3 %
  // short at safety 0.5): the stability suite passes on every example at
  // gentle_safety 0.5 and 1.0; 0.5 keeps a factor of two.
  double gentle_safety = 0.5;
  // A rock at rest ends without waiting out stop_duration: once every point
  // of it has stayed slower than a tenth of stop_speed for rest_window s,
  // touching the slope with no contact at its Coulomb cap, and is now slower
  // than when it became so (not tipping out of a balance), it is taken to
  // stay at rest, and it ends "stopped" at the time its slow spell reaches
  // stop_duration, where it lies. 0 turns it off (as does the reference
  // path).
  double rest_window = 0.1;      // s
  bool exact_flight = true;      // advance free flight exactly between contacts
  // Runs every rock on the general path with every lever off: spheres as
  // one-element clusters, every contact step t_c / N_c, no exact flight, no
  // neighbour list (the candidate spheres of the element's cell and the floor
  // tested every step). The reference the fast paths are checked against.
  bool reference_path = false;
  int threads = 0;               // 0: OpenMP default
  RecordOptions record;

  // Checks single fields and pairs; on failure sets *error (naming the field,
  // its value and the rule) and returns false.
  bool IsValid(std::string* error) const;
};

struct Scene {
  std::string name;
  HeightGrid grid;
  std::vector<Material> materials;
  HardnessModel hardness_model;
  std::vector<Partition> partitions;
  std::vector<RockGroup> groups;
  Forest forest;  // stems the rocks strike; empty: a bare slope (costs nothing)
  SimulationOptions options;
  double gravity = kStandardGravity;

  int total_rocks() const;
  // The scanned shapes of the groups (empty without any).
  std::vector<ShapeUse> ScannedShapes() const;
  // An upper estimate of the steps of a run: every rock in contact for
  // max_time at the scene's smallest contact step (SmallestContactStep).
  double EstimatedSteps() const;
  // options.IsValid, forest.IsValid, each barrier's line (at least 2 finite
  // vertices), height and capacity (finite, > 0), 1 to kMaxRocks rocks, and EstimatedSteps() at
  // most kMaxEstimatedSteps; on failure sets *error (value and rule) and returns false.
  bool IsValid(std::string* error) const;
  // Spreads `total` rocks over the groups in proportion to their counts
  // (largest remainder, ties to the earlier group), keeping their order.
  void SetTotalRocks(int total);
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SCENE_H_
