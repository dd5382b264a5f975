// Calibration bookkeeping: resume, the evaluation log, budgets, penalties and
// options (the twin experiments are in twin_heavy_test.cc).
#include "rockcal/calibrate/calibration.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <tuple>

#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using ::testing::HasSubstr;
using testing::TwinObservations;
using testing::TwinSite;

using testing::kTruth;

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "/rockcal_calibration_" + name;
}

// A small, quick objective for the bookkeeping tests (they also run under
// the sanitizers): few rocks.
struct Small {
  sites::Site site = TwinSite(6);
  ParameterSpace space = ParameterSpace::FromSite(site);
  observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  Objective objective{site.scene, space, obs, {}};
};

TEST(Calibration, ResumeEndsLikeAStraightRunWithFewerSimulations) {
  Small small;
  MethodOptions options;
  options.estimate = Estimate::kSmoothed;
  options.max_evals = 22;  // with the smoothed estimate's stencil (12 search, 10 kept back)
  const std::string straight_log = TempPath("straight.jsonl");
  EvaluationLog straight_log_file(straight_log, false, small.space, 1, 6);
  const MethodResult straight =
      RunMethod(Method::kBobyqa, small.objective, small.space.Current(small.site.scene), options,
                &straight_log_file);
  // Stop after k = 6 evaluations, then resume with the full budget.
  const std::string log_path = TempPath("resumed.jsonl");
  MethodOptions first = options;
  first.max_evals = 6;
  {
    EvaluationLog log(log_path, false, small.space, 1, 6);
    RunMethod(Method::kBobyqa, small.objective, small.space.Current(small.site.scene), first, &log);
  }
  EvaluationLog log(log_path, true, small.space, 1, 6);
  EXPECT_EQ(log.size(), 6);
  const MethodResult resumed = RunMethod(Method::kBobyqa, small.objective,
                                         small.space.Current(small.site.scene), options, &log);
  EXPECT_EQ(resumed.best, straight.best);
  EXPECT_EQ(resumed.best_misfit, straight.best_misfit);
  EXPECT_EQ(resumed.evaluations, straight.evaluations);
  EXPECT_EQ(resumed.simulated, straight.simulated - 6);
  for (std::size_t k = 0; k < resumed.trace.size(); ++k) {
    EXPECT_EQ(resumed.trace[k].parameters, straight.trace[k].parameters) << "evaluation " << k + 1;
    EXPECT_EQ(resumed.trace[k].replayed, k < 6);
  }
}

TEST(Calibration, LogOfAnotherCalibrationIsRefused) {
  Small small;
  const std::string path = TempPath("other.jsonl");
  {
    EvaluationLog log(path, false, small.space, 1, 6);
    MethodOptions options;
    options.max_evals = 2;
    RunMethod(Method::kSbplx, small.objective, small.space.Current(small.site.scene), options,
              &log);
  }
  try {
    EvaluationLog log(path, true, small.space, 7, 6);  // another seed
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ":2"));  // line 1 is the header
    EXPECT_THAT(e.what(), HasSubstr("another calibration"));
  }
  std::ofstream(path, std::ios::app) << "{\"method\": \"nlopt:sb";  // a torn last line
  EvaluationLog log(path, true, small.space, 1, 6);
  EXPECT_EQ(log.size(), 2);
}

// The log a resume accepts is left as it was until `accepted` has run (the
// caller's folder stops saying it is complete there), then rewritten without
// its torn last line; a refused log never calls it.
TEST(Calibration, AResumedLogIsRewrittenOnlyOnceAccepted) {
  Small small;
  const std::string path = TempPath("accepted.jsonl");
  {
    EvaluationLog log(path, false, small.space, 1, 6);
    MethodOptions options;
    options.max_evals = 2;
    RunMethod(Method::kSbplx, small.objective, small.space.Current(small.site.scene), options,
              &log);
  }
  const auto read = [&] {
    std::ostringstream bytes;
    bytes << std::ifstream(path).rdbuf();
    return bytes.str();
  };
  const std::string torn = "{\"method\": \"nlopt:sb";
  std::ofstream(path, std::ios::app) << torn;
  const std::string before = read();
  int calls = 0;
  EXPECT_THROW(EvaluationLog(path, true, small.space, 7, 6, {}, [&] { ++calls; }), InputError);
  EXPECT_EQ(calls, 0);
  std::string seen;
  const EvaluationLog log(path, true, small.space, 1, 6, {}, [&] {
    ++calls;
    seen = read();
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(seen, before);
  EXPECT_EQ(read().find(torn), std::string::npos);
  EXPECT_EQ(log.size(), 2);
}

// A logged evaluation whose residuals do not fit the objective (a log edited
// by hand) is refused before a method replays it: Ceres' residual array has
// the objective's count, and 500 more overran it.
TEST(Calibration, LoggedResidualsOfAnotherCountAreRefused) {
  Small small;
  const std::string path = TempPath("residuals.jsonl");
  MethodOptions options;
  options.max_evals = 2;
  {
    EvaluationLog log(path, false, small.space, 1, 6);
    RunMethod(Method::kCeres, small.objective, small.space.Current(small.site.scene), options,
              &log);
  }
  std::ifstream in(path);
  std::string header, first, rest;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, rest, '\0');
  in.close();
  nlohmann::json record = nlohmann::json::parse(first);
  for (int k = 0; k < 500; ++k) record["residuals"].push_back(1.0);
  std::ofstream(path) << header << '\n' << record.dump() << '\n' << rest;
  EvaluationLog log(path, true, small.space, 1, 6);
  options.max_evals = 4;
  try {
    RunMethod(Method::kCeres, small.objective, small.space.Current(small.site.scene), options,
              &log);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("ceres evaluation 1 has " +
                                    std::to_string(small.objective.residual_count() + 500) +
                                    " residuals where this calibration has " +
                                    std::to_string(small.objective.residual_count())));
  }
}

