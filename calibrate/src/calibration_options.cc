// The calibration's options: their check, the resolved defaults, the
// single-stage search a campaign runs, the posterior stage's names
// (calibration_run.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/name_table.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"

namespace rockcal::calibrate {

namespace {
constexpr core::Named<PosteriorStage> kPosteriorStages[] = {{PosteriorStage::kFirst, "first"},
                                                            {PosteriorStage::kFinal, "final"}};
}  // namespace

const char* PosteriorStageToString(PosteriorStage stage) {
  return core::NameOf(kPosteriorStages, stage);
}
bool StringToPosteriorStage(const std::string& name, PosteriorStage* stage) {
  return core::IdOf(kPosteriorStages, name, stage);
}

bool CalibrationOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (methods.empty()) {
    s << "methods: empty; give at least one of " << MethodNames();
  } else if (rocks < 0) {
    s << "rocks = " << rocks << ": must be >= 0 (0: the site's counts)";
  } else if (threads < 0) {
    s << "threads = " << threads << ": must be >= 0 (0: OpenMP's default)";
  } else if (reach_points < kAuto || reach_points == 1) {
    s << "reach_points = " << reach_points << ": must be kAuto (-1), 0 (none) or at least 2";
  } else if (refine_factor < 1) {
    s << "refine_factor = " << refine_factor << ": must be >= 1 (1: one stage)";
  } else if (!(refine_share > 0.0 && refine_share < 1.0)) {
    s << "refine_share = " << refine_share << ": must be in (0, 1)";
  } else if (!(refine_step > 0.0 && refine_step <= 1.0)) {
    s << "refine_step = " << refine_step << ": must be in (0, 1]";
  } else if (noise_check_seeds < 0) {
    s << "noise_check_seeds = " << noise_check_seeds << ": must be >= 0 (0: no check)";
  } else if (!(noise_check_ratio > 0.0 && noise_check_ratio <= 1.0)) {
    s << "noise_check_ratio = " << noise_check_ratio << ": must be in (0, 1]";
  } else if (noise_raise < 1) {
    s << "noise_raise = " << noise_raise << ": must be >= 1 (1: never raise the rocks)";
  } else if (race_points < kAuto) {
    s << "race_points = " << race_points << ": must be kAuto (-1) or >= 0 (0: no race)";
  } else if (noise_seeds < 0) {
    s << "noise_seeds = " << noise_seeds << ": must be >= 0";
  } else if (resume && log_path.empty()) {
    s << "resume needs a log_path";
  } else {
    for (const Method m : methods)
      if (!*MethodToString(m)) {
        s << "methods: unknown method " << static_cast<int>(m) << " (allowed: " << MethodNames()
          << ")";
        *error = s.str();
        return false;
      }
    if (!method.IsValid(error) || !misfit.IsValid(error)) return false;
    if (posterior && !posterior->IsValid(error)) return false;
    return true;
  }
  *error = s.str();
  return false;
}

CalibrationOptions CalibrationOptions::SingleStage() {
  CalibrationOptions o;
  o.reach_points = 0;
  o.refine_factor = 1;
  o.race_points = 0;
  o.noise_seeds = 0;
  o.noise_check_seeds = 0;
  return o;
}

CalibrationOptions CalibrationOptions::Resolved(int parameters) const {
  CalibrationOptions o = *this;
  if (o.reach_points == kAuto) o.reach_points = DefaultReachPoints(parameters, method.max_evals);
  if (o.race_points == kAuto)
    o.race_points = o.refine_factor > 1 ? std::max(2, o.reach_points / 12) : 0;
  return o;
}

int CalibrationOptions::DefaultReachPoints(int parameters, int max_evals) {
  return std::max(4 * (parameters + 1), max_evals / 2);
}

}  // namespace rockcal::calibrate
