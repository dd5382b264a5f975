// Field observations of a site (tree scars, runout, passing fractions), read
// from an observations file and held in SI units. See observations/README.md
// for the file format.
#ifndef ROCKCAL_OBSERVATIONS_OBSERVATIONS_H_
#define ROCKCAL_OBSERVATIONS_OBSERVATIONS_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/observations/track_flights.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::observations {

// A tree where scar heights were measured. The simulated counterpart is the
// height of the rocks whose bounding sphere reaches the trunk.
struct Tree {
  double x = 0.0, y = 0.0;      // m, trunk position in plan
  double radius = 0.0;          // m, trunk radius (>= 0)
  std::vector<double> heights;  // m, scar heights above the ground (>= 0)
  // Index of this tree in RequiredRecording(...).trees, hence in
  // core::RockRecord::trees. Set by LoadObservations (trees numbered in file
  // order over all tree-form scar sets).
  int probe = -1;
  // The stem of the scene's forest (index in core::Forest::stems) this tree
  // is: the nearest stem whose trunk touches or overlaps this one in plan
  // (axes at most the two radii apart); its scars are then compared with the
  // heights at which simulated rocks struck that stem (core::TreeStrike),
  // not the heights at which they passed it. -1: none (passages).
  int stem = -1;
};

// One set of tree scar heights, tied either to a partition (CRSP's practice)
// or to a list of trees. The heights of a tree-form set are pooled over its
// trees (one distribution per set).
struct ScarSet {
  std::string label;            // "tree_scars[0] BP-1" or "tree_scars[1] trees"
  int partition = -1;           // index into core::Scene::partitions; -1: tree form
  std::vector<double> heights;  // m, partition form only
  std::vector<Tree> trees;      // tree form only

  bool at_partition() const { return partition >= 0; }
  // The observed heights: `heights`, or every tree's heights in tree order.
  std::vector<double> ObservedHeights() const;
};

// Where boulders stopped, as distances along a direction (and, when stop
// points were given, signed lateral offsets from the line).
struct Runout {
  std::vector<Eigen::Vector2d> stop_points;              // m; empty when given as distances
  Eigen::Vector2d from = Eigen::Vector2d::Zero();        // m, origin of the distances
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // unit vector in plan
  // m, (p - from) . direction of each stop point, or the distances as given.
  std::vector<double> distances;
  // m, signed perpendicular offset of each stop point, positive to the left of
  // `direction` (direction x (p - from)). Empty when given as distances.
  std::vector<double> lateral;

  // Along-direction distance and lateral offset of a plan point p.
  double Distance(const Eigen::Vector2d& p) const { return (p - from).dot(direction); }
  double Lateral(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d d = p - from;
    return direction.x() * d.y() - direction.y() * d.x();
  }
  bool has_lateral() const { return !lateral.empty(); }
  // kg, the mass of each block (parallel to `distances`), when the file gives
  // them ("masses"); empty otherwise.
  std::vector<double> masses;
  // With masses: the runout is also compared per mass class, the blocks
  // split at the observed masses' quantiles k / mass_classes (0: not).
  int mass_classes = 0;
  // The share of the observed rocks that stopped ("stopped_fraction", 1
  // unless the file says otherwise) and how many rocks that share is of
  // ("observed_rocks", default the number of distances).
  double stopped_fraction = 1.0;
  int observed_rocks = 0;
  // The lower mass bounds (kg) of classes 2 .. mass_classes: the observed
  // masses' quantiles k / mass_classes. Empty without mass classes.
  std::vector<double> MassClassBounds() const;

  // Per-run observations (the file's "runs" or "runs_file"): each stop point
  // is one tracked run's, tied to the rock group released as that run was.
  // distances[i] is then run i's runout, the horizontal distance from its
  // own release (run_origins[i], the group's release point) to its stop
  // point, and the simulated counterpart is the distance from the same
  // origin of each rock of that group only (no lateral offsets). Parallel
  // to distances; empty for the pooled forms above.
  std::vector<std::string> run_ids;
  std::vector<int> run_groups;                // index into core::Scene::groups
  std::vector<Eigen::Vector2d> run_origins;   // m
  bool has_runs() const { return !run_groups.empty(); }
};