// The space and fingerprint of the evaluation logs under
// tests/calibrate/evaluation_logs/ and fuzz/seeds/evaluation_log_fuzz/.
ParameterSpace LogSpace() {
  Parameter hardness, roughness;
  hardness.material = roughness.material = "slope";
  roughness.kind = ParameterKind::kRoughness;
  roughness.lower = 0.01;
  roughness.upper = 0.5;
  return ParameterSpace({hardness, roughness});
}

// The header and two records of the fuzz seed log two_records.jsonl.
std::tuple<std::string, std::string, std::string> SeedLogLines() {
  std::ifstream in(std::string(ROCKCAL_SOURCE_DIR) +
                   "/fuzz/seeds/evaluation_log_fuzz/two_records.jsonl");
  std::string header, first, second;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  return {header, first, second};
}

Fingerprint LogFingerprint() {
  Fingerprint fingerprint;
  fingerprint.Add("site file", "0123456789abcdef");
  fingerprint.Add("seed", "1");
  return fingerprint;
}

// Logs that made the reader convert a number beyond its type (undefined
// behaviour; fuzz/evaluation_log_fuzz.cc reads them with the same space and
// fingerprint): each is refused, naming the line and the field.
TEST(Calibration, LogWithAWholeNumberOutOfRangeIsRefused) {
  const ParameterSpace space = LogSpace();
  const Fingerprint fingerprint = LogFingerprint();
  const std::string dir = std::string(ROCKCAL_SOURCE_DIR) + "/tests/calibrate/evaluation_logs/";
  for (const auto& [file, field] :
       {std::pair<const char*, const char*>{"evaluation_1e300", "evaluation"},
        {"rocks_minus_1e300", "rocks"},
        {"seed_1e30", "seed"}}) {
    const std::string path = TempPath(std::string(file) + ".jsonl");
    std::filesystem::copy_file(dir + file + ".jsonl", path,
                               std::filesystem::copy_options::overwrite_existing);
    try {
      EvaluationLog log(path, true, space, 1, 6, fingerprint);
      ADD_FAILURE() << file << ": expected an InputError, read " << log.size() << " records";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(path + ":2: not an evaluation record: \"" + field + "\""))
          << file;
    }
  }
}

// Issue 40: two runs writing one folder at once left evaluations 1-2 twice,
// interleaved, and --resume accepted them. An evaluation logged again or
// out of order for its method is refused, naming both lines; so is a line
// nested deeper than sites::kMaxJsonDepth. A log that cannot be written is
// a failure (std::runtime_error: exit 1), not bad input.
TEST(Calibration, LogOfTwoRunsDeepLinesAndUnwritableLogs) {
  const ParameterSpace space = LogSpace();
  const Fingerprint fingerprint = LogFingerprint();
  auto [header, first, second] = SeedLogLines();
  const std::string path = TempPath("two_runs.jsonl");
  std::ofstream(path) << header << '\n' << first << '\n' << second << '\n';
  EXPECT_EQ(EvaluationLog(path, true, space, 1, 6, fingerprint).size(), 2);
  std::ofstream(path) << header << '\n'
                      << first << '\n'
                      << first << '\n'
                      << second << '\n'
                      << second << '\n';
  try {
    EvaluationLog log(path, true, space, 1, 6, fingerprint);
    ADD_FAILURE() << "expected an InputError, read " << log.size() << " records";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ":3: nlopt:bobyqa evaluation 1 after its evaluation 1 "
                                           "(line 2): the log holds the lines of two runs"));
  }
  std::ofstream(path) << header << '\n'
                      << std::string(100000, '[') << std::string(100000, ']') << '\n'
                      << first << '\n';
  try {
    EvaluationLog log(path, true, space, 1, 6, fingerprint);
    ADD_FAILURE() << "expected an InputError, read " << log.size() << " records";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path + ":2: JSON nested 100000 levels deep"));
  }
  try {
    EvaluationLog log("/proc/rockcal_no_folder/evaluations.jsonl", false, space, 1, 6, fingerprint);
    ADD_FAILURE() << "expected a failure to write";
  } catch (const InputError& e) {
    ADD_FAILURE() << "bad input? " << e.what();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot write the evaluation log /proc/rockcal_no_folder"));
  }
}

