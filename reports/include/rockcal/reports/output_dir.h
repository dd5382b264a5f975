// Output folders and files that appear whole or not at all, that replace
// only what rockcal wrote, and whose failures name the output and the cause.
//
// Every output folder rockcal creates holds a marker file, kOutputMarker
// (JSON: the tool, its version, the command and "complete"). --force
// replaces only a folder that holds the marker and is none of the run's
// inputs, contains none and lies inside none.
//
// A run holds an advisory lock (flock) on the file kOutputLock inside its
// output folder (or inside the temporary folder that becomes it) for its
// whole life; the kernel releases it when the process ends, however it ends.
// A second run on the same folder, with or without --force or --resume, is
// refused (InputError) naming the holder written into the lock file.
#ifndef ROCKCAL_REPORTS_OUTPUT_DIR_H_
#define ROCKCAL_REPORTS_OUTPUT_DIR_H_

#include <optional>
#include <string>
#include <vector>

namespace rockcal::reports {

inline constexpr const char kOutputMarker[] = ".rockcal-output";
inline constexpr const char kOutputLock[] = ".rockcal-lock";

// The lock of a run on an output folder: flock(LOCK_EX) on `folder`/kOutputLock
// (created if missing), held until destroyed (or the process ends). The file
// holds the holder: "pid P on HOST: rockcal COMMAND, since TIME".
class OutputLock final {
 public:
  OutputLock() = default;
  // Throws InputError naming `output` and the holder when another run holds
  // the lock; std::runtime_error when the file cannot be created.
  OutputLock(const std::string& folder, const std::string& output, const std::string& command);
  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

// Throws InputError naming `output` and the holder when another run holds the
// lock of `folder`; nothing when the folder has no lock file or it is free.
void CheckNotLocked(const std::string& folder, const std::string& output);

// Who writes an output folder: the command ("simulate", ...) for the marker,
// and the files and folders the run reads, which the output must not touch.
struct OutputOrigin {
  std::string command;
  std::vector<std::string> inputs;
};

// Throws InputError unless the folder `path` is none of `inputs`, contains
// none and lies inside none (compared as canonical paths). An empty path is
// refused.
void CheckOutputAgainstInputs(const std::string& path, const std::vector<std::string>& inputs);

// Throws InputError (nothing is touched) unless the folder `path` may be
// written: it must not be, contain or lie inside any of `inputs` (compared as
// canonical paths), and an existing `path` needs `force` and must hold the
// marker. `force_flag` names the option in messages. An empty path is refused.
void CheckOutputFolder(const std::string& path, bool force, const std::vector<std::string>& inputs,
                       const std::string& force_flag = "--force");

// Writes the marker into `folder` (atomically), with "complete" when given
// (a calibration folder has none: its calibration.json says it is complete).
void WriteOutputMarker(const std::string& folder, const std::string& command,
                       std::optional<bool> complete);

// Whether `folder` holds the marker.
bool HasOutputMarker(const std::string& folder);

// Removes what killed runs left beside or inside an output: the entries of
// folder `dir` named `prefix` + ".tmp-PID" or ".old-PID" (`prefix` empty: any
// name) whose process PID no longer exists and, for a folder, whose lock no
// run holds (a folder shared between machines: the lock decides, not the
// PID). Returns how many were removed.
int RemoveStaleTemporaries(const std::string& dir, const std::string& prefix);
// RemoveStaleTemporaries(folder, "") in an output folder and in every folder
// under it (a calibration's rasters/, a campaign's sites/<name>/): what a
// run killed while writing there left. Returns how many were removed.
int RemoveStaleTemporariesInside(const std::string& folder);

class OutputDir final {
 public:
  // Checks `path` with CheckOutputFolder (InputError, nothing touched but
  // its own temporary folder), creates the temporary folder holding the lock,
  // refuses a folder another run holds (InputError naming it) and removes
  // stale temporaries of earlier killed runs.
  OutputDir(std::string path, bool force, OutputOrigin origin = {});
  ~OutputDir();  // removes the temporary folder unless committed
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  // Where to write file `name` now (inside the temporary folder).
  std::string File(const std::string& name) const;
  // The temporary folder itself.
  const std::string& folder() const { return temp_; }
  // Writes the marker and replaces `path` by the temporary folder (an
  // existing one only with force).
  void Commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, temp_;
  bool force_ = false, committed_ = false;
  OutputOrigin origin_;
  OutputLock lock_;
};

// A folder a run writes in place and a stopped run resumes (a calibration):
// the same checks as OutputDir, the same lock, held while this lives.
//   resume: `path` must hold `log` (else InputError); it is locked and
//           nothing in it changes until Continue(), which the caller calls
//           once it has checked that the run may resume (a refused resume
//           leaves the folder as it was): Continue() removes its stale
//           temporaries (in its subfolders too: RemoveStaleTemporariesInside)
//           and `complete_file` (which marks the folder complete and is
//           written last), and rewrites the marker.
//   else:   a new folder appears whole, with its marker and an empty `log`
//           (built under a temporary name and renamed into place); with
//           `force`, an existing folder rockcal wrote is replaced.
//           Continue() does nothing.
// A failure to write (read-only or full file system) is std::runtime_error.
class ResumableOutputDir final {
 public:
  ResumableOutputDir(std::string path, bool resume, bool force, OutputOrigin origin,
                     const std::string& log, const std::string& complete_file);
  void Continue();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  OutputLock lock_;
  bool pending_ = false;  // a resume whose changes Continue() has not made yet
  std::string command_, complete_file_;
};

// Writes `text` to `path` through a temporary file renamed into place. A
// failure throws std::runtime_error naming `path` and the cause (strerror,
// e.g. "No space left on device"); the temporary file is removed.
void WriteFileAtomically(const std::string& path, const std::string& text);

// Writes `text` to the file `file` (created or truncated) and closes it. A
// failure throws std::runtime_error naming `output` and the cause.
void WriteWholeFile(const std::string& output, const std::string& file, const std::string& text);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_OUTPUT_DIR_H_
