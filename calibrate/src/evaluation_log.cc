// The evaluation log and the fingerprint of a calibration (evaluation_log.h).
#include "rockcal/calibrate/evaluation_log.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/core/error.h"
#include "rockcal/sites/input_file.h"

namespace rockcal::calibrate {
namespace {

nlohmann::json ToJson(const Evaluation& e) {
  return {{"method", e.stage.name()}, {"evaluation", e.index},    {"parameters", e.parameters},
          {"misfit", e.misfit},       {"residuals", e.residuals}, {"penalised", e.penalised},
          {"seconds", e.seconds},     {"elapsed", e.elapsed},     {"log_scale", e.log_scale}};
}

// A whole-number field of a log record, from 0 to T's maximum. A fraction, a
// negative number or one beyond T (1e300) is not a record rockcal wrote, and
// converting it would be undefined behaviour.
template <typename T>
T WholeField(const nlohmann::json& record, const char* key, const std::string& where) {
  const nlohmann::json& v = record.at(key);
  if (v.is_number_unsigned()) {
    const std::uint64_t u = v.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())) return static_cast<T>(u);
  }
  throw InputError(where, std::string("not an evaluation record: \"") + key + "\" is " +
                              (v.is_number() ? v.dump() : std::string("a ") + v.type_name()) +
                              "; expected a whole number from 0 to " +
                              std::to_string(std::numeric_limits<T>::max()));
}

}  // namespace

std::vector<std::string> Fingerprint::Differences(const Fingerprint& logged) const {
  std::vector<std::string> out;
  auto find = [](const Fingerprint& f, const std::string& what) -> const std::string* {
    for (const auto& [name, value] : f.parts)
      if (name == what) return &value;
    return nullptr;
  };
  for (const auto& [name, value] : parts) {
    const std::string* old = find(logged, name);
    if (!old || *old != value) out.push_back(name);
  }
  for (const auto& [name, value] : logged.parts)
    if (!find(*this, name)) out.push_back(name);
  return out;
}

std::string HashFile(const std::string& path) {
  sites::CheckInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot read the file to fingerprint it");
  std::uint64_t h = 14695981039346656037ull;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize k = 0; k < in.gcount(); ++k) {
      h ^= static_cast<unsigned char>(buffer[k]);
      h *= 1099511628211ull;
    }
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

namespace {

// A resumed log's header: the fingerprint of the inputs it was made with,
// which must be `fingerprint` but for the parts named in `unknown`. Returns
// the logged fingerprint.
Fingerprint CheckLogHeader(const std::string& line, const std::string& where,
                           const Fingerprint& fingerprint,
                           const std::vector<std::string>& unknown) {
  nlohmann::json h = nlohmann::json::parse(line, nullptr, false);
  if (h.is_discarded() || !h.is_object() || !h.contains("fingerprint") ||
      !h["fingerprint"].is_object())
    throw InputError(where,
                     "no fingerprint header (a log written by an older rockcal, or not an "
                     "evaluation log): cannot tell whether its evaluations still hold; start "
                     "afresh with --force instead of --resume");
  Fingerprint logged;
  for (const auto& [name, value] : h["fingerprint"].items())
    logged.Add(name, value.is_string() ? value.get<std::string>() : value.dump());
  std::vector<std::string> changed = fingerprint.Differences(logged);
  changed.erase(std::remove_if(changed.begin(), changed.end(),
                               [&](const std::string& c) {
                                 return std::find(unknown.begin(), unknown.end(), c) !=
                                        unknown.end();
                               }),
                changed.end());
  if (!changed.empty()) {
    std::string list;
    for (const std::string& c : changed) list += (list.empty() ? "" : ", ") + c;
    throw InputError(where,
                     "cannot resume: what determines the evaluations changed since "
                     "this log was written: " +
                         list + "; restore it, or start afresh with --force instead of --resume");
  }
  return logged;
}

// One record of a resumed log, of the calibration at `seed`, `rocks` and
// parameter `names`. Throws nlohmann::json's exceptions on a line that is
// not a record.
Evaluation ReadLogRecord(const std::string& line, const std::string& where, std::uint64_t seed,
                         int rocks, const std::vector<std::string>& names) {
  const nlohmann::json j = nlohmann::json::parse(line);
  if (WholeField<std::uint64_t>(j, "seed", where) != seed ||
      WholeField<int>(j, "rocks", where) != rocks ||
      j.at("names").get<std::vector<std::string>>() != names)
    throw InputError(where,
                     "record of another calibration (different parameters, --seed or "
                     "--rocks); start afresh with --force instead of --resume");
  Evaluation e;
  const std::string method = j.at("method").get<std::string>();
  if (!Stage::FromName(method, &e.stage))
    throw InputError(where, "not an evaluation record: method '" + method + "' (expected one of " +
                                MethodNames() + ", or posterior)");
  e.index = WholeField<int>(j, "evaluation", where);
  e.parameters = j.at("parameters").get<std::vector<double>>();
  e.misfit = j.at("misfit").get<double>();
  e.residuals = j.at("residuals").get<std::vector<double>>();
  // Absent from a log written before the sigmas' log-likelihood term: not
  // known (the posterior simulates such a point again).
  const auto scale = j.find("log_scale");
  if (scale != j.end() && scale->is_number()) e.log_scale = scale->get<double>();
  e.penalised = j.at("penalised").get<bool>();
  e.seconds = j.at("seconds").get<double>();
  e.elapsed = j.at("elapsed").get<double>();
  return e;
}

// The records of the log at `path`, whose fingerprint must be
// `fingerprint` (but for the rocks when `rocks` is unknown), of the
// calibration at `seed`, `rocks` and parameter `names`. Reads only.
std::vector<Evaluation> ReadLog(const std::string& path, const Fingerprint& fingerprint,
                                std::uint64_t seed, std::optional<int> rocks,
                                const std::vector<std::string>& names) {
  sites::CheckInputFile(path);
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot resume: no evaluation log here");
  std::vector<Evaluation> records;
  std::string line;
  int number = 0;
  bool header = false;
  // Per method, the last evaluation logged and its line: a run appends its
  // evaluations in order, and a resumed run only after the last, so an
  // evaluation logged again or out of order is the line of another run
  // (two runs writing the same folder at once).
  std::map<Stage, std::pair<int, int>> last;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(number);
    sites::CheckJsonDepth(line, where);
    if (!header) {
      const Fingerprint logged =
          CheckLogHeader(line, where, fingerprint,
                         rocks ? std::vector<std::string>{} : std::vector<std::string>{"rocks"});
      if (!rocks) {
        // The records must hold the rocks the header names.
        rocks = -1;
        for (const auto& [name, value] : logged.parts)
          if (name == "rocks") {
            char* end = nullptr;
            const long n = std::strtol(value.c_str(), &end, 10);
            if (end != value.c_str() && *end == '\0' && n > 0 &&
                n <= std::numeric_limits<int>::max())
              rocks = static_cast<int>(n);
          }
        if (*rocks < 0)
          throw InputError(where,
                           "cannot resume: the header names no rock count; start afresh "
                           "with --force instead of --resume");
      }
      header = true;
      continue;
    }
    try {
      Evaluation e = ReadLogRecord(line, where, seed, *rocks, names);
      auto [before, inserted] = last.try_emplace(e.stage, e.index, number);
      if (!inserted && e.index <= before->second.first)
        throw InputError(where, e.stage.name() + " evaluation " + std::to_string(e.index) +
                                    " after its evaluation " +
                                    std::to_string(before->second.first) + " (line " +
                                    std::to_string(before->second.second) +
                                    "): the log holds the lines of two runs that wrote this "
                                    "folder at once, so it cannot be resumed; start afresh "
                                    "with --force instead of --resume");
      before->second = {e.index, number};
      records.push_back(std::move(e));
    } catch (const nlohmann::json::exception&) {
      // A line cut short by a killed run is the only damage expected: the
      // last line. Anything else is not ours.
      if (in.peek() == EOF) break;
      throw InputError(where, "not an evaluation record (expected one JSON object per line)");
    }
  }
  return records;
}

}  // namespace

