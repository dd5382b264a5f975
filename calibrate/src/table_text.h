// Number and field formatting shared by calibrate's JSON and CSV text
// (results_json.cc, posterior.cc, posterior_draws.cc) and its console
// reports. Private to calibrate/src.
#ifndef ROCKCAL_CALIBRATE_SRC_TABLE_TEXT_H_
#define ROCKCAL_CALIBRATE_SRC_TABLE_TEXT_H_

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "rockcal/core/format.h"

namespace rockcal::calibrate::text {

// A number for CSV: empty for NaN, "inf" / "-inf" for infinities.
inline std::string Num(double v, const char* format = "%.6g") {
  return std::isnan(v) ? "" : core::FormatNumber(v, format);
}

// JSON number, null when not finite (JSON has no inf or NaN).
inline nlohmann::json JsonNum(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

using core::CsvField;

// A share as a percentage for reading: "12.5 %", "0.042 %", "unknown" when
// not finite.
inline std::string Percent(double fraction) {
  if (!std::isfinite(fraction)) return "unknown";
  return core::FormatNumber(100.0 * fraction, fraction < 0.001 ? "%.2g %%" : "%.3g %%");
}

}  // namespace rockcal::calibrate::text

#endif  // ROCKCAL_CALIBRATE_SRC_TABLE_TEXT_H_
