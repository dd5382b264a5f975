// Errors a user can cause (bad files, JSON, values). Carries where the problem
// is (file, JSON path or line), so the command line can print it and exit 2.
#ifndef ROCKCAL_CORE_ERROR_H_
#define ROCKCAL_CORE_ERROR_H_

#include <stdexcept>
#include <string>

namespace rockcal {

class InputError final : public std::runtime_error {
 public:
  // `where` is "file: JSON path" or "file:line"; `what` says the value and
  // what was expected.
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what),
        where_(where),
        detail_(what) {}
  const std::string& where() const { return where_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string where_;
  std::string detail_;
};

}  // namespace rockcal

#endif  // ROCKCAL_CORE_ERROR_H_
