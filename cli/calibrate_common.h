// What `rockcal calibrate` and `rockcal campaign` share: the output folder
// that a stopped run resumes, the methods and options from the arguments,
// and the progress shown as the search goes.
#ifndef ROCKCAL_CLI_CALIBRATE_COMMON_H_
#define ROCKCAL_CLI_CALIBRATE_COMMON_H_

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "args.h"
#include "progress.h"
#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/reports/output_dir.h"
#include "run_inputs.h"

namespace rockcal::cli {

// Prepares DIR `out` for a calibration on rank 0 (reports::ResumableOutputDir,
// locked until `*dir` is reset): a new folder, or (with --resume) the folder
// of a stopped run, or (with --force) a replaced one; `complete_file` marks
// the folder complete and is written last. `inputs` are the run's. With
// --resume, `check_resume` (the logs read as the resume will read them)
// runs once the folder is locked; nothing in the folder changes until the
// calibration opens its log (ResumableOutputDir::Continue from
// `callbacks->log_opened`), so that a refused resume leaves it as it was.
void PrepareCalibrationFolder(const Args& args, const std::string& out, const RunInputs& inputs,
                              const std::string& command, const std::string& complete_file,
                              const std::function<void()>& check_resume,
                              std::optional<reports::ResumableOutputDir>* dir,
                              calibrate::CalibrationCallbacks* callbacks);

// Runs `work` (a calibration and its files, once DIR `out` is prepared). A
// failure that is not bad input (a full disk, a rank lost) is rethrown
// saying that `out` keeps the evaluations so far and that the same command
// with --resume continues it.
void ContinuableRun(const std::string& out, const std::function<void()>& work);

// --method or --methods onto *methods (left alone when neither is given),
// each name parsed by calibrate::StringToMethod; an unknown one is an
// InputError naming the flag, the name and the allowed names.
void MethodsFromArgs(const Args& args, std::vector<calibrate::Method>* methods);

// The calibration's options: `base` (the library's defaults unless given)
// with the flags given mapped onto it (--rocks, --seed, --threads,
// --max-evals, --max-seconds, --loss, --estimate, --resume, --refine,
// --reach, --race), but for the methods; the log is DIR/evaluations.jsonl.
// A flag not given leaves the field alone.
calibrate::CalibrationOptions OptionsFromArgs(
    const Args& args, const std::string& out,
    calibrate::CalibrationOptions base = calibrate::CalibrationOptions{});

// What a calibration shows as it goes: the start (with `stages` after its
// rocks per evaluation, e.g. " in one stage (--rocks: no refining stage)"),
// the reach check, a progress bar per method and each method's result.
calibrate::CalibrationCallbacks ProgressCallbacks(bool quiet, int max_evals,
                                                  std::optional<Progress>* progress,
                                                  const std::string& stages = "");

// --posterior with --posterior-points, --posterior-rounds, --posterior-stage
// (calibrate's; a campaign has one stage), --posterior-log-sigma and
// --predictive (20 draws by default) into options->posterior (with its
// predictive_draws) and posterior_stage; those without --posterior are an
// InputError naming them.
void PosteriorFromArgs(const Args& args, calibrate::CalibrationOptions* options);

// What the posterior stage shows as it goes: a line per stage (the design,
// each refining round, the sampling, the predictive bands) and a progress bar.
calibrate::PosteriorProgress PosteriorProgressPrinter(bool quiet, std::optional<Progress>* progress);

// Under mpirun: the folder this rank writes into (`out` on rank 0, a scratch
// folder elsewhere), with copies of rank 0's evaluation logs so that every
// rank replays the same evaluations on --resume.
std::string RankCalibrationFolder(const std::string& out);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_CALIBRATE_COMMON_H_
