#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace rockcal::cli {

Progress::Progress(std::string what, bool quiet)
    : what_(std::move(what)),
      active_(!quiet && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

Progress::~Progress() {
  if (drawn_) std::fprintf(stderr, "\n");
}

void Progress::Update(int done, int total, const std::string& extra) {
  if (!active_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total && now - last_ < std::chrono::milliseconds(200)) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  const double left = rate > 0 ? (total - done) / rate : 0.0;
  std::fprintf(stderr, "\r%s %d/%d  %.1f/s  %.0f s left %s\033[K", what_.c_str(), done, total, rate,
               left, extra.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void PrintWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::printf("WARNING: %s\n", w.c_str());
}

void PrintNotes(const std::vector<std::string>& notes, bool quiet) {
  if (quiet) return;
  for (const std::string& n : notes) std::printf("note: %s\n", n.c_str());
}

}  // namespace rockcal::cli
