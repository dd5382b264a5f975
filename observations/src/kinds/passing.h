// The observation kind of passing fractions (passing, passing_file): the share of rocks crossing a
// partition: its file keys, reader, recording, misfit terms and folds (kinds.h). Private to
// observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_PASSING_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_PASSING_H_

#include "kinds.h"

namespace rockcal::observations::kinds {

Kind PassingKind();

}  // namespace rockcal::observations::kinds

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_PASSING_H_
