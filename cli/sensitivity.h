// rockcal sensitivity SITE.json [--method morris|sobol] [--samples N] ... --out DIR
#ifndef ROCKCAL_CLI_SENSITIVITY_H_
#define ROCKCAL_CLI_SENSITIVITY_H_

#include <string>
#include <vector>

namespace rockcal::cli {

// `args` are the words after "sensitivity". Returns the exit status; throws
// InputError on bad arguments or files.
int Sensitivity(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_SENSITIVITY_H_
