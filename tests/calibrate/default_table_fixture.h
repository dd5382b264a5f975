// Builders shared by the default-table tests (calibrate and reports).
#ifndef ROCKCAL_TESTS_CALIBRATE_DEFAULT_TABLE_FIXTURE_H_
#define ROCKCAL_TESTS_CALIBRATE_DEFAULT_TABLE_FIXTURE_H_

#include <string>

#include "rockcal/calibrate/default_table.h"

namespace rockcal::calibrate::testing {

// One calibrated parameter of a result folder.
inline CalibratedParameter P(const std::string& material, const std::string& cls,
                             const std::string& name, double value, double lower, double upper) {
  CalibratedParameter p;
  p.material = material;
  p.material_class = cls;
  p.name = name;
  p.value = value;
  p.lower = lower;
  p.upper = upper;
  return p;
}

}  // namespace rockcal::calibrate::testing

#endif  // ROCKCAL_TESTS_CALIBRATE_DEFAULT_TABLE_FIXTURE_H_