// Issue 56: a log write that failed on a full disk went unnoticed by the
// NLopt methods (NLopt turns an objective's exception into its bare "nlopt
// failure", a failed method) until a later file was written. The first
// failed append now stops every method with the log's name and the cause,
// the records before it kept. /dev/full fails every write with ENOSPC.
TEST(Calibration, AFullDiskStopsTheMethodAtTheFirstFailedAppend) {
  Small small;
  namespace fs = std::filesystem;
  for (const Method method : {Method::kSbplx, Method::kCeres}) {
    SCOPED_TRACE(MethodToString(method));
    const std::string path = TempPath("full.jsonl");
    EvaluationLog log(path, false, small.space, 1, 6);
    MethodOptions options;
    options.max_evals = 2;
    RunMethod(method, small.objective, small.space.Current(small.site.scene), options, &log);
    ASSERT_EQ(log.size(), 2);
    const std::string kept = path + ".kept";
    fs::rename(path, kept);
    fs::create_symlink("/dev/full", path);
    options.max_evals = 4;
    try {
      const MethodResult r =
          RunMethod(method, small.objective, small.space.Current(small.site.scene), options, &log);
      ADD_FAILURE() << "expected a failure to write; the method ended " << r.termination.message
                    << " after " << r.evaluations << " evaluations";
    } catch (const InputError& e) {
      ADD_FAILURE() << "bad input? " << e.what();
    } catch (const std::runtime_error& e) {
      EXPECT_THAT(e.what(), HasSubstr("cannot write the evaluation log " + path +
                                      ": No space left on device"));
    }
    EXPECT_EQ(log.size(), 2) << "the failed evaluation is not taken as logged";
    fs::remove(path);
    fs::rename(kept, path);
    EXPECT_EQ(EvaluationLog(path, true, small.space, 1, 6).size(), 2);
  }
}

// Issue 56: a refused --resume deleted a finished result's marker. Check
// reads a log as a resume does and refuses what it refuses, writing
// nothing; with the rocks unknown (a noise check may raise them) the
// fingerprint's rocks are not compared, and the records must hold the
// header's.
TEST(Calibration, CheckReadsALogAsAResumeWithoutWritingIt) {
  const ParameterSpace space = LogSpace();
  Fingerprint fingerprint = LogFingerprint();
  fingerprint.Add("rocks", "6");
  auto [header, first, second] = SeedLogLines();
  header = R"({"fingerprint":{"rocks":"6","seed":"1","site file":"0123456789abcdef"}})";
  const std::string path = TempPath("check.jsonl");
  const std::string text = header + "\n" + first + "\n" + second + "\n" + "{\"torn";
  std::ofstream(path) << text;
  const auto contents = [&] {
    std::ostringstream bytes;
    bytes << std::ifstream(path).rdbuf();
    return bytes.str();
  };
  EXPECT_NO_THROW(EvaluationLog::Check(path, space, 1, 6, fingerprint));
  EXPECT_NO_THROW(EvaluationLog::Check(path, space, 1, std::nullopt, fingerprint));
  EXPECT_EQ(contents(), text) << "Check keeps even the torn last line a resume drops";

  Fingerprint other = LogFingerprint();
  other.Add("rocks", "12");
  const auto error = [&](std::optional<int> rocks, const Fingerprint& f, std::uint64_t seed) {
    try {
      EvaluationLog::Check(path, space, seed, rocks, f);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error(12, other, 1),
              HasSubstr(path + ":1: cannot resume: what determines the evaluations changed since "
                               "this log was written: rocks"));
  EXPECT_EQ(error(std::nullopt, other, 1), "no error") << "the rocks unknown: not compared";
  EXPECT_THAT(error(std::nullopt, other, 7), HasSubstr(path + ":2: record of another calibration"));
  Fingerprint seed = other;
  seed.parts[1].second = "7";
  EXPECT_THAT(error(std::nullopt, seed, 1), HasSubstr("this log was written: seed; restore it"));
  EXPECT_EQ(contents(), text) << "a refusal writes nothing";
  // The same refusals as the log a resume opens.
  EXPECT_THROW(EvaluationLog(path, true, space, 1, 12, other), InputError);
  EXPECT_EQ(contents(), text);
}

TEST(Calibration, EveryMethodRunsWithinItsBudget) {
  Small small;
  MethodOptions options;
  options.max_evals = 5;
  for (const Method m : AllMethods()) {
    const std::string method = MethodToString(m);
    const MethodResult r =
        RunMethod(m, small.objective, small.space.Current(small.site.scene), options, nullptr);
    EXPECT_LE(r.evaluations, 5) << method;
    EXPECT_GE(r.evaluations, 2) << method;
    EXPECT_TRUE(std::isfinite(r.best_misfit)) << method;
    EXPECT_EQ(r.best.size(), 4u) << method;
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(r.best[k], small.space.parameters()[k].lower) << method;
      EXPECT_LE(r.best[k], small.space.parameters()[k].upper) << method;
    }
  }
  EXPECT_THROW(RunMethod(static_cast<Method>(99), small.objective,
                         small.space.Current(small.site.scene), options, nullptr),
               InputError);
}

