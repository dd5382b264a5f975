// A site's values from a class table as parameter sets to draw: `rockcal
// simulate` of a site whose materials name a class (sites/class_table.h)
// draws D sets, each value uniformly and independently within its row's
// interval (the envelope of the calibrations' posterior 5-95 % intervals,
// or the range of their values), and simulates rock i with set i mod D
// through the posterior draws' machinery (posterior_draws.h). The uniform
// draw is no posterior of a new site: it spreads the values over the range
// that the table's calibrations hold. docs/default-table.md.
#ifndef ROCKCAL_CALIBRATE_CLASS_DRAWS_H_
#define ROCKCAL_CALIBRATE_CLASS_DRAWS_H_

#include <cstdint>
#include <vector>

#include "rockcal/calibrate/parameters_file.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// One parameter per class material and field taken from the table with an
// interval: value the row's median, lower and upper its interval (SI),
// class the material's class. file names the table(s); no samples file.
// Empty parameters when no value taken from a table has an interval.
CalibratedSite ClassParameters(const sites::Site& site);

// `draws` parameter sets, each value uniform in [lower, upper] of its
// parameter, from the random stream of `seed` (the run's): the same at any
// thread count.
std::vector<std::vector<double>> ClassDrawSamples(const CalibratedSite& parameters, int draws,
                                                  std::uint64_t seed);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_CLASS_DRAWS_H_
