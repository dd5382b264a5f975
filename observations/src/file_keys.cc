#include "rockcal/observations/file_keys.h"

#include "kinds/kinds.h"

namespace rockcal::observations {

const std::vector<sites::FileObjectKeys>& ObservationsFileKeys() {
  // "$" holds "units", every kind's keys and "error"; then each kind's
  // objects, and "$.error" with each kind's measurement error, in table order.
  static const std::vector<sites::FileObjectKeys> objects = [] {
    sites::FileObjectKeys root{"$", {"units"}};
    sites::FileObjectKeys error{"$.error", {}};
    std::vector<sites::FileObjectKeys> kind_objects;
    for (const kinds::Kind& kind : kinds::Kinds()) {
      root.keys.insert(root.keys.end(), kind.root_keys.begin(), kind.root_keys.end());
      kind_objects.insert(kind_objects.end(), kind.objects.begin(), kind.objects.end());
      error.keys.insert(error.keys.end(), kind.error_keys.begin(), kind.error_keys.end());
    }
    root.keys.push_back("error");
    std::vector<sites::FileObjectKeys> all{root};
    all.insert(all.end(), kind_objects.begin(), kind_objects.end());
    all.push_back(error);
    return all;
  }();
  return objects;
}

const std::vector<const char*>& ObservationsKeysAt(const std::string& path) {
  return sites::KeysAt(ObservationsFileKeys(), path);
}

}  // namespace rockcal::observations
