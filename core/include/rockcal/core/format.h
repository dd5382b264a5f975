// Numbers and fields as text: the one number formatter and the one CSV field
// quoter of rockcal, used by every reader's messages and every writer's files.
#ifndef ROCKCAL_CORE_FORMAT_H_
#define ROCKCAL_CORE_FORMAT_H_

#include <string>

namespace rockcal::core {

// `value` through the printf conversion `format`, which takes exactly one
// double ("%.10g", "%.3f", "%.1f %%"). The default is the shortest form with
// up to 10 significant digits ("0.3048", "12", "1e-05"); infinities and NaN
// come out as printf writes them ("inf", "-inf", "nan").
std::string FormatNumber(double value, const char* format = "%.10g");

// A CSV field (RFC 4180): `text` as is, or in double quotes with each quote
// doubled when it holds a comma, a quote or a line break.
std::string CsvField(const std::string& text);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_FORMAT_H_