TEST(Calibration, NonFiniteSimulationIsAFinitePenalty) {
  Small small;
  core::Scene scene = small.site.scene;
  scene.groups[0].release.zone.clear();
  scene.groups[0].release.point = Eigen::Vector2d(-100, -100);  // off the grid: every rock leaves
  Objective objective(scene, small.space, small.obs, {});
  const observations::Misfit m = objective.Evaluate(small.space.Current(scene));
  EXPECT_TRUE(std::isfinite(m.value));
  EXPECT_TRUE(m.penalised);
  EXPECT_EQ(static_cast<int>(m.residuals.size()), objective.residual_count());
  for (const auto& r : m.residuals) EXPECT_TRUE(std::isfinite(r.value));
}

// One name table each for parsing and printing: every name reads back as
// its value, and a name not in the table is refused.
TEST(Calibration, LossAndEstimateNamesRoundTrip) {
  for (CeresLoss loss : {CeresLoss::kNone, CeresLoss::kHuber, CeresLoss::kCauchy}) {
    CeresLoss read = CeresLoss::kNone;
    EXPECT_TRUE(StringToCeresLoss(CeresLossToString(loss), &read)) << CeresLossToString(loss);
    EXPECT_EQ(read, loss) << CeresLossToString(loss);
  }
  for (Estimate estimate : {Estimate::kLowest, Estimate::kSmoothed}) {
    Estimate read = Estimate::kLowest;
    EXPECT_TRUE(StringToEstimate(EstimateToString(estimate), &read)) << EstimateToString(estimate);
    EXPECT_EQ(read, estimate) << EstimateToString(estimate);
  }
  CeresLoss loss = CeresLoss::kHuber;
  EXPECT_FALSE(StringToCeresLoss("l1", &loss));
  EXPECT_EQ(loss, CeresLoss::kHuber) << "left alone";
  Estimate estimate = Estimate::kSmoothed;
  EXPECT_FALSE(StringToEstimate("mean", &estimate));
  EXPECT_EQ(estimate, Estimate::kSmoothed) << "left alone";
  EXPECT_EQ(CeresLossNames(), "none, huber, cauchy");
  EXPECT_EQ(EstimateNames(), "lowest, smoothed");
}

// The methods' one table parses and prints every name; a stage's name (the
// log's "method") reads back to the same stage, and nothing else reads.
TEST(Calibration, MethodAndStageNamesRoundTrip) {
  ASSERT_EQ(AllMethods().size(), 9u);
  for (const Method m : AllMethods()) {
    Method read = Method::kCeres;
    EXPECT_TRUE(StringToMethod(MethodToString(m), &read)) << MethodToString(m);
    EXPECT_EQ(read, m) << MethodToString(m);
    for (const int rocks : {0, 1, 160}) {
      const Stage stage{m, rocks};
      Stage back;
      ASSERT_TRUE(Stage::FromName(stage.name(), &back)) << stage.name();
      EXPECT_EQ(back, stage) << stage.name();
    }
  }
  EXPECT_EQ(MethodNames(),
            "nlopt:bobyqa, nlopt:sbplx, nlopt:neldermead, nlopt:cobyla, nlopt:direct_l, "
            "nlopt:crs2, nlopt:isres, nlopt:mlsl, ceres");
  EXPECT_EQ((Stage{Method::kDirectL, 160}).name(), "nlopt:direct_l (160 rocks)");
  EXPECT_EQ(Stage::Posterior().name(), "posterior");
  Stage read;
  EXPECT_TRUE(Stage::FromName("posterior", &read));
  EXPECT_EQ(read, Stage::Posterior());
  EXPECT_NE(read, Stage{});
  Method method = Method::kSbplx;
  EXPECT_FALSE(StringToMethod("nlopt:nope", &method));
  EXPECT_FALSE(StringToMethod("bobyqa", &method));
  EXPECT_EQ(method, Method::kSbplx) << "left alone";
  read = Stage{Method::kCeres, 7};
  for (const char* bad :
       {"nlopt:nope", "nlopt:bobyqa ", "nlopt:bobyqa (0 rocks)", "nlopt:bobyqa (-3 rocks)",
        "nlopt:bobyqa (12 rocks", "nlopt:bobyqa (012 rocks)", "nlopt:bobyqa (12 rock)",
        "nlopt:bobyqa (12 rocks) x", "Posterior", ""}) {
    EXPECT_FALSE(Stage::FromName(bad, &read)) << bad;
    EXPECT_EQ(read, (Stage{Method::kCeres, 7})) << "left alone: " << bad;
  }
}

