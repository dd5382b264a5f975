#include "rockcal/calibrate/recording.h"

#include <algorithm>
#include <vector>

#include "rockcal/core/statistics.h"

namespace rockcal::calibrate {

core::RecordOptions RecordingFor(const core::Scene& scene, const RecordingNeeds& needs) {
  core::RecordOptions record;
  if (needs.observations)
    record = observations::RequiredRecording(*needs.observations, record);
  else
    record.partitions = false;
  record.partitions = record.partitions || needs.partitions;
  record.energy_check = needs.energy_check;
  record.trajectories = needs.trajectories;
  // Tracks fix the sampling interval (theirs, so that the simulated paths
  // are measured as the tracks are: docs/field-campaigns.md, section 6).
  if (record.trajectory_groups.empty()) record.sample_seconds = needs.sample_seconds;
  if (needs.report) {
    record.passages = true;
    record.tree_strikes = record.tree_strikes || !scene.forest.empty();  // the Forest section
    if (record.trajectories == 0) {
      // A sample of every group (the profile shows how each behaves), not the
      // first rocks, which may all be of the first group.
      std::vector<int> counts;
      for (const core::RockGroup& g : scene.groups) counts.push_back(g.count);
      record.trajectory_rocks = core::SpreadOverGroups(counts, needs.report_trajectories);
    }
  }
  return record;
}

}  // namespace rockcal::calibrate
