#include "rockcal/reports/output_dir.h"

#include <signal.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "rockcal/core/error.h"

#ifndef ROCKCAL_VERSION
#define ROCKCAL_VERSION "unknown"
#endif

namespace rockcal::reports {
namespace {

namespace fs = std::filesystem;

// `path` made absolute, with links and "..", "." resolved as far as it exists.
fs::path Canonical(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
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

}  // namespace

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
    std::error_code remove_ec;
    if (fs::remove_all(it->path(), remove_ec) > 0 && !remove_ec) ++removed;
  }
  return removed;
}

OutputDir::OutputDir(std::string path, bool force, OutputOrigin origin)
    : path_(std::move(path)), force_(force), origin_(std::move(origin)) {
  while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
  CheckOutputFolder(path_, force_, origin_.inputs);
  const fs::path p(path_);
  RemoveStaleTemporaries(p.parent_path().string(), p.filename().string());
  temp_ = path_ + ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(temp_, ec);
  if (!fs::create_directory(temp_, ec))
    throw std::runtime_error("cannot create the output folder " + path_ + " (its temporary " +
                             temp_ + "): " + ec.message());
}

OutputDir::~OutputDir() {
  if (!committed_) {
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
