// What a rock's record keeps of its path (RecordOptions): partition
// crossings, tree passages, trajectory samples and the grid cells it passed
// over. Only what the options ask for is recorded. Internal to core.
#ifndef ROCKCAL_CORE_SRC_RECORDING_H_
#define ROCKCAL_CORE_SRC_RECORDING_H_

#include <limits>
#include <vector>

#include "rock_state.h"
#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

class Recorder final {
 public:
  // cluster: the rock turns as a cluster (orientation, full inertia).
  Recorder(const Scene& scene, const Terrain& terrain, const RockBody& body, bool cluster,
           RockRecord* rec);

  // At release: empty crossings and passages, the first trajectory sample.
  void Start(const RockState& s);
  // Partition crossings, tree passages and trajectory samples within the
  // advance from s0 to s (flew: on the exact parabola; else a small step).
  // When a barrier that stops rocks catches the rock within it: true, with
  // *stopped the state at the crossing (what is recorded ends there, and
  // RockRecord::stopped_by names the barrier). Without such barriers in the
  // scene, no extra work.
  bool Advance(const RockState& s0, const RockState& s, bool flew, RockState* stopped);
  // At the end, in state s: the cells in order, the last sample.
  void Finish(const RockState& s);

 private:
  // Crossings, passages and samples within the advance (Advance's work
  // once the advance's end is known).
  void Track(const RockState& s0, const RockState& s, bool flew);
  // The first crossing within the advance of a barrier that stops rocks and
  // catches this one: true, with *f its fraction along the advance, *at the
  // barrier's index and *crossing what the rock carried there.
  // Marks the barriers crossed before it (or all crossed) as met.
  bool Caught(const RockState& s0, const RockState& s, bool flew, double* f, int* at,
              Crossing* crossing);
  // State at fraction f of the advance from s0 to s: after a flight the
  // exact parabola and, with `turn`, a cluster's torque-free turn from s0
  // (without it the spin and orientation stay s0's: the kinetic energy of
  // the turn, all that a crossing or cell visit keeps of it, is the same all
  // along a flight); within a small step, linear.
  RockState Between(const RockState& s0, const RockState& s, double f, bool flew,
                    bool turn = false) const;
  // The crossing in state s, reached within an advance that began at s0 (on
  // the slope, as every advance does).
  Crossing Record(const RockState& s0, const RockState& s) const;
  // Height of the ground below (x, y); over a hole (no terrain data) the
  // ground where the plan path from s0 to (x, y) left the slope.
  double GroundBelow(const RockState& s0, double x, double y) const;
  void Sample(const RockState& s, bool force = false);
  // The cells passed over within the advance from s0 to s: every quarter
  // cell along a flight; after a small step or a flight shorter than that,
  // its end, when it is over another cell or an eighth of a cell from the
  // last sample kept (a rock near the ground changes its height and energy
  // little over that; its impacts begin at a flight's end).
  void Visit(const RockState& s0, const RockState& s, bool flew);
  // Keeps state s (reached from s0) in the record of the cell it is over;
  // unless `every`, not within an eighth of a cell of the last sample kept.
  void VisitAt(const RockState& s0, const RockState& s, bool every);
  // Terrain::Elevation at x's plan position; the last one found is kept (an
  // advance starts where the last one ended).
  bool ElevationAt(const Eigen::Vector3d& x, double* z);

  const Scene& scene_;
  const RecordOptions& opt_;
  const Terrain& terrain_;
  const RockBody& body_;
  const bool cluster_;
  const Eigen::Vector3d gravity_;
  const Eigen::Vector3d inv_inertia_;  // the body's principal moments inverted
  RockRecord* rec_;
  // The scene's barriers that stop rocks (indices into Scene::partitions).
  std::vector<int> stopping_;
  std::vector<char> met_;           // per stopping_ entry: crossed already
  std::vector<double> crossed_at_;  // per stopping_ entry: Caught's fraction, -1 none
  bool trajectory_ = false;
  double next_sample_ = 0.0;
  Eigen::Vector2d last_visit_ = Eigen::Vector2d::Zero();  // plan position of the last cell sample
  // The extent of that sample's cell (VisitAt); empty before the first.
  Eigen::Vector2d last_cell_low_ = Eigen::Vector2d::Constant(1.0),
                  last_cell_high_ = Eigen::Vector2d::Constant(-1.0);
  // The last elevation found (ElevationAt) and where; NaN: none yet.
  Eigen::Vector2d elevation_at_ =
      Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  double elevation_ = 0.0;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_RECORDING_H_
