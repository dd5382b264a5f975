#ifndef ROCKCAL_CLI_PROGRESS_H_
#define ROCKCAL_CLI_PROGRESS_H_

#include <chrono>
#include <string>
#include <vector>

namespace rockcal::cli {

// A progress line on stderr, redrawn at most a few times a second; silent when
// stderr is not a terminal or when quiet.
class Progress final {
 public:
  Progress(std::string what, bool quiet);
  ~Progress();
  // `done` of `total` units; `extra` is appended (e.g. "best misfit 3.2").
  void Update(int done, int total, const std::string& extra = "");

 private:
  std::string what_;
  bool active_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

// Each warning on stdout as "WARNING: <text>", a line each.
void PrintWarnings(const std::vector<std::string>& warnings);

// Each note on stdout as "note: <text>", a line each (a site's resampling,
// sites::Site::resampled); nothing when quiet.
void PrintNotes(const std::vector<std::string>& notes, bool quiet);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_PROGRESS_H_
