// What a simulation records, decided in one place from who will read it.
#ifndef ROCKCAL_CALIBRATE_RECORDING_H_
#define ROCKCAL_CALIBRATE_RECORDING_H_

#include "rockcal/core/scene.h"
#include "rockcal/observations/observations.h"

namespace rockcal::calibrate {

// The readers of one simulation's records. Defaults: nobody (nothing beyond
// the rocks' outcomes and stop points is recorded).
struct RecordingNeeds {
  // The misfit against these observations (ComputeMisfit): the partitions
  // and the trees they refer to. Null: no misfit.
  const observations::Observations* observations = nullptr;
  bool partitions = false;    // every partition's crossings (summary.json, rocks.csv)
  bool energy_check = false;  // the largest relative energy gain (diagnostics.json)
  // report.html: the passages per grid cell (its density map) and the paths
  // of min(rocks, report_trajectories) rocks spread over every group
  // (core::SpreadOverGroups; its profile), unless `trajectories` asks for
  // some already.
  bool report = false;
  int report_trajectories = 30;  // >= 0
  int trajectories = 0;          // the paths of the first N rocks (trajectories.csv), >= 0
  // s between trajectory samples, > 0; with tracks observed, the tracks'
  // median interval instead (observations::RequiredRecording).
  double sample_seconds = 0.05;
};

// The recording options of `scene` (its rock count) for `needs`.
core::RecordOptions RecordingFor(const core::Scene& scene, const RecordingNeeds& needs);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_RECORDING_H_
