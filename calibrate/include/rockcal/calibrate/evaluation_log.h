// The evaluation log of a calibration (DIR/evaluations.jsonl) and the
// fingerprint of what determines its evaluations: what a stopped calibration
// resumes from without repeating work.
#ifndef ROCKCAL_CALIBRATE_EVALUATION_LOG_H_
#define ROCKCAL_CALIBRATE_EVALUATION_LOG_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rockcal/calibrate/evaluation.h"
#include "rockcal/calibrate/parameter_space.h"

namespace rockcal::calibrate {

// What determines a calibration's evaluations, as named parts: the hash of a
// file's bytes, or a value written out ("seed" = "1"). Stored as the first
// line of the evaluation log, so that a resume can name what changed.
struct Fingerprint {
  std::vector<std::pair<std::string, std::string>> parts;  // (what, hash or value), in order

  void Add(std::string what, std::string value) {
    parts.emplace_back(std::move(what), std::move(value));
  }
  // The names of the parts that differ from `logged`'s (changed, added or
  // missing), in this one's order and then `logged`'s.
  std::vector<std::string> Differences(const Fingerprint& logged) const;
};

// FNV-1a (64 bits) of the bytes of `path`, in hex. Throws InputError when the
// file cannot be read.
std::string HashFile(const std::string& path);

// DIR/evaluations.jsonl: a header line {"fingerprint": {...}}, then one JSON
// object per evaluation, appended (and flushed) as each finishes.
class EvaluationLog final {
 public:
  // Starts a new log at `path` (truncating it), or with `resume` reads the
  // records already there first. A log whose header's fingerprint differs
  // from `fingerprint` (the InputError names the parts), a log without a
  // header (an older rockcal's), or a record that does not belong to this
  // calibration (other parameters, seed or rock count) is an InputError.
  // `accepted`, if given, is called once the log is found to be this run's
  // and before the log is first written (rewritten without a torn last line):
  // a resumed output folder ceases to say it is complete before it changes.
  EvaluationLog(std::string path, bool resume, const ParameterSpace& space, std::uint64_t seed,
                int rocks, Fingerprint fingerprint = {},
                const std::function<void()>& accepted = {});
  // Reads the log at `path` as a resume would and throws the InputError it
  // would throw, changing nothing: so that a refused --resume is refused
  // before the folder is touched or anything simulated. `rocks` unknown
  // (nullopt: the rocks a noise check may raise) leaves the fingerprint's
  // "rocks" uncompared, and the records must hold the header's.
  static void Check(const std::string& path, const ParameterSpace& space, std::uint64_t seed,
                    std::optional<int> rocks, const Fingerprint& fingerprint);
  // The logged evaluation of `stage` at exactly `physical`, if any.
  const Evaluation* Find(const Stage& stage, const std::vector<double>& physical) const;
  void Append(const Evaluation& evaluation);
  int size() const { return static_cast<int>(records_.size()); }
  const std::string& path() const { return path_; }

 private:
  void ReadBack();       // the records of a log resumed
  void Rewrite() const;  // the log anew with the records kept, atomically
  std::string path_;
  std::uint64_t seed_;
  int rocks_;
  Fingerprint fingerprint_;
  std::vector<std::string> names_;
  std::vector<Evaluation> records_;
};

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_EVALUATION_LOG_H_
