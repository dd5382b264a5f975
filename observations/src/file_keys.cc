#include "rockcal/observations/file_keys.h"

namespace rockcal::observations {

const std::vector<sites::FileObjectKeys>& ObservationsFileKeys() {
  static const std::vector<sites::FileObjectKeys> objects = {
      {"$",
       {"units", "tree_scars", "runout", "runs", "runs_file", "passing", "passing_file", "error"}},
      {"$.tree_scars[]", {"partition", "heights", "heights_file", "trees", "trees_file"}},
      {"$.tree_scars[].trees[]", {"x", "y", "radius", "heights", "heights_file"}},
      {"$.runout",
       {"stop_points", "stop_points_file", "distances", "distances_file", "from", "direction",
        "masses", "mass_classes", "stopped_fraction", "observed_rocks"}},
      {"$.runs[]", {"id", "group", "stop"}},
      {"$.passing[]", {"partition", "fraction"}},
      {"$.error", {"height", "runout", "passing"}},
  };
  return objects;
}

const std::vector<const char*>& ObservationsKeysAt(const std::string& path) {
  return sites::KeysAt(ObservationsFileKeys(), path);
}

}  // namespace rockcal::observations