TEST(Calibration, OptionsAreChecked) {
  MethodOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error));
  o.max_evals = 1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("max_evals = 1"));
  o = MethodOptions{};
  o.ceres_loss = static_cast<CeresLoss>(7);
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("ceres_loss = 7: must be one of none, huber, cauchy"));
  o = MethodOptions{};
  o.estimate = static_cast<Estimate>(7);
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("estimate = 7: must be one of lowest, smoothed"));
  o = MethodOptions{};
  o.smoothing_radius = 0.0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THAT(error, HasSubstr("smoothing_radius = 0"));
}

// Two parameters and evaluations whose residuals are r(u) = A (u - u*) plus
// `noise` (normal, standard deviation `noise`, fixed seed) at the points
// `units` of the unit box.
struct LinearResiduals {
  ParameterSpace space{{Bound("a", 0, ParameterKind::kHardness, 0.0, 1.0),
                        Bound("b", 1, ParameterKind::kRoughness, 0.1, 0.6)}};

  static Parameter Bound(const char* material, int index, ParameterKind kind, double lower,
                         double upper) {
    Parameter p;
    p.material = material;
    p.material_index = index;
    p.kind = kind;
    p.lower = lower;
    p.upper = upper;
    return p;
  }
  Eigen::Vector2d optimum{0.4, 0.6};
  Eigen::Matrix<double, 5, 2> a =
      (Eigen::Matrix<double, 5, 2>() << 8, 1, -3, 6, 5, 5, 0, -7, 2, 2).finished();

  std::vector<Evaluation> Trace(const std::vector<Eigen::Vector2d>& units, double noise) const {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> normal(0.0, noise);
    std::vector<Evaluation> trace;
    for (const Eigen::Vector2d& u : units) {
      Evaluation e;
      e.parameters = space.ToPhysical({u[0], u[1]});
      Eigen::Matrix<double, 5, 1> r = a * (u - optimum);
      for (int k = 0; k < 5; ++k) e.residuals.push_back(r[k] + (noise > 0 ? normal(rng) : 0.0));
      e.misfit = 0.0;
      for (double v : e.residuals) e.misfit += 0.5 * v * v;
      trace.push_back(e);
    }
    return trace;
  }
  static const Evaluation& Lowest(const std::vector<Evaluation>& trace) {
    return *std::min_element(
        trace.begin(), trace.end(),
        [](const Evaluation& x, const Evaluation& y) { return x.misfit < y.misfit; });
  }
};

TEST(SmoothedEstimate, ExactForLinearResiduals) {
  const LinearResiduals lin;
  std::vector<Eigen::Vector2d> units;
  for (double x : {0.3, 0.45, 0.6})
    for (double y : {0.5, 0.65, 0.8}) units.emplace_back(x, y);
  const std::vector<Evaluation> trace = lin.Trace(units, 0.0);
  SmoothedEstimate info;
  const auto u =
      FitSmoothedEstimate(trace, lin.space, LinearResiduals::Lowest(trace).parameters, 0.2, &info);
  ASSERT_TRUE(u.has_value()) << info.message;
  EXPECT_NEAR((*u)[0], 0.4, 1e-9);
  EXPECT_NEAR((*u)[1], 0.6, 1e-9);
  EXPECT_NEAR(info.predicted_misfit, 0.0, 1e-12);
  EXPECT_EQ(info.points, 9);
}

