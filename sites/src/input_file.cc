#include "rockcal/sites/input_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "rockcal/core/error.h"

namespace rockcal::sites {

namespace {

// What is wrong with a file of mode `mode` as an input ("is a folder,
// expected a file"); empty for a regular file.
std::string KindProblem(mode_t mode) {
  if (S_ISREG(mode)) return "";
  if (S_ISDIR(mode)) return "is a folder, expected a file";
  std::string kind = "not a regular file";
  if (S_ISFIFO(mode)) kind = "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) kind = "a socket";
  if (S_ISCHR(mode)) kind = "a character device";
  if (S_ISBLK(mode)) kind = "a block device";
  return "is " + kind + ", expected a regular file (not read: it could block or never end)";
}

}  // namespace

void CheckInputFile(const std::string& path) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0) return;
  const std::string problem = KindProblem(st.st_mode);
  if (!problem.empty()) throw InputError(path, problem);
}

std::string InputFileProblem(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || ::access(path.c_str(), R_OK) != 0)
    return "cannot open " + what + " '" + path + "': " + std::strerror(errno);
  const std::string problem = KindProblem(st.st_mode);
  return problem.empty() ? "" : "'" + path + "' " + problem;
}

int JsonDepth(const std::string& text) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > deepest) deepest = depth;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

void CheckJsonDepth(const std::string& text, const std::string& where) {
  const int depth = JsonDepth(text);
  if (depth > kMaxJsonDepth)
    throw InputError(where, "JSON nested " + std::to_string(depth) +
                                " levels deep (arrays and objects); expected at most " +
                                std::to_string(kMaxJsonDepth) + " (rockcal's files nest a few)");
}

}  // namespace rockcal::sites
