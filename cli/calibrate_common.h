// What `rockcal calibrate` and `rockcal campaign` share: the output folder
// that a stopped run resumes, the methods and options from the arguments,
// and the progress shown as the search goes.
#ifndef ROCKCAL_CLI_CALIBRATE_COMMON_H_
#define ROCKCAL_CLI_CALIBRATE_COMMON_H_

#include <optional>
#include <string>
#include <vector>

#include "args.h"
#include "progress.h"
#include "rockcal/calibrate/calibration_run.h"

namespace rockcal::cli {

// Prepares DIR `out` for a calibration (command `command`, e.g. "calibrate"):
// a new folder, or (with `resume`) the folder of a stopped run, or (with
// `force`) a replaced one. Nothing is removed without `force`, and `force`
// replaces only a folder rockcal wrote that holds none of `inputs`
// (reports::CheckOutputFolder). Files a killed run left half-written are
// removed, and so is `complete_file`, which marks the folder complete: it is
// written again, after every other file, when the run finishes. A new
// folder appears whole, with its marker and an empty evaluation log (built
// under a temporary name and renamed into place), so that a run killed at
// any moment leaves no folder or one that --resume continues.
void PrepareCalibrationFolder(std::string out, bool resume, bool force,
                              const std::vector<std::string>& inputs, const std::string& command,
                              const std::string& complete_file);

// --method or --methods, each checked against calibrate::MethodNames().
std::vector<std::string> MethodsFromArgs(const Args& args);

// The calibration's options from the arguments (--rocks, --seed, --threads,
// --max-evals, --max-seconds, --loss, --estimate, --resume, --refine), but
// for the methods and the reach check; the log is DIR/evaluations.jsonl.
calibrate::CalibrationOptions OptionsFromArgs(const Args& args, const std::string& out);

// What a calibration shows as it goes: the start, the reach check, a
// progress bar per method and each method's result.
calibrate::CalibrationCallbacks ProgressCallbacks(bool quiet, int max_evals,
                                                  std::optional<Progress>* progress);

// Under mpirun: the folder this rank writes into (`out` on rank 0, a scratch
// folder elsewhere), with copies of rank 0's evaluation logs so that every
// rank replays the same evaluations on --resume.
std::string RankCalibrationFolder(const std::string& out);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_CALIBRATE_COMMON_H_
