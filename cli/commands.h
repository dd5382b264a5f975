#ifndef ROCKCAL_CLI_COMMANDS_H_
#define ROCKCAL_CLI_COMMANDS_H_

#include <string>
#include <vector>

namespace rockcal::cli {

int Simulate(const std::vector<std::string>& args);
int Validate(const std::vector<std::string>& args);
int Calibrate(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_COMMANDS_H_