TEST(SmoothedEstimate, AveragesNoiseThatFoolsTheLowestEvaluation) {
  // 80 evaluations scattered around the optimum, residual noise 0.5: the
  // lowest misfit falls where the noise happens to be small, not at u*. The
  // least-squares fit sees through it: its error is about
  // 0.5 / (|A| sqrt(80)) ~ 0.005 per parameter.
  const LinearResiduals lin;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> offset(-0.15, 0.15);
  std::vector<Eigen::Vector2d> units;
  for (int k = 0; k < 80; ++k) units.emplace_back(0.4 + offset(rng), 0.6 + offset(rng));
  const std::vector<Evaluation> trace = lin.Trace(units, 0.5);
  const Evaluation& lowest = LinearResiduals::Lowest(trace);
  SmoothedEstimate info;
  const auto u = FitSmoothedEstimate(trace, lin.space, lowest.parameters, 0.2, &info);
  ASSERT_TRUE(u.has_value()) << info.message;
  const std::vector<double> low = lin.space.ToUnit(lowest.parameters);
  const double error = std::hypot((*u)[0] - 0.4, (*u)[1] - 0.6);
  const double lowest_error = std::hypot(low[0] - 0.4, low[1] - 0.6);
  EXPECT_LT(error, 0.02) << "estimate " << (*u)[0] << ", " << (*u)[1];
  EXPECT_LT(error, lowest_error) << "lowest evaluation " << low[0] << ", " << low[1];
}

// Issue 12: the standard errors of a search without its own (NLopt) come
// from the same local model of its evaluations: for residuals A (u - u*)
// exactly the Gauss-Newton covariance (A^T A)^-1, in physical units.
TEST(LocalModelUncertainty, IsTheGaussNewtonCovarianceOfTheEvaluations) {
  const LinearResiduals lin;
  std::vector<Eigen::Vector2d> units;
  for (double x : {0.3, 0.45, 0.6})
    for (double y : {0.5, 0.65, 0.8}) units.emplace_back(x, y);
  const std::vector<Evaluation> trace = lin.Trace(units, 0.0);
  const std::vector<double> at = lin.space.ToPhysical({0.4, 0.6});
  const Uncertainty u = LocalModelUncertainty(trace, lin.space, at, 0.0, 0.2);
  ASSERT_TRUE(u.computed);
  ASSERT_FALSE(u.rank_deficient) << u.message;
  const Eigen::Matrix2d cov = (lin.a.transpose() * lin.a).inverse();
  EXPECT_NEAR(u.std_error[0], std::sqrt(cov(0, 0)) * 1.0, 1e-9);
  EXPECT_NEAR(u.std_error[1], std::sqrt(cov(1, 1)) * 0.5, 1e-9);
  EXPECT_NEAR(u.correlation[0][1], cov(0, 1) / std::sqrt(cov(0, 0) * cov(1, 1)), 1e-9);
  EXPECT_THAT(u.message, HasSubstr("the 9 evaluations within"));
  EXPECT_TRUE(u.from_search);
  // A parameter the residuals do not see is named as not identifiable.
  LinearResiduals blind;
  blind.a.col(1).setZero();
  const Uncertainty b = LocalModelUncertainty(blind.Trace(units, 0.0), blind.space, at, 0.0, 0.2);
  ASSERT_TRUE(b.computed);
  EXPECT_TRUE(b.rank_deficient);
  EXPECT_THAT(b.message, HasSubstr("along 1 of 2 directions, the least determined +b.roughness: "
                                   "the values are not shown to be determined"));
  // Too few evaluations: not computed.
  const std::vector<Evaluation> few(trace.begin(), trace.begin() + 4);
  EXPECT_FALSE(LocalModelUncertainty(few, lin.space, at, 0.0, 0.2).computed);
}

// Noisy evaluations make the fitted slopes steeper on average than the
// misfit is, and the errors too small; the model's own scatter says by how
// much. A slope the noise swamps is reported as not determined.
TEST(LocalModelUncertainty, TakesTheNoiseOfTheSlopesOff) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  std::vector<Eigen::Vector2d> units;
  for (int k = 0; k < 40; ++k) units.emplace_back(0.4 + offset(rng), 0.6 + offset(rng));
  LinearResiduals weak;
  weak.a.col(1) *= 0.01;  // b moves the residuals by ~0.01 over the box; noise 1
  const std::vector<double> at = weak.space.ToPhysical({0.4, 0.6});
  const Uncertainty u = LocalModelUncertainty(weak.Trace(units, 1.0), weak.space, at, 2.5, 0.2);
  ASSERT_TRUE(u.computed);
  EXPECT_TRUE(u.rank_deficient) << u.message;
  EXPECT_THAT(u.message, HasSubstr("the least determined +b.roughness: the values are not shown"));
  // Slopes well above the noise: errors near the noise-free ones.
  const LinearResiduals strong;
  const Uncertainty s = LocalModelUncertainty(strong.Trace(units, 0.3), strong.space, at, 0.0, 0.2);
  ASSERT_TRUE(s.computed);
  ASSERT_FALSE(s.rank_deficient) << s.message;
  const Eigen::Matrix2d cov = (strong.a.transpose() * strong.a).inverse();
  EXPECT_NEAR(s.std_error[0] / std::sqrt(cov(0, 0)), 1.0, 0.2);
  EXPECT_NEAR(s.std_error[1] / (std::sqrt(cov(1, 1)) * 0.5), 1.0, 0.2);
}

