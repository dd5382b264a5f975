#include "rockcal/reports/output_dir.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "rockcal/core/error.h"

#ifndef ROCKCAL_VERSION
#define ROCKCAL_VERSION "unknown"
#endif

namespace rockcal::reports {
namespace {

namespace fs = std::filesystem;

// `path` made absolute, with links and "..", "." resolved as far as it
// exists. A path the system cannot resolve (a name too long, a loop of
// links) is an InputError naming it and the system's reason.
fs::path Canonical(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (!ec) p = fs::weakly_canonical(p, ec);
  if (ec)
    throw InputError(
        path, "cannot be resolved: " + ec.message() + " (expected a path the system accepts)");
  if (!p.has_filename()) p = p.parent_path();
  return p;
}

// Whether `inner` is `outer` or lies inside it (both canonical).
bool Within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i)
    if (i == inner.end() || *i != *o) return false;
  return true;
}

// The PID of a name `prefix`.tmp-PID or `prefix`.old-PID; 0 if it is none.
pid_t TemporaryPid(const std::string& name, const std::string& prefix) {
  for (const char* tag : {".tmp-", ".old-"}) {
    const std::size_t at = name.rfind(tag);
    if (at == std::string::npos || at + 5 >= name.size()) continue;
    if (!prefix.empty() && name.compare(0, at, prefix) != 0) continue;
    if (!prefix.empty() && at != prefix.size()) continue;
    const std::string digits = name.substr(at + 5);
    if (digits.size() > 9) continue;
    bool all_digits = true;
    for (char c : digits) all_digits = all_digits && std::isdigit(static_cast<unsigned char>(c));
    if (all_digits) return static_cast<pid_t>(std::stol(digits));
  }
  return 0;
}

std::string Cause(int error) { return std::strerror(error); }

// Who holds the lock file `fd`, as written by OutputLock, made printable.
std::string Holder(int fd) {
  char buffer[512];
  // A run writes its name just after taking the lock: give it ~0.1 s.
  ssize_t n = 0;
  for (int attempt = 0; attempt < 5 && (n = ::pread(fd, buffer, sizeof buffer - 1, 0)) <= 0;
       ++attempt)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::string text;
  for (ssize_t k = 0; k < n; ++k) {
    const unsigned char c = static_cast<unsigned char>(buffer[k]);
    if (c == '\n') break;
    text += std::isprint(c) ? static_cast<char>(c) : '?';
  }
  return text.empty() ? "a run that has not written its name yet" : text;
}

InputError InUse(const std::string& output, const std::string& holder) {
  return InputError(output, "is in use by another rockcal run (" + holder +
                                "); wait until it ends, or choose another --out");
}

