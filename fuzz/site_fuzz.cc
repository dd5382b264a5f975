// The site reader (strict JSON, ranges, polygons, the surface): any input
// is read or refused with an InputError, never a crash or another exception.
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/site.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rockcal::fuzz::WriteInput(data, size, "_site.json");
  try {
    rockcal::sites::LoadSite(path);
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
