// The observation kind of tracked trajectories (tracks_file): the paths of
// tracked runs, their flights and impacts against those of the runs'
// simulated rocks: its file keys, reader, recording, misfit terms and folds
// (kinds.h). Private to observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_TRACKS_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_TRACKS_H_

#include "kinds.h"

namespace rockcal::observations::kinds {

Kind TracksKind();

}  // namespace rockcal::observations::kinds

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_TRACKS_H_
