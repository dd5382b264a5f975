#include "rockcal/core/format.h"

#include <cstdio>

namespace rockcal::core {

std::string FormatNumber(double value, const char* format) {
  char buf[64];
  const int n = std::snprintf(buf, sizeof buf, format, value);
  if (n < 0) return "";
  if (static_cast<std::size_t>(n) < sizeof buf)
    return std::string(buf, static_cast<std::size_t>(n));
  std::string out(static_cast<std::size_t>(n) + 1, '\0');
  std::snprintf(out.data(), out.size(), format, value);
  out.resize(static_cast<std::size_t>(n));
  return out;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace rockcal::core
