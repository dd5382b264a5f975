// The vocabulary of a calibration's search: the methods by name, the stage
// that made an evaluation, and one evaluation of the objective.
#ifndef ROCKCAL_CALIBRATE_EVALUATION_H_
#define ROCKCAL_CALIBRATE_EVALUATION_H_

#include <limits>
#include <string>
#include <vector>

namespace rockcal::calibrate {

// The calibration methods: NLopt's local algorithms (BOBYQA, Subplex,
// Nelder-Mead, COBYLA), its global ones (DIRECT-L, CRS2, ISRES, MLSL; each
// polished by BOBYQA), and Ceres' least squares on the residuals.
enum class Method {
  kBobyqa,
  kSbplx,
  kNelderMead,
  kCobyla,
  kDirectL,
  kCrs2,
  kIsres,
  kMlsl,
  kCeres,
};
// Their names ("nlopt:bobyqa", "nlopt:sbplx", "nlopt:neldermead",
// "nlopt:cobyla", "nlopt:direct_l", "nlopt:crs2", "nlopt:isres",
// "nlopt:mlsl", "ceres") from one table for parsing and printing, as the
// loss's. StringToMethod returns false (and leaves *method alone) for a name
// not in the table; MethodNames lists the table, comma separated, for
// messages; AllMethods lists the methods in its order.
const char* MethodToString(Method method);
bool StringToMethod(const std::string& name, Method* method);
std::string MethodNames();
const std::vector<Method>& AllMethods();

// Which search made an evaluation or a result: a method at the run's rocks,
// the same method again in a refining stage at more rocks, or the
// posterior's sampling. Its name is what the evaluation log, trace.csv and
// the reports show: "nlopt:bobyqa", "nlopt:bobyqa (160 rocks)", "posterior".
struct Stage {
  Method method = Method::kBobyqa;
  int rocks = 0;           // a refining stage's rocks per evaluation; 0: the first stage
  bool posterior = false;  // the posterior's evaluations (method and rocks unused)

  static Stage Posterior();
  std::string name() const;
  // The stage of a name() (the log's "method"); false for another name.
  static bool FromName(const std::string& name, Stage* stage);
  bool operator==(const Stage& other) const;
  bool operator!=(const Stage& other) const { return !(*this == other); }
  bool operator<(const Stage& other) const;  // any strict order, for maps
};

// One evaluation of the objective.
struct Evaluation {
  Stage stage;                     // logged as its name ("method")
  int index = 0;                   // 1-based within the method
  std::vector<double> parameters;  // physical values
  double misfit = 0.0;
  std::vector<double> residuals;
  // observations::Misfit::log_scale; NaN when not known (a log record
  // written without it).
  double log_scale = std::numeric_limits<double>::quiet_NaN();
  bool penalised = false;
  double seconds = 0.0;   // wall seconds of its simulation
  double elapsed = 0.0;   // wall seconds since the method started, when it finished
  bool replayed = false;  // taken from the log of an earlier run
};

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_EVALUATION_H_
