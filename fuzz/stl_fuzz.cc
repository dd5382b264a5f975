// The STL reader (ASCII and binary).
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/stl.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rockcal::fuzz::WriteInput(data, size, "_surface.stl");
  try {
    rockcal::sites::ReadStl(path, rockcal::sites::StlAxes::kXYZ, 1.0);
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