// Share of released rocks that cross a partition.
struct Passing {
  std::string label;    // "passing[0] BP-2"
  int partition = -1;   // index into core::Scene::partitions
  double fraction = 0;  // in [0, 1]
};

// One tracked run's path (the file's "tracks_file"): the rock's centre over
// time, and what DetectFlights reads off it (docs/field-campaigns.md,
// section 6).
struct Track {
  std::string run;                   // the run's id (Runout::run_ids)
  int line = 0;                      // the tracks file's line of its first sample
  std::vector<TrackSample> samples;  // SI, in increasing time
  // Detected once the track's error is known (LoadObservations): one jump
  // height and length per flight, one incoming speed per impact.
  std::vector<double> jump_heights;   // m, the centre's highest point above the ground
  std::vector<double> jump_lengths;   // m, in plan
  std::vector<double> impact_speeds;  // m/s, the speed just before the impact
};

// The tracked runs' paths, compared as distributions of jump heights, jump
// lengths and impact speeds with those of the tracked runs' groups'
// simulated rocks, measured alike (the same detector and thresholds).
struct Tracks {
  std::string file;           // the tracks file (resolved)
  std::vector<Track> tracks;  // in the order of their first rows
  // s, the median interval between consecutive samples over every track:
  // the simulated paths are sampled at this interval.
  double sample_seconds = 0.0;
  // The detector's options: `noise` is the track error (error.track).
  FlightOptions flight;
  // The quantile levels each distribution is compared at.
  static std::vector<double> Levels();  // 0.25, 0.5, 0.75
};

// One measured impact of a tracked rock (the file's "impacts" or
// "impacts_file"; docs/field-campaigns.md): the rock's centre at the impact
// and its velocity before and after, replayed by core/impact_replay.h.
struct Impact {
  std::string id;  // its id (the file's, or "impact <row>")
  int group = 0;   // index into core::Scene::groups
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();        // m
  Eigen::Vector3d velocity_in = Eigen::Vector3d::Zero();   // m/s
  Eigen::Vector3d velocity_out = Eigen::Vector3d::Zero();  // m/s
  std::optional<Eigen::Vector3d> spin;                     // rad/s, measured incoming spin
  // The ground's unit normal there (core::GroundNormal's, from the grid):
  // the rebound ratios are taken about it.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};
constexpr int kDefaultImpactDraws = 16;

// One-sigma measurement errors, SI.
struct MeasurementErrors {
  double height = 0.0;    // m, of a scar height (> 0 when tree scars are given)
  double runout = 0.0;    // m, of a stop position along and across the direction
  double passing = 0.05;  // of a passing fraction, in (0, 1]
  double track = 0.0;     // m, of a track sample's position per axis (> 0 with tracks)
  double impact_speed = 0.0;  // m/s, of a track's impact speed (> 0 with tracks)
  double rebound = 0.05;  // of a rebound ratio (normal or tangential), > 0
};

struct Observations {
  std::string path;  // the observations file
  sites::Units units = sites::Units::kUS;
  std::vector<ScarSet> tree_scars;
  std::optional<Runout> runout;
  std::vector<Passing> passing;
  std::optional<Tracks> tracks;  // tracks of tracked runs (needs runout with runs)
  std::vector<Impact> impacts;
  int impact_draws = kDefaultImpactDraws;  // replays per impact ("impact_draws")
  MeasurementErrors error;
  // What the reader found and chose (e.g. the runout direction), one line each,
  // for `rockcal validate`.
  std::vector<std::string> notes;
  // Every file the observations were read from: the observations file, then
  // the CSV files it named (as resolved). A calibration's log fingerprints them.
  std::vector<std::string> inputs;

