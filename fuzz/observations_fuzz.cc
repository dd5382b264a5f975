// The observations reader against a fixed scene with two partitions.
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/observations/observations.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rockcal::core::Scene scene = [] {
    rockcal::core::Scene s;
    rockcal::core::Partition x, z;
    x.id = "BP-1";
    x.kind = rockcal::core::Partition::Kind::kX;
    x.value = 50;
    z.id = "BP-2";
    z.kind = rockcal::core::Partition::Kind::kZ;
    z.value = 10;
    s.partitions = {x, z};
    rockcal::core::RockGroup g;
    g.count = 10;
    g.release.point = Eigen::Vector2d(1, 2);
    s.groups = {g};
    return s;
  }();
  const std::string path = rockcal::fuzz::WriteInput(data, size, "_obs.json");
  try {
    rockcal::observations::LoadObservations(path, scene);
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
