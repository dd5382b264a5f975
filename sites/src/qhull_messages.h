// Internal to sites/: the messages Qhull writes to a stream, caught in memory
// so that a failed hull or triangulation can quote Qhull's reason (used by
// delaunay.cc and shape_file.cc).
#ifndef ROCKCAL_SITES_SRC_QHULL_MESSAGES_H_
#define ROCKCAL_SITES_SRC_QHULL_MESSAGES_H_

#include <cstdio>
#include <cstdlib>
#include <string>

namespace rockcal::sites {

// Qhull's messages (written to a memory stream) as a string.
class QhullMessages final {
 public:
  QhullMessages() : file_(open_memstream(&text_, &size_)) {}
  ~QhullMessages() {
    if (file_) std::fclose(file_);
    std::free(text_);
  }
  QhullMessages(const QhullMessages&) = delete;
  QhullMessages& operator=(const QhullMessages&) = delete;
  FILE* file() const { return file_; }
  // The first line written, "" when nothing was.
  std::string FirstLine() {
    if (file_) std::fflush(file_);
    const std::string all = text_ ? std::string(text_, size_) : std::string();
    const std::size_t begin = all.find_first_not_of(" \n");
    if (begin == std::string::npos) return "";
    return all.substr(begin, all.find('\n', begin) - begin);
  }

 private:
  char* text_ = nullptr;
  std::size_t size_ = 0;
  FILE* file_;
};

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_SRC_QHULL_MESSAGES_H_
