// The ESRI ASCII grid reader.
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/esri_grid.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rockcal::fuzz::WriteInput(data, size, "_grid.asc");
  try {
    rockcal::sites::ReadEsriGrid(path);
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
