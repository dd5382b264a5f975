// Number and field formatting shared by calibrate's JSON and CSV writers
// (study.cc, sensitivity.cc). Private to calibrate/src.
#ifndef ROCKCAL_CALIBRATE_SRC_TABLE_TEXT_H_
#define ROCKCAL_CALIBRATE_SRC_TABLE_TEXT_H_

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace rockcal::calibrate::text {

// A number for CSV: empty for NaN, "inf" / "-inf" for infinities.
inline std::string Num(double v, const char* format = "%.6g") {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// JSON number, null when not finite (JSON has no inf or NaN).
inline nlohmann::json JsonNum(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

// CSV field: quoted when it holds a comma, quote or newline.
inline std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace rockcal::calibrate::text

#endif  // ROCKCAL_CALIBRATE_SRC_TABLE_TEXT_H_
