// The point-cloud and CRSP LIDAR text readers; a FIFO, a folder and
// /dev/zero are refused at once.
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/point_files.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  rockcal::fuzz::MakeSpecialFiles();
  for (const char* path : {rockcal::fuzz::kFifo, rockcal::fuzz::kFolder, "/dev/zero"}) {
    try {
      rockcal::sites::ReadPointsFile(path);
      __builtin_trap();  // read as points
    } catch (const rockcal::InputError&) {
    }
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rockcal::fuzz::WriteInput(data, size, "_points.txt");
  try {
    rockcal::sites::ReadPointsFile(path);
  } catch (const rockcal::InputError&) {
  }
  try {
    rockcal::sites::ReadLidarFile(path);
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
