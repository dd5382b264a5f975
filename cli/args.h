// A small argument reader for the rockcal commands: positionals and --flags,
// every error a rockcal::InputError naming the argument.
#ifndef ROCKCAL_CLI_ARGS_H_
#define ROCKCAL_CLI_ARGS_H_

#include <map>
#include <set>
#include <string>
#include <vector>

#include "command_flags.h"

namespace rockcal::cli {

class Args final {
 public:
  // `flags` take no value; `options` take one (and may repeat when listed in `multi`).
  Args(const std::vector<std::string>& argv, const std::set<std::string>& flags,
       const std::set<std::string>& options, const std::set<std::string>& multi = {});
  // What `accepted` (a command's entry of command_flags.h) lists.
  Args(const std::vector<std::string>& argv, const CommandFlags& accepted)
      : Args(argv, accepted.flags, accepted.options, accepted.multi) {}

  const std::vector<std::string>& positionals() const { return positionals_; }
  // The one positional argument, named `what` in the error when not exactly one.
  std::string OnlyPositional(const char* what) const;
  bool Flag(const std::string& name) const { return flags_.count(name) > 0; }
  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name) const;  // required
  std::string Get(const std::string& name, const std::string& fallback) const;
  std::vector<std::string> All(const std::string& name) const;
  // The comma-separated items of the required --name, empty ones kept
  // ("a,," holds three) for the caller to refuse by name.
  std::vector<std::string> List(const std::string& name) const;
  long Integer(const std::string& name, long fallback, long lo, long hi) const;
  double Number(const std::string& name, double fallback, double lo, double hi) const;

 private:
  std::vector<std::string> positionals_;
  std::set<std::string> flags_;
  std::multimap<std::string, std::string> values_;
};

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_ARGS_H_
