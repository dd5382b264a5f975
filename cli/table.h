// rockcal table RESULT_DIR... --out DIR
#ifndef ROCKCAL_CLI_TABLE_H_
#define ROCKCAL_CLI_TABLE_H_

#include <string>
#include <vector>

namespace rockcal::cli {

// `args` are the words after "table". Returns 0; throws InputError on bad
// arguments or files (nothing written then).
int Table(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_TABLE_H_