// flock(`operation` | LOCK_NB), retried a few times over ~0.1 s: another
// run's check (CheckNotLocked) holds a shared lock for an instant.
bool TryLock(int fd, int operation) {
  for (int attempt = 0;; ++attempt) {
    if (::flock(fd, operation | LOCK_NB) == 0) return true;
    if (errno != EWOULDBLOCK || attempt == 5) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// "pid P on HOST: rockcal COMMAND, since 2026-11-27T17:40:00Z".
std::string HolderText(const std::string& command) {
  char host[256] = "?";
  ::gethostname(host, sizeof host - 1);
  host[sizeof host - 1] = '\0';
  char when[32] = "?";
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  if (::gmtime_r(&now, &utc)) std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return "pid " + std::to_string(::getpid()) + " on " + host + ": rockcal " +
         (command.empty() ? std::string("?") : command) + ", since " + when + "\n";
}

// Refuses (InputError naming `path`) when another run holds the lock of a
// temporary folder of `path` other than `own`, or (unless this run holds it,
// `holds_path`) of `path` itself: the temporaries first, so that a run
// renaming its temporary into place meanwhile is seen in one place or the
// other.
void CheckNoOtherRun(const std::string& path, const std::string& own, bool holds_path) {
  const fs::path p(path);
  const std::string parent = p.parent_path().empty() ? "." : p.parent_path().string();
  const std::string name = p.filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    if (entry.rfind(name + ".tmp-", 0) != 0 || TemporaryPid(entry, name) == 0) continue;
    if (!own.empty() && fs::equivalent(it->path(), own, ec)) continue;
    CheckNotLocked(it->path().string(), path);
  }
  if (!holds_path && fs::is_directory(p, ec)) CheckNotLocked(path, path);
}

std::string WithoutTrailingSlashes(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

// Creates the temporary folder `temp` of output `path` (std::runtime_error
// naming both when it cannot: a read-only or full file system).
void CreateTemporary(const std::string& path, const std::string& temp) {
  std::error_code ec;
  fs::remove_all(temp, ec);
  if (!fs::create_directory(temp, ec))
    throw std::runtime_error("cannot create the output folder " + path + " (its temporary " + temp +
                             "): " + ec.message());
}

}  // namespace

OutputLock::OutputLock(const std::string& folder, const std::string& output,
                       const std::string& command) {
  const std::string file = folder + "/" + kOutputLock;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const int fd =
        ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd < 0) {
      const int error = errno;
      if (error == ENOENT)
        throw InputError(output,
                         "disappeared while this run locked it (another rockcal run "
                         "replacing it?); try again");
      throw std::runtime_error("cannot lock the output folder " + output + " (" + file +
                               "): " + Cause(error));
    }
    struct stat held {
    }, named{};
    if (::fstat(fd, &held) != 0 || !S_ISREG(held.st_mode)) {
      ::close(fd);
      throw InputError(file, "is not a regular file; expected rockcal's lock file");
    }
    if (!TryLock(fd, LOCK_EX)) {
      const int error = errno;
      const std::string holder = Holder(fd);
      ::close(fd);
      if (error == EWOULDBLOCK) throw InUse(output, holder);
      throw std::runtime_error("cannot lock the output folder " + output + " (" + file +
                               "): " + Cause(error));
    }
    // The path may name another file by now (the folder replaced by a
    // --force run between open and flock): hold the lock of the one it names.
    if (::stat(file.c_str(), &named) == 0 && named.st_dev == held.st_dev &&
        named.st_ino == held.st_ino) {
      const std::string text = HolderText(command);
      // The holder is for messages only: a full disk does not stop the run.
      if (::ftruncate(fd, 0) == 0 && ::pwrite(fd, text.data(), text.size(), 0) < 0) {
      }
      fd_ = fd;
      return;
    }
    ::close(fd);
  }
  throw InputError(output, "is being replaced by another rockcal run; try again when it ends");
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // A run that ends leaves an empty lock file; a killed one leaves its name.
  if (::ftruncate(fd_, 0) != 0) {
  }
  ::close(fd_);
}

OutputLock::OutputLock(OutputLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    OutputLock old(std::move(*this));
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

void CheckNotLocked(const std::string& folder, const std::string& output) {
  const std::string file = folder + "/" + kOutputLock;
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) return;  // no lock file: no run of this rockcal holds it
  struct stat st {};
  const bool held = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
                    ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  const std::string holder = held ? Holder(fd) : "";
  ::close(fd);  // releases the shared lock if taken
  if (held) throw InUse(output, holder);
}

void CheckOutputAgainstInputs(const std::string& path, const std::vector<std::string>& inputs) {
  if (path.empty())
    throw InputError("argument --out", "is empty; expected the name of an output folder");
  const fs::path out = Canonical(path);
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    const fs::path in = Canonical(input);
    if (in == out)
      throw InputError(path, "is an input of this run (" + input + "); expected a new folder");
    if (Within(in, out))
      throw InputError(
          path, "contains " + input + ", an input of this run; expected a folder holding no input");
    if (Within(out, in))
      throw InputError(path, "lies inside " + input +
                                 ", an input of this run; expected a folder outside the inputs");
  }
}

