// An output folder that appears whole or not at all: files are written into a
// temporary sibling folder and renamed into place by Commit().
#ifndef ROCKCAL_REPORTS_OUTPUT_DIR_H_
#define ROCKCAL_REPORTS_OUTPUT_DIR_H_

#include <string>

namespace rockcal::reports {

class OutputDir final {
 public:
  // Throws InputError if `path` exists and `force` is false (nothing is
  // touched), or if its parent folder does not exist.
  OutputDir(std::string path, bool force);
  ~OutputDir();  // removes the temporary folder unless committed
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  // Where to write file `name` now (inside the temporary folder).
  std::string File(const std::string& name) const;
  // The temporary folder itself.
  const std::string& folder() const { return temp_; }
  // Replaces `path` by the temporary folder (an existing one only with force).
  void Commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, temp_;
  bool force_ = false, committed_ = false;
};

// Writes `text` to `path` through a temporary file renamed into place.
void WriteFileAtomically(const std::string& path, const std::string& text);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_OUTPUT_DIR_H_
