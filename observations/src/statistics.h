// The misfit's shared statistics beside those misfit.h declares (quantile
// and maximum errors, the maximum's order position, the fit verdict), all
// defined in statistics.cc. Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_STATISTICS_H_
#define ROCKCAL_OBSERVATIONS_SRC_STATISTICS_H_

#include <vector>

namespace rockcal::observations {

// Value at a fractional position k in [0, n - 1] of an ascending sample,
// interpolated linearly between neighbouring order statistics.
double AtPosition(const std::vector<double>& sorted, double k);

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_SRC_STATISTICS_H_
