// The observation kind of tracked runs (runs, runs_file): each run's stop against its own rock
// group: its file keys, reader, recording, misfit terms and folds (kinds.h). Private to
// observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_RUNS_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_RUNS_H_

#include "kinds.h"

namespace rockcal::observations::kinds {

Kind RunsKind();

}  // namespace rockcal::observations::kinds

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_RUNS_H_
