// THE table of observation kinds (kinds.h). Its order is the order in which
// the reader reads them, ObservationsFileKeys() lists their keys, the misfit
// lists their residuals and the folds draw their deals: a new kind goes at
// the end, so that no earlier result changes.
#include "kinds.h"

#include <algorithm>
#include <cstdlib>

#include "impacts.h"
#include "passing.h"
#include "runout.h"
#include "runs.h"
#include "scars.h"
#include "tracks.h"

namespace rockcal::observations::kinds {

const std::vector<Kind>& Kinds() {
  static const std::vector<Kind> kinds = {
      ScarsKind(),    // tree_scars
      RunoutKind(),   // runout
      RunsKind(),     // runs, runs_file
      PassingKind(),  // passing, passing_file
      TracksKind(),   // tracks_file
      ImpactsKind(),  // impacts, impacts_file
  };
  return kinds;
}

std::vector<std::vector<std::size_t>> Deal(std::size_t n, int k, std::mt19937_64* rng) {
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  for (std::size_t i = n; i > 1; --i) {  // Fisher-Yates, independent of the library's shuffle
    const std::size_t j = static_cast<std::size_t>((*rng)() % i);
    std::swap(order[i - 1], order[j]);
  }
  std::vector<std::vector<std::size_t>> out(static_cast<std::size_t>(k));
  for (std::size_t i = 0; i < n; ++i) out[i % static_cast<std::size_t>(k)].push_back(order[i]);
  for (auto& fold : out) std::sort(fold.begin(), fold.end());
  return out;
}

std::optional<ResidualId> IndexedText(ObservationKind kind, const std::string& key,
                                      const std::string& text) {
  const auto rest = After(text, key + "[");
  if (!rest) return std::nullopt;
  return ResidualId::Of(kind, std::atoi(rest->c_str()), text);
}

bool Keep(const std::vector<std::size_t>& fold_indices, std::size_t i, bool held_out) {
  return std::binary_search(fold_indices.begin(), fold_indices.end(), i) == held_out;
}

}  // namespace rockcal::observations::kinds
