// The site reader (strict JSON, ranges, polygons, the surface): any input
// is read or refused with an InputError, never a crash, a hang or another
// exception; so is deep nesting (fuzz_input.h's Nested) and a site naming a
// FIFO, a folder or a device as its data file (the seeds special_*.json).
#include "fuzz_input.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/site.h"

namespace {

// Special files given as the site file itself: refused, at once.
void SpecialSites() {
  for (const char* path : {rockcal::fuzz::kFifo, rockcal::fuzz::kFolder, "/dev/zero"}) {
    try {
      rockcal::sites::LoadSite(path);
      __builtin_trap();  // read as a site
    } catch (const rockcal::InputError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  rockcal::fuzz::MakeSpecialFiles();
  SpecialSites();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      rockcal::fuzz::WriteText(rockcal::fuzz::Nested(data, size), "_site.json");
  try {
    rockcal::sites::LoadSite(path);
  } catch (const rockcal::InputError&) {
  }
  return 0;
}
