#include "rockcal/sites/input_file.h"

#include <sys/stat.h>

#include "rockcal/core/error.h"

namespace rockcal::sites {

void CheckInputFile(const std::string& path) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
  std::string kind = "not a regular file";
  if (S_ISDIR(st.st_mode)) throw InputError(path, "is a folder, expected a file");
  if (S_ISFIFO(st.st_mode)) kind = "a FIFO (named pipe)";
  if (S_ISSOCK(st.st_mode)) kind = "a socket";
  if (S_ISCHR(st.st_mode)) kind = "a character device";
  if (S_ISBLK(st.st_mode)) kind = "a block device";
  throw InputError(path, "is " + kind +
                             ", expected a regular file (not read: it could block "
                             "or never end)");
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
