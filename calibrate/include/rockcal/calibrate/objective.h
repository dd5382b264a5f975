// What a calibration searches (ObjectiveFunction), and the calibration
// objective of one site (Objective): the whole scene simulated with a fixed
// seed set (common random numbers), so the misfit is a deterministic
// function of the parameters; a failed simulation gives a large finite
// penalty, never NaN.
#ifndef ROCKCAL_CALIBRATE_OBJECTIVE_H_
#define ROCKCAL_CALIBRATE_OBJECTIVE_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rockcal/calibrate/evaluation.h"
#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// What the calibration methods (RunMethod), the evaluation log and the
// uncertainty see of a calibration: a residual vector of fixed length, a
// deterministic function of the physical values of a box of parameters. One
// site's Objective and a campaign's joint objective (CampaignObjective, of
// several sites) implement it, so both are searched by the same code.
class ObjectiveFunction {
 public:
  virtual ~ObjectiveFunction() = default;

  // The parameters searched, with their bounds.
  virtual const ParameterSpace& space() const = 0;
  // Number of residuals every evaluation returns.
  virtual int residual_count() const = 0;
  // The misfit at `physical` (residuals always of residual_count(): a
  // penalised evaluation spreads the penalty over them); never throws for a
  // failed simulation.
  virtual observations::Misfit Evaluate(const std::vector<double>& physical) const = 0;
  // Evaluate at each of `points` (physical values), the points independent
  // of one another, spread over the ranks under mpirun (parallel::Map).
  // Misfits in the order of `points`, identical to evaluating them one by
  // one. `done(index, misfit)` follows each point as it finishes (on rank 0
  // only under mpirun).
  virtual std::vector<observations::Misfit> EvaluateAll(
      const std::vector<std::vector<double>>& points,
      const std::function<void(int, const observations::Misfit&)>& done = nullptr) const = 0;
  // The correlation of the residuals' errors at `physical`, residual_count()
  // square with a unit diagonal, from `replicates` bootstrap resamples of
  // the rocks simulated there (BootstrapResidualCorrelation, seeded by
  // `seed`); empty when the objective cannot tell (this default) or its
  // evaluation there is penalised.
  virtual Eigen::MatrixXd ResidualCorrelation(const std::vector<double>& /*physical*/,
                                              int /*replicates*/, std::uint64_t /*seed*/) const {
    return {};
  }
};

// The evaluation by `stage` at `physical` whose misfit is `m`: its value,
// log term, penalty and residuals' values (the index and times are the
// caller's).
Evaluation EvaluationOf(const Stage& stage, const std::vector<double>& physical,
                        const observations::Misfit& m);

class Objective final : public ObjectiveFunction {
 public:
  // `scene` is the site's scene with the run's rock count and seed; the
  // recording is reduced to what the observations need.
  Objective(core::Scene scene, ParameterSpace space, observations::Observations observations,
            observations::MisfitOptions misfit);

  const ParameterSpace& space() const override { return space_; }
  const core::Scene& scene() const { return scene_; }
  const observations::Observations& observations() const { return observations_; }
  const observations::MisfitOptions& misfit_options() const { return misfit_; }
  int residual_count() const override { return residual_count_; }

  // Simulates the scene at `physical` (every rank's share of its rocks
  // under mpirun, parallel::Simulate) and returns the misfit.
  observations::Misfit Evaluate(const std::vector<double>& physical) const override;

  // Under mpirun each point is simulated whole on one rank, the points
  // handed out to the ranks as they become free (parallel::Map).
  std::vector<observations::Misfit> EvaluateAll(
      const std::vector<std::vector<double>>& points,
      const std::function<void(int, const observations::Misfit&)>& done = nullptr) const override;

  // Simulates the scene at `physical` as Evaluate does and bootstraps its
  // rocks (BootstrapResidualCorrelation).
  Eigen::MatrixXd ResidualCorrelation(const std::vector<double>& physical, int replicates,
                                      std::uint64_t seed) const override;

 private:
  // The scene at `physical` (into *scene) simulated on the terrain of its
  // roughness (built once per roughness), every rank's share under mpirun.
  core::SimulationResult Simulate(const std::vector<double>& physical, core::Scene* scene) const;

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

// A misfit as bytes for parallel::Map (every field, doubles bit for bit),
// and back.
std::string EncodeMisfit(const observations::Misfit& misfit);
observations::Misfit DecodeMisfit(const std::string& bytes);

// evaluate(0), ..., evaluate(n - 1), independent of one another, handed to
// the ranks by parallel::Map (in this process without MPI); the misfits in
// index order, `done(k, misfit)` after each (on rank 0 under mpirun).
std::vector<observations::Misfit> MapMisfits(
    int n, const std::function<observations::Misfit(int)>& evaluate,
    const std::function<void(int, const observations::Misfit&)>& done);

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_OBJECTIVE_H_
