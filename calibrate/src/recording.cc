#include "rockcal/calibrate/recording.h"

#include <algorithm>

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
  record.sample_seconds = needs.sample_seconds;
  if (needs.report) {
    record.passages = true;
    if (record.trajectories == 0)
      record.trajectories = std::min(scene.total_rocks(), needs.report_trajectories);
  }
  return record;
}

}  // namespace rockcal::calibrate
