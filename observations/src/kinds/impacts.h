// The observation kind of measured impacts (impacts, impacts_file): a tracked
// rock's velocity before and after one impact, replayed on the production
// contact path (core/impact_replay.h): its file keys, reader, recording,
// misfit terms and folds (kinds.h). Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_IMPACTS_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_IMPACTS_H_

#include "kinds.h"

namespace rockcal::observations::kinds {

Kind ImpactsKind();

}  // namespace rockcal::observations::kinds

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_IMPACTS_H_
