// The public functions of observations.h that go over every kind of
// observation (kinds/kinds.cc lists them): what a simulation must record and
// the K-fold split. LoadObservations is in reader.cc, each kind's part in
// its own file pair under kinds/.
#include "rockcal/observations/observations.h"

#include <random>

#include "kinds/kinds.h"
#include "rockcal/core/error.h"

namespace rockcal::observations {

core::RecordOptions RequiredRecording(const Observations& observations, core::RecordOptions base) {
  bool partitions = false;
  base.trees.clear();
  for (const kinds::Kind& kind : kinds::Kinds())
    if (kind.record) kind.record(observations, &base, &partitions);
  base.partitions = partitions;
  return base;
}

std::vector<Fold> MakeFolds(const Observations& observations, int k, std::uint64_t seed) {
  if (k < 2) throw InputError("--holdout", std::to_string(k) + ": expected at least 2 folds");
  std::mt19937_64 rng(seed);
  std::vector<Fold> folds(static_cast<std::size_t>(k));
  for (int f = 0; f < k; ++f) {
    folds[static_cast<std::size_t>(f)].index = f;
    folds[static_cast<std::size_t>(f)].count = k;
  }
  for (const kinds::Kind& kind : kinds::Kinds())
    if (kind.fold) kind.fold(observations, k, &rng, &folds);
  return folds;
}

Observations Subset(const Observations& observations, const Fold& fold, bool held_out) {
  Observations out = observations;
  for (const kinds::Kind& kind : kinds::Kinds())
    if (kind.subset) kind.subset(observations, fold, held_out, &out);
  return out;
}

Eigen::Vector2d ReleaseCentroid(const core::Release& release) {
  const std::vector<Eigen::Vector2d>& zone = release.zone;
  if (zone.empty()) return release.point;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : zone) mean += p;
  mean /= static_cast<double>(zone.size());
  // Area centroid (shoelace), relative to the vertex mean for accuracy.
  double twice_area = 0.0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double extent = 0.0;
  for (std::size_t i = 0; i < zone.size(); ++i) {
    const Eigen::Vector2d a = zone[i] - mean;
    const Eigen::Vector2d b = zone[(i + 1) % zone.size()] - mean;
    const double cross = a.x() * b.y() - b.x() * a.y();
    twice_area += cross;
    sum += (a + b) * cross;
    extent = std::max(extent, a.norm());
  }
  if (!(std::abs(twice_area) > 1e-12 * extent * extent)) return mean;
  return mean + sum / (3.0 * twice_area);
}

}  // namespace rockcal::observations
