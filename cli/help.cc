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

namespace {

// A prose line of Markdown as plain text: a link [text](target) is its
// text, `code` and **bold** lose their marks, a heading its #s, and a table
// row its pipes (its rule line is dropped by the caller).
std::string PlainLine(const std::string& line) {
  std::string s = line;
  std::size_t hashes = 0;
  while (hashes < s.size() && s[hashes] == '#') ++hashes;
  if (hashes > 0 && hashes < s.size() && s[hashes] == ' ') s.erase(0, hashes + 1);
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '[') {  // a link: [text](target) -> text
      const std::size_t close = s.find("](", i);
      const std::size_t end = close == std::string::npos ? close : s.find(')', close);
      if (close != std::string::npos && end != std::string::npos &&
          s.find('[', i + 1) > close) {
        out += PlainLine(s.substr(i + 1, close - i - 1));
        i = end;
        continue;
      }
    }
    if (c == '`') continue;
    if (c == '*' && i + 1 < s.size() && s[i + 1] == '*') {
      ++i;
      continue;
    }
    out += c;
  }
  if (StartsWith(out, "|")) {  // a table row: cells apart by two spaces
    std::string row;
    for (std::size_t i = 1; i < out.size(); ++i) row += out[i] == '|' ? ' ' : out[i];
    const std::size_t first = row.find_first_not_of(' ');
    if (first == std::string::npos) return "";
    return row.substr(first, row.find_last_not_of(' ') - first + 1);
  }
  return out;
}

bool IsTableRule(const std::string& line) {
  return StartsWith(line, "|") && line.find_first_not_of("|-: ") == std::string::npos;
}

}  // namespace

std::string ForTerminal(const std::string& markdown) {
  std::istringstream in(markdown);
  std::string line, out;
  bool code = false;
  while (std::getline(in, line)) {
    if (StartsWith(line, "```")) {
      code = !code;
      continue;
    }
    if (code) {
      out += line + "\n";  // code as written
    } else if (!IsTableRule(line)) {
      out += PlainLine(line) + "\n";
    }
  }
  return out;
}

bool AsksForHelp(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

}  // namespace rockcal::cli
