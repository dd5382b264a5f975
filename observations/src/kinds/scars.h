// The observation kind of tree scars (tree_scars): scar heights at a partition or at trees:
// its file keys, reader, recording, misfit terms and folds (kinds.h).
// Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_SCARS_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_SCARS_H_

#include "kinds.h"

namespace rockcal::observations::kinds {

Kind ScarsKind();

}  // namespace rockcal::observations::kinds

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_SCARS_H_