  bool empty() const {
    return tree_scars.empty() && !runout && passing.empty() && !tracks && impacts.empty();
  }
};

// Reads and validates the observations file at `path` against `scene` (whose
// partitions the file may name and whose first rock group's release is the
// default origin of runout distances). Strict: unknown, missing or mistyped
// keys, unknown partition ids, negative heights, fractions outside [0, 1],
// empty lists and bad CSV rows throw InputError naming the file, the JSON path
// (or the CSV line), the value and what was expected.
Observations LoadObservations(const std::string& path, const core::Scene& scene);

// The impacts DetectFlights finds in the tracks (Observations::tracks, with
// their error as its noise, over `scene`'s surface), as an impacts file: the
// header "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out", then one
// row per impact in track order; `id` is "<run>-<k>" (k from 1 along the
// track), `group` the run's rock group's id, lengths in the observations
// file's units (velocities per second). Header only without tracks.
std::string DetectedImpactsCsv(const Observations& observations, const core::Scene& scene);

// One warning per pair of tracked runs with the same release point and the
// same stop point (within 1 mm): most likely one run written twice, which
// counts twice in the misfit. Empty without runs.
std::vector<std::string> DuplicateRunWarnings(const Observations& observations);

// The scatter of a tracked campaign's repeated runs: what no prediction from
// the release can beat on average. Runs are repeats when their rock groups
// release the same rocks (shape, sizes, box, unit weight and inventory
// blocks alike) from release points within kRepeatRadius of one another;
// a set is the first run not yet in a set and every later such run (sets of
// fewer than 3 runs are left out). Over the runs of the sets, the mean
// |runout - the median of its set| (`own_median_error_m`: the set's median
// known, so a lower bound) and |runout - the median of the set's other
// runs| (`others_median_error_m`: a prediction from the other repeats,
// as a held-out run is predicted). A model's cross-validated mean per-run
// error near them is at the campaign's own repeatability.
struct RepeatScatter {
  static constexpr double kRepeatRadius = 2.0;  // m, in plan
  int sets = 0;
  int runs = 0;
  double own_median_error_m = 0.0;
  double others_median_error_m = 0.0;
  // One line for validate and the calibration's report.
  std::string Sentence() const;
};
// Unset without runs or without a set of 3 repeats.
std::optional<RepeatScatter> RunRepeatScatter(const Observations& observations,
                                              const core::Scene& scene);

// What a simulation must record for ComputeMisfit: `base` with `partitions`
// set only when a scar set or a passing fraction refers to a partition, and
// `trees` replaced by the trees of the tree-form scar sets (in Tree::probe
// order; empty when there are none). Other fields are left as in `base`.
// With tracks, also the paths of every rock of the tracked runs' groups
// (trajectory_groups), sampled every Tracks::sample_seconds.
core::RecordOptions RequiredRecording(const Observations& observations, core::RecordOptions base);

// One fold of a K-fold split of the observations: the values it holds out.
struct Fold {
  int index = 0, count = 1;  // fold `index` (0-based) of `count`
  // Per scar set (in order): indices into its ObservedHeights().
  std::vector<std::vector<std::size_t>> scars;
  // Indices into runout.distances (and stop_points, lateral).
  std::vector<std::size_t> runout;
  std::vector<std::size_t> impacts;  // indices into impacts
};

// Splits the observations into `k` (>= 2) folds: the runout values and each
// scar set's heights are dealt round-robin over the folds in an order
// shuffled with `seed`, so each fold holds about 1/k of every list. Passing
// fractions are in no fold (they stay in every training set). Throws
// InputError when a list has fewer than k values.
std::vector<Fold> MakeFolds(const Observations& observations, int k, std::uint64_t seed);

// The observations without the fold's values (`held_out` false: its training
// set, passing fractions included) or with only them (`held_out` true: no
// passing fractions). A scar set or runout left without values is dropped;
// tree probes are renumbered in order.
Observations Subset(const Observations& observations, const Fold& fold, bool held_out);

// Plan centroid of a release: the area centroid of its zone polygon (the mean
// of its vertices when the polygon has no area), or its point.
Eigen::Vector2d ReleaseCentroid(const core::Release& release);

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_OBSERVATIONS_H_
