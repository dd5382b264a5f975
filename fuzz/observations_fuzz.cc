// The observations reader against a fixed scene with two partitions: any
// input is read or refused with an InputError, deep nesting included
// (fuzz_input.h's Nested), and so are a FIFO, a folder and /dev/zero.
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/observations/observations.h"

namespace {

const rockcal::core::Scene& FuzzScene() {
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
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  rockcal::fuzz::MakeSpecialFiles();
  for (const char* path : {rockcal::fuzz::kFifo, rockcal::fuzz::kFolder, "/dev/zero"}) {
    try {
      rockcal::observations::LoadObservations(path, FuzzScene());
      __builtin_trap();  // read as observations
    } catch (const rockcal::InputError&) {
    }
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rockcal::fuzz::WriteText(rockcal::fuzz::Nested(data, size), "_obs.json");
  try {
    rockcal::observations::LoadObservations(path, FuzzScene());
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
