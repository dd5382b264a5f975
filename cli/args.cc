#include "args.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "rockcal/core/error.h"

namespace rockcal::cli {

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& flags,
           const std::set<std::string>& options, const std::set<std::string>& multi) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.rfind("--", 0) != 0) {
      positionals_.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (flags.count(name)) {
      if (inline_value) throw InputError("argument " + a, "--" + name + " takes no value");
      flags_.insert(name);
    } else if (options.count(name)) {
      if (!inline_value) {
        if (i + 1 >= argv.size()) throw InputError("argument " + a, "--" + name + " needs a value");
        value = argv[++i];
      }
      if (value.empty())
        throw InputError("argument --" + name, "is empty; expected a value after --" + name);
      if (values_.count(name) && !multi.count(name))
        throw InputError("argument " + a, "--" + name + " given twice");
      values_.emplace(name, value);
    } else {
      std::string list;
      for (const auto& f : flags) list += " --" + f;
      for (const auto& o : options) list += " --" + o;
      throw InputError("argument " + a, "unknown option (allowed:" + list + ")");
    }
  }
}

std::string Args::Get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw InputError("arguments", "missing required --" + name);
  return it->second;
}

std::string Args::Get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

std::vector<std::string> Args::All(const std::string& name) const {
  std::vector<std::string> out;
  auto range = values_.equal_range(name);
  for (auto it = range.first; it != range.second; ++it) out.push_back(it->second);
  return out;
}

std::vector<std::string> Args::List(const std::string& name) const {
  const std::string text = Get(name);
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    out.push_back(
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

long Args::Integer(const std::string& name, long fallback, long lo, long hi) const {
  if (!Has(name)) return fallback;
  const std::string v = Get(name);
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(v.c_str(), &end, 10);
  // Digits with an optional minus sign: strtol's leading blanks and '+' are
  // not a whole number as the documentation writes one.
  const bool plain = !v.empty() && (std::isdigit(static_cast<unsigned char>(v[0])) ||
                                    (v[0] == '-' && v.size() > 1));
  if (!plain || *end != '\0' || errno == ERANGE || x < lo || x > hi)
    throw InputError("argument --" + name, "'" + v + "' is not a whole number in [" +
                                               std::to_string(lo) + ", " + std::to_string(hi) +
                                               "]");
  return x;
}

double Args::Number(const std::string& name, double fallback, double lo, double hi) const {
  if (!Has(name)) return fallback;
  const std::string v = Get(name);
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !std::isfinite(x) || x < lo || x > hi) {
    std::ostringstream s;
    s << "'" << v << "' is not a number in [" << lo << ", " << hi << "]";
    throw InputError("argument --" + name, s.str());
  }
  return x;
}

std::string Args::OnlyPositional(const char* what) const {
  if (positionals_.size() != 1)
    throw InputError("arguments", std::string("expected exactly one ") + what + " (found " +
                                      std::to_string(positionals_.size()) + ")");
  return positionals_[0];
}

}  // namespace rockcal::cli
