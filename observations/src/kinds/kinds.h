// The kinds of observation (tree scars, runout, tracked runs, passing
// fractions, ...) and THE table of them. Each kind is one file pair in this
// folder holding its file keys, its reader, what it needs recorded, its
// misfit terms and its share of a K-fold split; kinds.cc lists them, in the
// order the reader reads them and the misfit lists their residuals.
// observations/README.md ("Adding a kind") says how to add one. Private to
// observations/src.
#ifndef ROCKCAL_OBSERVATIONS_SRC_KINDS_KINDS_H_
#define ROCKCAL_OBSERVATIONS_SRC_KINDS_KINDS_H_

#include <cstddef>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "rockcal/core/scene.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::observations {

class Reader;        // ../reader.h
struct MisfitTerms;  // ../compare.h

namespace kinds {

// `text` after `prefix` when it begins with it, else nullopt: the name of a
// residual text such as "run v083".
inline std::optional<std::string> After(const std::string& text, const std::string& prefix) {
  if (text.size() <= prefix.size() || text.compare(0, prefix.size(), prefix) != 0)
    return std::nullopt;
  return text.substr(prefix.size());
}
// The index of a text "<key>[<index>] <label>" (a scar set's, a passing
// fraction's) with the whole text as its name, or nullopt for another text.
std::optional<ResidualId> IndexedText(ObservationKind kind, const std::string& key,
                                      const std::string& text);

// One kind of observation. Every function may be null (the kind has no part
// in that step); each one of a kind with nothing observed does nothing.
struct Kind {
  const char* name = "";  // its main key at "$": "tree_scars"
  // Its keys of the file's top object "$" and of its own objects, and its
  // keys of "$.error", each in the reader's order (ObservationsFileKeys()
  // lists "units", every kind's root keys, "error", then the kinds' objects
  // and "$.error" with every kind's error keys).
  std::vector<const char*> root_keys;
  std::vector<sites::FileObjectKeys> objects;
  std::vector<const char*> error_keys;
  // The residual kinds it names (ResidualId::observation() asks the kind
  // that lists a residual's kind for its text).
  std::vector<ObservationKind> residual_kinds;
  std::string (*observation_text)(const ResidualId& id) = nullptr;
  // Its inverse (ResidualId::Parse): the kind, index and name of a text of
  // this kind, or nullopt for a text that is not this kind's.
  std::optional<ResidualId> (*parse_text)(const std::string& text) = nullptr;

  // Reads its keys of the file's top object `root` into `observations`
  // (with its notes); nothing when the file has none of them.
  void (*read)(const Reader& reader, const sites::JsonNode& root,
               Observations* observations) = nullptr;
  // Reads its keys of the file's "error" object.
  void (*read_error)(const Reader& reader, const sites::JsonNode& error,
                     Observations* observations) = nullptr;
  // Why `observations` lack a measurement error this kind needs, "" when
  // they do not; `error` is the file's "error" object or null.
  std::string (*missing_error)(const Observations& observations,
                               const sites::JsonNode* error) = nullptr;
  // What a simulation must record for it (RequiredRecording): appends to
  // base->trees, sets *partitions when it reads partition crossings.
  void (*record)(const Observations& observations, core::RecordOptions* base,
                 bool* partitions) = nullptr;
  // Appends its residuals (ComputeMisfit).
  void (*misfit)(const Observations& observations, const MisfitTerms& terms) = nullptr;
  // Deals its values over the `folds` (MakeFolds), drawing from `rng`.
  void (*fold)(const Observations& observations, int k, std::mt19937_64* rng,
               std::vector<Fold>* folds) = nullptr;
  // Keeps in `out` (a copy of `observations`) only its values out of the
  // fold (held_out false) or in it (held_out true) (Subset).
  void (*subset)(const Observations& observations, const Fold& fold, bool held_out,
                 Observations* out) = nullptr;
};

// THE table: every kind once, in reading and residual order.
const std::vector<Kind>& Kinds();

// For the kinds' folds: indices 0..n-1, shuffled with `rng`, dealt
// round-robin into k ascending lists; and whether index i is in
// `fold_indices` (held_out) or not (training).
std::vector<std::vector<std::size_t>> Deal(std::size_t n, int k, std::mt19937_64* rng);
bool Keep(const std::vector<std::size_t>& fold_indices, std::size_t i, bool held_out);

}  // namespace kinds
}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_SRC_KINDS_KINDS_H_
