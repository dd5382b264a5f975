// The calibration methods' dispatcher: the method table (each Method's name
// and the SearchMethod that runs it, search.h), the options' check, the
// names of the enums and stages, and RunMethod.
#include "rockcal/calibrate/calibration.h"

#include <cstdlib>
#include <limits>
#include <nlopt.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "rockcal/core/error.h"
#include "rockcal/core/name_table.h"
#include "search.h"

namespace rockcal::calibrate {
namespace {

// The methods' one table: name, and the search that runs each.
struct MethodInfo {
  Method id;
  const char* name;
  const SearchMethod* search;
};

const NloptSearch kBobyqa(nlopt::LN_BOBYQA, false);
const NloptSearch kSbplx(nlopt::LN_SBPLX, false);
const NloptSearch kNelderMead(nlopt::LN_NELDERMEAD, false);
const NloptSearch kCobyla(nlopt::LN_COBYLA, false);
const NloptSearch kDirectL(nlopt::GN_DIRECT_L, true);
const NloptSearch kCrs2(nlopt::GN_CRS2_LM, true);
const NloptSearch kIsres(nlopt::GN_ISRES, true);
const NloptSearch kMlsl(nlopt::G_MLSL_LDS, true);
const CeresSearch kCeres;

const MethodInfo kMethods[] = {
    {Method::kBobyqa, "nlopt:bobyqa", &kBobyqa},
    {Method::kSbplx, "nlopt:sbplx", &kSbplx},
    {Method::kNelderMead, "nlopt:neldermead", &kNelderMead},
    {Method::kCobyla, "nlopt:cobyla", &kCobyla},
    {Method::kDirectL, "nlopt:direct_l", &kDirectL},
    {Method::kCrs2, "nlopt:crs2", &kCrs2},
    {Method::kIsres, "nlopt:isres", &kIsres},
    {Method::kMlsl, "nlopt:mlsl", &kMlsl},
    {Method::kCeres, "ceres", &kCeres},
};

}  // namespace

bool MethodOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (max_evals < kMinEvals) {
    s << "max_evals = " << max_evals << ": must be >= " << kMinEvals;
  } else if (!(max_seconds >= 0)) {
    s << "max_seconds = " << max_seconds << ": must be >= 0 (0: no limit)";
  } else if (!(polish_fraction >= 0 && polish_fraction <= 0.9)) {
    s << "polish_fraction = " << polish_fraction << ": must be in [0, 0.9]";
  } else if (!(initial_step > 0 && initial_step <= 1)) {
    s << "initial_step = " << initial_step << ": must be in (0, 1]";
  } else if (!(ceres_step > 0 && ceres_step <= 2)) {
    s << "ceres_step = " << ceres_step << ": must be in (0, 2]";
  } else if (!*CeresLossToString(ceres_loss)) {
    s << "ceres_loss = " << static_cast<int>(ceres_loss) << ": must be one of " << CeresLossNames();
  } else if (!*EstimateToString(estimate)) {
    s << "estimate = " << static_cast<int>(estimate) << ": must be one of " << EstimateNames();
  } else if (!(smoothing_radius > 0 && smoothing_radius <= 1)) {
    s << "smoothing_radius = " << smoothing_radius << ": must be in (0, 1]";
  } else {
    return true;
  }
  *error = s.str();
  return false;
}

namespace {

constexpr core::Named<CeresLoss> kCeresLosses[] = {
    {CeresLoss::kNone, "none"}, {CeresLoss::kHuber, "huber"}, {CeresLoss::kCauchy, "cauchy"}};
constexpr core::Named<Estimate> kEstimates[] = {{Estimate::kLowest, "lowest"},
                                                {Estimate::kSmoothed, "smoothed"}};

}  // namespace

const char* CeresLossToString(CeresLoss loss) { return core::NameOf(kCeresLosses, loss); }
bool StringToCeresLoss(const std::string& name, CeresLoss* loss) {
  return core::IdOf(kCeresLosses, name, loss);
}
std::string CeresLossNames() { return core::NameList(kCeresLosses); }
const char* EstimateToString(Estimate estimate) { return core::NameOf(kEstimates, estimate); }
bool StringToEstimate(const std::string& name, Estimate* estimate) {
  return core::IdOf(kEstimates, name, estimate);
}
std::string EstimateNames() { return core::NameList(kEstimates); }

