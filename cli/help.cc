#include "help.h"

#include <cstddef>
#include <sstream>

namespace rockcal::cli {

// Defined in the file the build generates from docs/reference/commands.md.
extern const unsigned char kCommandsReferenceBytes[];
extern const std::size_t kCommandsReferenceLength;

namespace {

constexpr const char* kSectionPrefix = "## rockcal ";

bool StartsWith(const std::string& line, const std::string& prefix) {
  return line.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

std::string CommandsReference() {
  return std::string(reinterpret_cast<const char*>(kCommandsReferenceBytes),
                     kCommandsReferenceLength);
}

std::string OverviewHelp(const std::string& reference) {
  std::istringstream in(reference);
  std::string line, out;
  while (std::getline(in, line) && !StartsWith(line, kSectionPrefix)) out += line + "\n";
  return out;
}

std::string CommandHelp(const std::string& reference, const std::string& command) {
  std::istringstream in(reference);
  std::string line, out;
  bool inside = false;
  while (std::getline(in, line)) {
    if (StartsWith(line, "## ")) {
      if (inside) break;
      inside = line == kSectionPrefix + command;
    }
    if (inside) out += line + "\n";
  }
  return out;
}

std::string ForTerminal(const std::string& markdown) {
  std::istringstream in(markdown);
  std::string line, out;
  while (std::getline(in, line))
    if (!StartsWith(line, "```")) out += line + "\n";
  return out;
}

bool AsksForHelp(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

}  // namespace rockcal::cli
