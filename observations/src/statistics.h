// The misfit's shared statistics beside those misfit.h declares (quantile
// and maximum errors, the maximum's order position, the fit verdict), all
// defined in statistics.cc. Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_STATISTICS_H_
#define ROCKCAL_OBSERVATIONS_SRC_STATISTICS_H_

#include <vector>

#include "rockcal/core/statistics.h"

namespace rockcal::observations {

// Value at a fractional position of an ascending sample: core's.
using core::AtPosition;

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_SRC_STATISTICS_H_