const char* MethodToString(Method method) { return core::NameOf(kMethods, method); }
bool StringToMethod(const std::string& name, Method* method) {
  return core::IdOf(kMethods, name, method);
}
std::string MethodNames() { return core::NameList(kMethods); }
const std::vector<Method>& AllMethods() {
  static const std::vector<Method> methods = core::IdList(kMethods);
  return methods;
}

namespace {
constexpr const char* kPosteriorStage = "posterior";
}  // namespace

Stage Stage::Posterior() {
  Stage s;
  s.posterior = true;
  return s;
}

std::string Stage::name() const {
  if (posterior) return kPosteriorStage;
  // No comma: the name is a field of trace.csv and comparison.csv.
  return std::string(MethodToString(method)) +
         (rocks > 0 ? " (" + std::to_string(rocks) + " rocks)" : "");
}

bool Stage::FromName(const std::string& name, Stage* stage) {
  if (name == kPosteriorStage) {
    *stage = Posterior();
    return true;
  }
  Stage s;
  const std::size_t space = name.find(' ');
  if (!StringToMethod(name.substr(0, space), &s.method)) return false;
  if (space != std::string::npos) {
    // A refining stage's " (N rocks)": N read, and the name taken only when
    // name() writes it back the same.
    const long rocks = std::strtol(name.c_str() + std::min(name.size(), space + 2), nullptr, 10);
    if (rocks < 1 || rocks > std::numeric_limits<int>::max()) return false;
    s.rocks = static_cast<int>(rocks);
    if (s.name() != name) return false;
  }
  *stage = s;
  return true;
}

bool Stage::operator==(const Stage& o) const {
  return posterior == o.posterior && (posterior || (method == o.method && rocks == o.rocks));
}

bool Stage::operator<(const Stage& o) const {
  if (posterior != o.posterior) return posterior < o.posterior;
  if (posterior) return false;
  return std::tie(method, rocks) < std::tie(o.method, o.rocks);
}

const char* TerminationName(TerminationType type) {
  switch (type) {
    case TerminationType::kConverged:
      return "converged";
    case TerminationType::kBudgetUsed:
      return "budget used";
    case TerminationType::kStopped:
      return "stopped";
    case TerminationType::kFailed:
      return "failed";
  }
  return "?";
}

MethodResult RunMethod(Method method, const ObjectiveFunction& objective,
                       const std::vector<double>& start, const MethodOptions& options,
                       EvaluationLog* log, const CalibrationProgress& progress) {
  const MethodInfo* info = core::FindEntry(kMethods, method);
  if (!info)
    throw InputError("calibration options", "method " + std::to_string(static_cast<int>(method)) +
                                                ": must be one of " + MethodNames());
  std::string error;
  if (!options.IsValid(&error)) throw InputError("calibration options", error);
  Evaluator ev(Stage{method}, objective, options, log, progress);
  // The smoothed estimate keeps evaluations back from the search; a budget
  // too small for it goes to the search whole.
  const int n = objective.space().size();
  const Smoothing smoothed = SmoothingFor(options, n);
  if (smoothed == Smoothing::kBoth) ev.Reserve(SmoothingEvaluations(n));
  if (smoothed == Smoothing::kFirstStage) ev.Reserve(1);
  const std::vector<double> unit = objective.space().ToUnit(start);
  const Termination termination = info->search->Search(unit, options, objective.space(), &ev);
  MethodResult result = Conclude(&ev, termination, smoothed, options, objective);
  result.uncertainty = info->search->UncertaintyOf(result, objective, options);
  return result;
}

double TimeToReach(const MethodResult& result, double target, double fraction) {
  double best = std::numeric_limits<double>::infinity();
  for (const Evaluation& e : result.trace) {
    best = std::min(best, e.misfit);
    if (best <= target * (1 + fraction) + 1e-300) return e.elapsed;
  }
  return -1.0;
}

}  // namespace rockcal::calibrate
