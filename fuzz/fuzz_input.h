// The fuzz input as a file: the readers under test read files.
#ifndef ROCKCAL_FUZZ_FUZZ_INPUT_H_
#define ROCKCAL_FUZZ_FUZZ_INPUT_H_

#include <sys/stat.h>
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

// The special files every reader must refuse (an InputError) without
// blocking: a FIFO and a folder at fixed paths, which seeds name
// (fuzz/seeds/site_fuzz/special_*.json); /dev/zero is a third.
inline constexpr const char kFifo[] = "/tmp/rockcal_fuzz_fifo";
inline constexpr const char kFolder[] = "/tmp/rockcal_fuzz_folder";
inline void MakeSpecialFiles() {
  ::mkfifo(kFifo, 0600);
  ::mkdir(kFolder, 0700);
}

// Deep nesting from a short input: an input "\xff" D1 D2 REST becomes REST
// inside 4 * (256 * D1 + D2) arrays (up to 262,140 levels; a JSON reader
// with a recursive parser or destructor overflows its stack well before);
// any other input is kept.
inline std::string Nested(const std::uint8_t* data, std::size_t size) {
  if (size < 3 || data[0] != 0xff) return std::string(reinterpret_cast<const char*>(data), size);
  const std::size_t depth = 4 * (256 * std::size_t{data[1]} + data[2]);
  return std::string(depth, '[') + std::string(reinterpret_cast<const char*>(data) + 3, size - 3) +
         std::string(depth, ']');
}

// Writes `text` like WriteInput.
inline std::string WriteText(const std::string& text, const char* suffix) {
  return WriteInput(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), suffix);
}

}  // namespace rockcal::fuzz

#endif  // ROCKCAL_FUZZ_FUZZ_INPUT_H_
