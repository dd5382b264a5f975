// The fuzz input as a file: the readers under test read files.
#ifndef ROCKCAL_FUZZ_FUZZ_INPUT_H_
#define ROCKCAL_FUZZ_FUZZ_INPUT_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace rockcal::fuzz {

// Writes `data` to a file private to this process and returns its path.
inline std::string WriteInput(const std::uint8_t* data, std::size_t size, const char* suffix) {
  const std::string path =
      "/tmp/rockcal_fuzz_" + std::to_string(::getpid()) + std::string(suffix);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

}  // namespace rockcal::fuzz

#endif  // ROCKCAL_FUZZ_FUZZ_INPUT_H_
