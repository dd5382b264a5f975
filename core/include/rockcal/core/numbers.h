// Numbers the sources share, defined once.
#ifndef ROCKCAL_CORE_NUMBERS_H_
#define ROCKCAL_CORE_NUMBERS_H_

#include <limits>

namespace rockcal::core {

// One definition each: sources compiled in one batch (ROCKCAL_UNITY_BUILD)
// would otherwise see a file-local copy per source.
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_NUMBERS_H_
