// The physically sensible ranges of rockcal's input. A value outside them is
// bad input (the readers name file, path, value and range), so that a typo
// fails instead of giving a meaningless simulation or calibration.
#ifndef ROCKCAL_CORE_LIMITS_H_
#define ROCKCAL_CORE_LIMITS_H_

namespace rockcal::core {

inline constexpr double kMaxCoordinate = 1e7;        // m: |x|, |y|, |z| of any point
inline constexpr double kMaxRockSize = 100.0;        // m: a rock's size
inline constexpr double kMinUnitWeight = 1e3;        // N/m^3 (1 kN/m^3)
inline constexpr double kMaxUnitWeight = 200e3;      // N/m^3 (200 kN/m^3)
inline constexpr double kMaxSpeed = 500.0;           // m/s: a release velocity component
inline constexpr double kMaxObservationError = 1e4;  // m: a one-sigma measurement error
inline constexpr double kMinContactTime = 1e-5;      // s: below it a run never ends
inline constexpr double kMaxContactTime = 1.0;       // s
// Pa: undergrowth's stress on a rock's frontal area (100 kPa decelerates a
// 0.3 m block at about 10 g).
inline constexpr double kMaxVegetationStress = 100e3;
inline constexpr int kMaxRocks = 10'000'000;         // rocks in one run
// The largest seed, in a site file ("simulation": {"seed"}) and given to
// --seed alike: 2^63 - 1.
inline constexpr long kMaxSeed = 9223372036854775807L;
// Upper estimate of the steps of one run (every rock in contact for max_time
// at its shortest step) above which a run is refused: it would not finish.
inline constexpr double kMaxEstimatedSteps = 1e13;

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_LIMITS_H_