EvaluationLog::EvaluationLog(std::string path, bool resume, const ParameterSpace& space,
                             std::uint64_t seed, int rocks, Fingerprint fingerprint,
                             const std::function<void()>& accepted)
    : path_(std::move(path)), seed_(seed), rocks_(rocks), fingerprint_(std::move(fingerprint)) {
  for (const auto& p : space.parameters()) names_.push_back(p.label());
  if (resume) ReadBack();
  if (accepted) accepted();
  Rewrite();
}

// The records of the log at path_, whose fingerprint must be this run's.
void EvaluationLog::ReadBack() { records_ = ReadLog(path_, fingerprint_, seed_, rocks_, names_); }

void EvaluationLog::Check(const std::string& path, const ParameterSpace& space, std::uint64_t seed,
                          std::optional<int> rocks, const Fingerprint& fingerprint) {
  std::vector<std::string> names;
  for (const auto& p : space.parameters()) names.push_back(p.label());
  ReadLog(path, fingerprint, seed, rocks, names);
}

// Rewrites the log with the good records only (drops a torn last line),
// through a temporary file renamed into place: a run killed meanwhile
// leaves the old log whole.
void EvaluationLog::Rewrite() const {
  const std::string temp = path_ + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::trunc);
    if (!out)
      throw std::runtime_error("cannot write the evaluation log " + path_ + " (its temporary " +
                               temp + "): " + std::strerror(errno));
    nlohmann::json parts = nlohmann::json::object();
    for (const auto& [name, value] : fingerprint_.parts) parts[name] = value;
    out << nlohmann::json{{"fingerprint", parts}}.dump() << '\n';
    for (const Evaluation& e : records_) {
      nlohmann::json j = ToJson(e);
      j["seed"] = seed_;
      j["rocks"] = rocks_;
      j["names"] = names_;
      out << j.dump() << '\n';
    }
    out.flush();
    if (!out) {
      const int error = errno;
      std::remove(temp.c_str());
      throw std::runtime_error("cannot write the evaluation log " + path_ + " (its temporary " +
                               temp + "): " + std::strerror(error));
    }
  }
  if (std::rename(temp.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    std::remove(temp.c_str());
    throw std::runtime_error("cannot write the evaluation log " + path_ +
                             " (renaming its temporary " + temp + "): " + std::strerror(error));
  }
}

const Evaluation* EvaluationLog::Find(const Stage& stage,
                                      const std::vector<double>& physical) const {
  for (const Evaluation& e : records_)
    if (e.stage == stage && e.parameters == physical) return &e;
  return nullptr;
}

void EvaluationLog::Append(const Evaluation& evaluation) {
  nlohmann::json j = ToJson(evaluation);
  j["seed"] = seed_;
  j["rocks"] = rocks_;
  j["names"] = names_;
  // The first write that fails (a full disk, a file size limit) stops the
  // run here, the records before it kept whole: the stream is flushed and
  // closed, and either failing is the write failing (docs/reference/errors.md).
  std::ofstream out(path_, std::ios::app);
  errno = 0;
  if (out) out << j.dump() << '\n';
  if (out) out.flush();
  if (out) out.close();
  if (!out)
    throw std::runtime_error("cannot write the evaluation log " + path_ + ": " +
                             std::strerror(errno != 0 ? errno : EIO));
  records_.push_back(evaluation);
}

}  // namespace rockcal::calibrate
