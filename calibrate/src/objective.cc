#include "rockcal/calibrate/objective.h"

#include <cmath>
#include <exception>

#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/residual_correlation.h"
#include "rockcal/parallel/parallel.h"

namespace rockcal::calibrate {
namespace {

// The roughness values of `physical` (the terrain's cache key).
std::vector<double> RoughnessKey(const ParameterSpace& space, const std::vector<double>& physical) {
  std::vector<double> key;
  for (std::size_t k = 0; k < physical.size(); ++k)
    if (space.parameters()[k].kind == ParameterKind::kRoughness) key.push_back(physical[k]);
  return key;
}

}  // namespace

Evaluation EvaluationOf(const Stage& stage, const std::vector<double>& physical,
                        const observations::Misfit& m) {
  Evaluation e;
  e.stage = stage;
  e.parameters = physical;
  e.misfit = m.value;
  e.log_scale = m.log_scale;
  e.penalised = m.penalised;
  for (const observations::Residual& r : m.residuals) e.residuals.push_back(r.value);
  return e;
}

std::string EncodeMisfit(const observations::Misfit& m) {
  parallel::Writer w;
  w.Double(m.value);
  w.Double(m.log_scale);
  w.Int(m.penalised ? 1 : 0);
  w.String(m.message);
  w.Int(static_cast<long long>(m.residuals.size()));
  for (const observations::Residual& r : m.residuals) {
    w.Int(static_cast<long long>(r.id.kind));
    w.Int(r.id.index);
    w.String(r.id.name);
    w.Int(static_cast<long long>(r.id.statistic));
    w.Double(r.id.level);
    w.String(r.id.site);
    w.Double(r.simulated);
    w.Double(r.observed);
    w.Double(r.sigma);
    w.Double(r.value);
    w.Double(r.fixed_sigma);
  }
  return w.bytes();
}

observations::Misfit DecodeMisfit(const std::string& bytes) {
  parallel::Reader r(bytes);
  observations::Misfit m;
  m.value = r.Double();
  m.log_scale = r.Double();
  m.penalised = r.Int() != 0;
  m.message = r.String();
  m.residuals.resize(static_cast<std::size_t>(r.Int()));
  for (observations::Residual& res : m.residuals) {
    res.id.kind = static_cast<observations::ObservationKind>(r.Int());
    res.id.index = static_cast<int>(r.Int());
    res.id.name = r.String();
    res.id.statistic = static_cast<observations::Statistic>(r.Int());
    res.id.level = r.Double();
    res.id.site = r.String();
    res.simulated = r.Double();
    res.observed = r.Double();
    res.sigma = r.Double();
    res.value = r.Double();
    res.fixed_sigma = r.Double();
  }
  return m;
}

std::vector<observations::Misfit> Objective::EvaluateAll(
    const std::vector<std::vector<double>>& points,
    const std::function<void(int, const observations::Misfit&)>& done) const {
  return MapMisfits(
      static_cast<int>(points.size()),
      [&](int k) { return Evaluate(points[static_cast<std::size_t>(k)]); }, done);
}

std::vector<observations::Misfit> MapMisfits(
    int n, const std::function<observations::Misfit(int)>& evaluate,
    const std::function<void(int, const observations::Misfit&)>& done) {
  const std::vector<std::string> bytes = parallel::Map(
      n, [&](int k) { return EncodeMisfit(evaluate(k)); },
      [&](int k, const std::string& b) {
        if (done) done(k, DecodeMisfit(b));
      });
  std::vector<observations::Misfit> out;
  out.reserve(bytes.size());
  for (const std::string& b : bytes) out.push_back(DecodeMisfit(b));
  return out;
}

Objective::Objective(core::Scene scene, ParameterSpace space,
                     observations::Observations observations, observations::MisfitOptions misfit)
    : scene_(std::move(scene)),
      space_(std::move(space)),
      observations_(std::move(observations)),
      misfit_(std::move(misfit)) {
  RecordingNeeds needs;
  needs.observations = &observations_;
  needs.energy_check = scene_.options.record.energy_check;  // as the caller asked
  scene_.options.record = RecordingFor(scene_, needs);
  // The number of residuals follows from the observations alone: count them
  // on an empty result shaped like a real one.
  core::SimulationResult shape;
  shape.rocks.resize(2);
  // Every field set: `{}` for the crossing point would leave the Eigen vector
  // uninitialised, and a NaN there made the shape "non-finite" (no residuals).
  const core::Crossing crossed{true, 1.0, 1.0, 1.0, Eigen::Vector3d::Zero()};
  for (auto& r : shape.rocks) {
    r.outcome = core::Outcome::kStopped;
    r.crossings.assign(scene_.partitions.size(), crossed);
    r.trees.assign(scene_.options.record.trees.size(), crossed);
    r.trajectory.assign(
        1, core::TrajectorySample{0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                  Eigen::Vector3d::Zero(), Eigen::Vector4d(1, 0, 0, 0)});
  }
  shape.rocks[1].stop = Eigen::Vector3d(1, 1, 0);
  for (const core::ImpactReplay& impact : scene_.options.record.impacts) {
    core::ImpactRebound replays;
    replays.velocity.assign(static_cast<std::size_t>(impact.draws), Eigen::Vector3d(1, 0, 1));
    replays.left.assign(static_cast<std::size_t>(impact.draws), 1);
    shape.impacts.push_back(std::move(replays));
  }
  residual_count_ = static_cast<int>(
      observations::ComputeMisfit(observations_, scene_, shape, misfit_).residuals.size());
}

core::SimulationResult Objective::Simulate(const std::vector<double>& physical,
                                          core::Scene* scene) const {
  *scene = scene_;
  space_.Apply(physical, scene);
  std::shared_ptr<const core::Terrain> terrain;
  {
    std::lock_guard<std::mutex> lock(terrain_mutex_);
    const std::vector<double> key = RoughnessKey(space_, physical);
    if (!terrain_ || key != terrain_key_) {
      terrain_ = std::make_shared<const core::Terrain>(core::BuildTerrain(*scene));
      terrain_key_ = key;
    }
    terrain = terrain_;
  }
  return parallel::Simulate(*scene, *terrain);
}

Eigen::MatrixXd Objective::ResidualCorrelation(const std::vector<double>& physical, int replicates,
                                               std::uint64_t seed) const {
  try {
    core::Scene scene;
    const core::SimulationResult sim = Simulate(physical, &scene);
    Eigen::MatrixXd r =
        BootstrapResidualCorrelation(observations_, scene, sim, misfit_, replicates, seed);
    if (r.rows() != residual_count_) return {};
    return r;
  } catch (const std::exception&) {
    return {};  // a failed simulation: no correlation to tell
  }
}

observations::Misfit Objective::Evaluate(const std::vector<double>& physical) const {
  core::Scene scene;
  observations::Misfit misfit;
  try {
    const core::SimulationResult sim = Simulate(physical, &scene);
    misfit = observations::ComputeMisfit(observations_, scene, sim, misfit_);
  } catch (const std::exception& e) {
    misfit = observations::Misfit{};
    misfit.value = misfit_.penalty;
    misfit.penalised = true;
    misfit.message = std::string("simulation failed: ") + e.what();
  }
  if (!std::isfinite(misfit.value)) {
    misfit.value = misfit_.penalty;
    misfit.penalised = true;
  }
  // Keep the residual vector's length fixed: spread a penalty over it.
  if (static_cast<int>(misfit.residuals.size()) != residual_count_) {
    misfit.residuals.assign(static_cast<std::size_t>(residual_count_), observations::Residual{});
    const double each = residual_count_ > 0 ? std::sqrt(2.0 * misfit.value / residual_count_) : 0.0;
    for (auto& r : misfit.residuals) r.value = each;
  }
  for (auto& r : misfit.residuals)
    if (!std::isfinite(r.value)) r.value = std::sqrt(2.0 * misfit_.penalty / std::max(residual_count_, 1));
  return misfit;
}

}  // namespace rockcal::calibrate