void CheckOutputFolder(const std::string& path, bool force, const std::vector<std::string>& inputs,
                       const std::string& force_flag) {
  CheckOutputAgainstInputs(path, inputs);
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(path, ec))) CheckNotLocked(path, path);
  if (fs::exists(fs::symlink_status(path, ec))) {
    if (!force)
      throw InputError(path,
                       "output folder exists already (give " + force_flag + " to replace it)");
    if (!fs::is_directory(fs::symlink_status(path, ec)))
      throw InputError(path, "exists and is not a folder; " + force_flag +
                                 " replaces only an output folder rockcal wrote");
    if (!HasOutputMarker(path))
      throw InputError(path, std::string("holds no ") + kOutputMarker +
                                 " file, so rockcal did not write it; " + force_flag +
                                 " replaces only an output folder rockcal wrote (remove it "
                                 "yourself, or choose another --out)");
  }
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  if (!fs::is_directory(parent, ec))
    throw InputError(path, "the folder that should hold it does not exist: " + parent.string());
}

void WriteOutputMarker(const std::string& folder, const std::string& command,
                       std::optional<bool> complete) {
  nlohmann::json marker = {{"tool", "rockcal"}, {"version", ROCKCAL_VERSION}, {"command", command}};
  if (complete) marker["complete"] = *complete;
  WriteFileAtomically(folder + "/" + kOutputMarker, marker.dump(2) + "\n");
}

bool HasOutputMarker(const std::string& folder) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(folder) / kOutputMarker, ec);
}

int RemoveStaleTemporaries(const std::string& dir, const std::string& prefix) {
  std::error_code ec;
  int removed = 0;
  for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    const pid_t pid = TemporaryPid(it->path().filename().string(), prefix);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    if (it->is_directory(ec)) {
      try {
        CheckNotLocked(it->path().string(), it->path().string());
      } catch (const InputError&) {
        continue;  // a live run holds it (on another machine sharing the folder)
      }
    }
    std::error_code remove_ec;
    if (fs::remove_all(it->path(), remove_ec) > 0 && !remove_ec) ++removed;
  }
  return removed;
}

int RemoveStaleTemporariesInside(const std::string& folder) {
  int removed = RemoveStaleTemporaries(folder, "");
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && !it->is_symlink(ec) &&
        TemporaryPid(it->path().filename().string(), "") == 0)
      removed += RemoveStaleTemporariesInside(it->path().string());
  return removed;
}

OutputDir::OutputDir(std::string path, bool force, OutputOrigin origin)
    : path_(WithoutTrailingSlashes(std::move(path))), force_(force), origin_(std::move(origin)) {
  CheckOutputFolder(path_, force_, origin_.inputs);
  const fs::path p(path_);
  temp_ = path_ + ".tmp-" + std::to_string(::getpid());
  CreateTemporary(path_, temp_);
  try {
    lock_ = OutputLock(temp_, path_, origin_.command);
    CheckNoOtherRun(path_, temp_, false);
  } catch (...) {
    lock_ = OutputLock();
    std::error_code ec;
    fs::remove_all(temp_, ec);
    throw;
  }
  RemoveStaleTemporaries(p.parent_path().string(), p.filename().string());
}

OutputDir::~OutputDir() {
  if (!committed_) {
    lock_ = OutputLock();
    std::error_code ec;
    fs::remove_all(temp_, ec);
  }
}

std::string OutputDir::File(const std::string& name) const { return temp_ + "/" + name; }

void OutputDir::Commit() {
  WriteOutputMarker(temp_, origin_.command, true);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(path_, ec))) {
    if (!force_) throw InputError(path_, "output folder appeared while running; not replaced");
    if (!HasOutputMarker(path_))
      throw InputError(path_,
                       "output folder was replaced while running by one rockcal did not "
                       "write; not replaced");
    const std::string old = path_ + ".old-" + std::to_string(::getpid());
    fs::rename(path_, old, ec);
    if (ec)
      throw std::runtime_error("cannot move the old output folder " + path_ +
                               " aside: " + ec.message());
    fs::rename(temp_, path_, ec);
    if (ec)
      throw std::runtime_error("cannot move the output folder " + temp_ + " to " + path_ + ": " +
                               ec.message());
    fs::remove_all(old, ec);
  } else {
    fs::rename(temp_, path_, ec);
    if (ec)
      throw std::runtime_error("cannot move the output folder " + temp_ + " to " + path_ + ": " +
                               ec.message());
  }
  committed_ = true;
}

