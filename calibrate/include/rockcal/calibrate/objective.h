// The calibration objective: the whole scene simulated with a fixed seed set
// (common random numbers), so the misfit is a deterministic function of the
// parameters; a failed simulation gives a large finite penalty, never NaN.
#ifndef ROCKCAL_CALIBRATE_OBJECTIVE_H_
#define ROCKCAL_CALIBRATE_OBJECTIVE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

class Objective final {
 public:
  // `scene` is the site's scene with the run's rock count and seed; the
  // recording is reduced to what the observations need.
  Objective(core::Scene scene, ParameterSpace space, observations::Observations observations,
            observations::MisfitOptions misfit);

  const ParameterSpace& space() const { return space_; }
  const core::Scene& scene() const { return scene_; }
  const observations::Observations& observations() const { return observations_; }
  // Number of residuals every evaluation returns.
  int residual_count() const { return residual_count_; }

  // Simulates at `physical` and returns the misfit (residuals always of
  // residual_count(): a penalised evaluation spreads the penalty over them).
  // `result`, when given, receives the simulation.
  observations::Misfit Evaluate(const std::vector<double>& physical,
                                core::SimulationResult* result = nullptr) const;

  // Evaluate at each of `points` (physical values), the points independent
  // of one another: under mpirun each point is simulated whole on one rank,
  // the points handed out to the ranks as they become free
  // (parallel::Map). Misfits in the order of `points`, identical to
  // evaluating them one by one. `done(index, misfit)` follows each point as
  // it finishes (on rank 0 only under mpirun).
  std::vector<observations::Misfit> EvaluateAll(
      const std::vector<std::vector<double>>& points,
      const std::function<void(int, const observations::Misfit&)>& done = nullptr) const;

 private:
  core::Scene scene_;
  ParameterSpace space_;
  observations::Observations observations_;
  observations::MisfitOptions misfit_;
  int residual_count_ = 0;
  // The terrain of the last roughness values (rebuilt only when they change).
  mutable std::mutex terrain_mutex_;
  mutable std::vector<double> terrain_key_;
  mutable std::shared_ptr<const core::Terrain> terrain_;
};

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_OBJECTIVE_H_