TEST(SmoothedEstimate, SaysWhenTheEvaluationsCannotDetermineIt) {
  const LinearResiduals lin;
  SmoothedEstimate info;
  // Five points: fewer than 2 (n + 1) = 6.
  std::vector<Eigen::Vector2d> few = {{0.3, 0.5}, {0.4, 0.5}, {0.5, 0.5}, {0.3, 0.6}, {0.4, 0.7}};
  std::vector<Evaluation> trace = lin.Trace(few, 0.0);
  EXPECT_FALSE(FitSmoothedEstimate(trace, lin.space, trace[1].parameters, 0.2, &info));
  EXPECT_THAT(info.message, HasSubstr("fewer than the 6"));
  // Eight points on one line: the second parameter never varies.
  std::vector<Eigen::Vector2d> line;
  for (int k = 0; k < 8; ++k) line.emplace_back(0.3 + 0.02 * k, 0.5);
  trace = lin.Trace(line, 0.0);
  EXPECT_FALSE(FitSmoothedEstimate(trace, lin.space, trace[4].parameters, 0.2, &info));
  EXPECT_THAT(info.message, HasSubstr("do not span every parameter"));
  // A penalised evaluation does not count.
  trace =
      lin.Trace({{0.3, 0.5}, {0.5, 0.5}, {0.3, 0.7}, {0.5, 0.7}, {0.4, 0.6}, {0.45, 0.55}}, 0.0);
  ASSERT_TRUE(FitSmoothedEstimate(trace, lin.space, trace[4].parameters, 0.2, &info));
  trace[0].penalised = true;
  EXPECT_FALSE(FitSmoothedEstimate(trace, lin.space, trace[4].parameters, 0.2, &info));
}

TEST(Calibration, SmoothedEstimateIsEvaluatedAndReported) {
  Small small;
  MethodOptions options;
  options.estimate = Estimate::kSmoothed;
  // Four parameters: at least 10 for the search, 10 kept back for the
  // stencil (9) and the estimate (1).
  options.max_evals = 20;
  for (const Method m : {Method::kBobyqa, Method::kCeres}) {
    const std::string method = MethodToString(m);
    const MethodResult r =
        RunMethod(m, small.objective, small.space.Current(small.site.scene), options, nullptr);
    EXPECT_LE(r.evaluations, 20) << method;
    EXPECT_GE(r.smoothed.points, 10) << method << ": " << r.smoothed.message;
    EXPECT_THAT(r.smoothed.message, HasSubstr("then a stencil of 9 evaluations")) << method;
    // No evaluation was lower than the lowest kept.
    for (const Evaluation& e : r.trace) EXPECT_GE(e.misfit, r.lowest_misfit) << method;
    // Six rocks make a very noisy misfit: the estimate is taken only where
    // it holds, and then its misfit is the one evaluated there (the last
    // evaluation) and within one of the fit's scatters of the lowest;
    // otherwise the lowest evaluation stands, and the message says why.
    if (r.smoothed.used) {
      // The second stage's estimate, evaluated last; or, when it did not
      // hold, the first stage's, evaluated before the stencil.
      if (r.smoothed.message.find("the first estimate's") == std::string::npos) {
        EXPECT_EQ(r.trace.back().parameters, r.best) << method << ": " << r.smoothed.message;
      } else {
        EXPECT_TRUE(std::any_of(r.trace.begin(), r.trace.end(),
                                [&](const Evaluation& e) { return e.parameters == r.best; }))
            << method << ": " << r.smoothed.message;
      }
      EXPECT_EQ(r.best_misfit, small.objective.Evaluate(r.best).value) << method;
      EXPECT_EQ(r.best_misfit, r.smoothed.evaluated_misfit) << method;
      EXPECT_LE(r.best_misfit, r.lowest_misfit + r.smoothed.scatter + 1e-9) << method;
    } else {
      EXPECT_THAT(r.smoothed.message, HasSubstr("the calibrated values are the lowest evaluation"))
          << method;
      EXPECT_EQ(r.best, r.lowest) << method;
      EXPECT_EQ(r.best_misfit, r.lowest_misfit) << method;
      EXPECT_GT(r.smoothed.evaluated_misfit, r.lowest_misfit) << method;
    }
  }
  // Room for the first stage only (11 to 19 evaluations): the search's own
  // evaluations make the model, and one more evaluates its minimiser.
  options.max_evals = 12;
  MethodResult r = RunMethod(Method::kBobyqa, small.objective,
                             small.space.Current(small.site.scene), options, nullptr);
  EXPECT_EQ(r.evaluations, 12);
  EXPECT_THAT(r.smoothed.message, HasSubstr("no stencil: a budget of 12 evaluations leaves no "
                                            "room for it (it needs 20)"));
  EXPECT_GE(r.smoothed.points, 10) << r.smoothed.message;
  if (r.smoothed.used) {
    EXPECT_EQ(r.trace.back().parameters, r.best) << r.smoothed.message;
    EXPECT_EQ(r.best_misfit, r.smoothed.evaluated_misfit);
    EXPECT_LE(r.best_misfit, r.lowest_misfit + r.smoothed.scatter + 1e-9);
  } else {
    EXPECT_THAT(r.smoothed.message, HasSubstr("did not hold, so the lowest evaluation"));
    EXPECT_EQ(r.best, r.lowest);
  }
  options.max_evals = 10;  // too small a budget: the lowest
  r = RunMethod(Method::kBobyqa, small.objective, small.space.Current(small.site.scene), options,
                nullptr);
  EXPECT_FALSE(r.smoothed.used);
  EXPECT_THAT(r.smoothed.message, HasSubstr("too small for it (it needs 11)"));
  EXPECT_EQ(r.best, r.lowest);
  options.max_evals = 20;
  options.estimate = Estimate::kLowest;
  r = RunMethod(Method::kBobyqa, small.objective, small.space.Current(small.site.scene), options,
                nullptr);
  EXPECT_FALSE(r.smoothed.used);
  EXPECT_EQ(r.best, r.lowest);
  EXPECT_EQ(r.best_misfit, r.lowest_misfit);
}

