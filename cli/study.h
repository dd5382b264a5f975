// rockcal study stability|convergence|reach SITE.json ... --out DIR
#ifndef ROCKCAL_CLI_STUDY_H_
#define ROCKCAL_CLI_STUDY_H_

#include <string>
#include <vector>

namespace rockcal::cli {

// `args` are the words after "study". Returns the exit status (0, or 1 when
// the study could not run); throws InputError on bad arguments or files.
int Study(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_STUDY_H_
