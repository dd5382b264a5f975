#include "rockcal/reports/output_dir.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

#include "rockcal/core/error.h"

namespace rockcal::reports {

namespace fs = std::filesystem;

OutputDir::OutputDir(std::string path, bool force) : path_(std::move(path)), force_(force) {
  while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
  std::error_code ec;
  if (fs::exists(path_, ec) && !force_)
    throw InputError(path_, "output folder exists already (give --force to replace it)");
  fs::path parent = fs::path(path_).parent_path();
  if (parent.empty()) parent = ".";
  if (!fs::is_directory(parent, ec))
    throw InputError(path_, "the folder that should hold it does not exist: " + parent.string());
  temp_ = path_ + ".tmp-" + std::to_string(::getpid());
  fs::remove_all(temp_, ec);
  if (!fs::create_directory(temp_, ec))
    throw InputError(temp_, "cannot create the temporary output folder: " + ec.message());
}

OutputDir::~OutputDir() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_, ec);
  }
}

std::string OutputDir::File(const std::string& name) const { return temp_ + "/" + name; }

void OutputDir::Commit() {
  std::error_code ec;
  if (fs::exists(path_, ec)) {
    if (!force_) throw InputError(path_, "output folder appeared while running; not replaced");
    const std::string old = path_ + ".old-" + std::to_string(::getpid());
    fs::rename(path_, old);
    fs::rename(temp_, path_);
    fs::remove_all(old, ec);
  } else {
    fs::rename(temp_, path_);
  }
  committed_ = true;
}

void WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string temp = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write " + temp);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + temp);
  }
  fs::rename(temp, path);
}

}  // namespace rockcal::reports