TEST(ParameterSpace, UnitBoxRoundTripAndApply) {
  const sites::Site site = TwinSite(4);
  const ParameterSpace space = ParameterSpace::FromSite(site);
  ASSERT_EQ(space.size(), 4);
  const std::vector<double> x = {0.5, 0.35, 0.1, 0.6};
  const std::vector<double> u = space.ToUnit(x);
  EXPECT_NEAR(u[0], 0.5, 1e-15);
  EXPECT_NEAR(u[2], 0.0, 1e-15);
  EXPECT_NEAR(u[3], 1.0, 1e-15);
  const std::vector<double> back = space.ToPhysical(u);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(back[k], x[k], 1e-15);
  core::Scene scene = site.scene;
  space.Apply(x, &scene);
  EXPECT_EQ(scene.materials[0].hardness, 0.5);
  EXPECT_EQ(scene.materials[0].roughness_m, 0.35);
  EXPECT_EQ(scene.materials[1].hardness, 0.1);
  EXPECT_EQ(space.Current(scene), x);
  EXPECT_FALSE(space.SameTerrain(x, {0.5, 0.36, 0.1, 0.6}));
  EXPECT_TRUE(space.SameTerrain(x, {0.4, 0.35, 0.2, 0.6}));
}

TEST(ParameterSpace, FrictionAndRollingResistanceStartFromTheHardnessModel) {
  sites::Site site = TwinSite(4);
  site.calibrate.push_back({site.scene.materials[1].id, "friction", 0.3, 0.9, ""});
  site.calibrate.push_back({site.scene.materials[1].id, "rolling_resistance", 0.0, 0.6, ""});
  const ParameterSpace space = ParameterSpace::FromSite(site);
  ASSERT_EQ(space.size(), 6);
  EXPECT_EQ(space.parameters()[4].kind, ParameterKind::kFriction);
  core::Scene scene = site.scene;
  // No explicit values: the hardness model's, f = 0.9 - 0.5 H and
  // mu_r = 0.15 - 0.13 H.
  const double h = scene.materials[1].hardness;
  const std::vector<double> start = space.Current(scene);
  EXPECT_DOUBLE_EQ(start[4], 0.9 - 0.5 * h);
  EXPECT_DOUBLE_EQ(start[5], 0.15 - 0.13 * h);
  std::vector<double> x = start;
  x[4] = 0.42;
  x[5] = 0.25;
  space.Apply(x, &scene);
  EXPECT_EQ(core::DeriveContactLaw(scene.materials[1]).friction, 0.42);
  EXPECT_EQ(core::DeriveContactLaw(scene.materials[1]).rolling_resistance, 0.25);
  EXPECT_EQ(space.Current(scene), x);
}

TEST(ParameterSpace, RoughnessBoundAtZeroIsRefused) {
  sites::Site site = TwinSite(4);
  site.calibrate[1].lower = 0.0;
  try {
    ParameterSpace::FromSite(site);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("slope"));
    EXPECT_THAT(e.what(), HasSubstr("must be > 0"));
  }
}

}  // namespace
}  // namespace rockcal::calibrate