ResumableOutputDir::ResumableOutputDir(std::string path, bool resume, bool force,
                                       OutputOrigin origin, const std::string& log,
                                       const std::string& complete_file)
    : path_(WithoutTrailingSlashes(std::move(path))),
      command_(origin.command),
      complete_file_(complete_file) {
  std::error_code ec;
  const fs::path p(path_);
  const std::string name = p.filename().string();
  const bool named = !name.empty() && name != "." && name != "..";
  if (resume) {
    if (path_.empty() || !fs::exists(p / log, ec))
      throw InputError(path_, "nothing to resume: no " + log + " in this folder");
    CheckOutputAgainstInputs(path_, origin.inputs);
    lock_ = OutputLock(path_, path_, origin.command);
    if (named) CheckNoOtherRun(path_, "", true);  // a --force run preparing its replacement
    pending_ = true;
    return;
  }
  if (!force && fs::exists(fs::symlink_status(path_, ec))) {
    if (fs::is_directory(p, ec)) CheckNotLocked(path_, path_);
    throw InputError(path_,
                     "output folder exists already (give --force to replace it, or "
                     "--resume to continue the run it holds)");
  }
  CheckOutputFolder(path_, force, origin.inputs);
  const std::string pid = std::to_string(::getpid());
  const std::string temp = path_ + ".tmp-" + pid;
  CreateTemporary(path_, temp);
  try {
    lock_ = OutputLock(temp, path_, origin.command);
    CheckNoOtherRun(path_, temp, false);
    if (named) RemoveStaleTemporaries(p.parent_path().string(), name);
    WriteOutputMarker(temp, origin.command, std::nullopt);
    WriteFileAtomically(temp + "/" + log, "");
    std::string old;
    if (fs::exists(fs::symlink_status(path_, ec))) {
      // Out of the way in one step; removed once the new folder is in place.
      old = path_ + ".old-" + pid;
      fs::rename(path_, old, ec);
      if (ec)
        throw std::runtime_error("cannot move the old output folder " + path_ +
                                 " aside: " + ec.message());
    }
    fs::rename(temp, path_, ec);
    if (ec) {
      std::error_code ignored;
      if (!old.empty()) fs::rename(old, path_, ignored);
      if (ec == std::errc::file_exists || ec == std::errc::directory_not_empty)
        throw InputError(path_,
                         "appeared while this run created it (another rockcal run?); "
                         "not replaced");
      throw std::runtime_error("cannot create the output folder " + path_ +
                               " (renaming its temporary " + temp + "): " + ec.message());
    }
    if (!old.empty()) fs::remove_all(old, ec);
  } catch (...) {
    lock_ = OutputLock();
    std::error_code ignored;
    fs::remove_all(temp, ignored);
    throw;
  }
}

void ResumableOutputDir::Continue() {
  if (!pending_) return;
  std::error_code ec;
  const fs::path p(path_);
  const std::string name = p.filename().string();
  if (!name.empty() && name != "." && name != "..")
    RemoveStaleTemporaries(p.parent_path().string(), name);
  RemoveStaleTemporariesInside(path_);
  fs::remove(p / complete_file_, ec);
  if (ec)
    throw std::runtime_error("cannot remove the old " + complete_file_ + " of " + path_ + ": " +
                             ec.message());
  WriteOutputMarker(path_, command_, std::nullopt);
  pending_ = false;
}

void WriteWholeFile(const std::string& output, const std::string& file, const std::string& text) {
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + output + ": " + Cause(errno));
  errno = 0;
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  int error = written ? 0 : errno;
  if (std::fflush(f) != 0 && error == 0) error = errno;
  if (std::fclose(f) != 0 && error == 0) error = errno;
  if (!written && error == 0) error = EIO;
  if (error != 0) throw std::runtime_error("cannot write " + output + ": " + Cause(error));
}

void WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string temp = path + ".tmp-" + std::to_string(::getpid());
  try {
    WriteWholeFile(path, temp, text);
  } catch (...) {
    std::remove(temp.c_str());
    throw;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temp.c_str());
    throw std::runtime_error("cannot write " + path + " (renaming its temporary file " + temp +
                             "): " + Cause(error));
  }
}

}  // namespace rockcal::reports
