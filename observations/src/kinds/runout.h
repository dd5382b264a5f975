// The observation kind of runout (runout): where boulders stopped, pooled about one origin:
// its file keys, reader, recording, misfit terms and folds (kinds.h).
// Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_RUNOUT_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_RUNOUT_H_

#include "kinds.h"

namespace rockcal::observations::kinds {

Kind RunoutKind();

// Throws unless the file's top object `root` holds at most one of the
// runout's forms: 'runout' (pooled about one origin), 'runs' and
// 'runs_file' (tracked runs, runs.h); both kinds fill Observations::runout.
void CheckOneRunoutForm(const sites::JsonNode& root);

}  // namespace rockcal::observations::kinds

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_RUNOUT_H_
