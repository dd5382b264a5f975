#include "study.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "args.h"
#include "commands.h"
#include "progress.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/reach.h"
#include "rockcal/calibrate/study.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/result_files.h"
#include "rockcal/sites/site.h"
#include "run_inputs.h"

namespace rockcal::cli {
namespace {

constexpr const char* kStudies = "stability, convergence, reach";

// A comma-separated list of whole numbers in [lo, hi] given to --name.
std::vector<int> IntegerList(const Args& args, const std::string& name, long lo, long hi) {
  const std::string text = args.Get(name);
  std::vector<int> out;
  for (const std::string& item : args.List(name)) {
    char* end = nullptr;
    const long x = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || x < lo || x > hi)
      throw InputError("argument --" + name,
                       "'" + item + "'" + (item == text ? "" : " in '" + text + "'") +
                           " is not a whole number in [" + std::to_string(lo) + ", " +
                           std::to_string(hi) +
                           "] (expected a comma-separated list, e.g. 10,20,50)");
    out.push_back(static_cast<int>(x));
  }
  return out;
}

// The site section of a study's report.html.
reports::StudyReportInput ReportInput(const sites::Site& site) {
  reports::StudyReportInput in;
  in.scene = &site.scene;
  in.site_file = site.path;
  in.units = site.units;
  in.notes = site.notes;
  return in;
}

// Options that belong to the other study are errors, not silently ignored.
void RejectOptions(const Args& args, const std::string& study,
                   const std::vector<std::pair<const char*, const char*>>& options) {
  for (const auto& [name, hint] : options)
    if (args.Has(name))
      throw InputError("argument --" + std::string(name),
                       "not an option of 'study " + study + "' (" + hint + ")");
}

int Stability(const Args& args, sites::Site* site, const std::string& out) {
  RejectOptions(args, "stability",
                {{"steps-per-contact", "a convergence option"},
                 {"rock-counts", "a convergence option; --rocks N sets the rocks per case"},
                 {"target", "a convergence option"},
                 {"bootstrap", "a convergence option"},
                 {"observations", "a reach option"},
                 {"points", "a reach option"},
                 {"design", "a reach option"}});
  calibrate::StabilityOptions opt;
  opt.rocks = static_cast<int>(args.Integer("rocks", opt.rocks, 1, 1000000));
  if (args.Has("seed"))
    opt.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  opt.threads = static_cast<int>(args.Integer("threads", opt.threads, 0, 1024));
  if (args.Has("cases"))
    for (const std::string& name : args.List("cases")) {
      calibrate::StabilityCaseId id;
      if (!calibrate::StringToStabilityCase(name, &id))
        throw InputError("argument --cases", "unknown case '" + name + "' (allowed: " +
                                                 calibrate::StabilityCaseNames() + ")");
      opt.cases.push_back(id);
    }
  std::string error;
  if (!opt.IsValid(&error)) throw InputError("arguments", error);

  RankOutputDir dir(out, args.Flag("force"), RunInputs().Add(*site).Origin("study stability"));
  Progress progress("stability", args.Flag("quiet"));
  opt.progress = [&](int done, int total, const std::string& what) {
    progress.Update(done, total, what);
  };
  const calibrate::StabilityStudy study = calibrate::RunStabilitySuite(site->scene, opt);
  reports::WriteStabilityFiles(dir.folder(), ReportInput(*site), study);
  dir.Commit();
  const std::vector<calibrate::StabilityCase>& cases = study.cases;
  const int failed = study.failed();
  if (!args.Flag("quiet")) {
    std::printf("%s: stability suite, %d rocks per case\n", site->scene.name.c_str(), opt.rocks);
    std::fputs(calibrate::StabilityReport(cases).c_str(), stdout);
    std::printf(
        "%zu cases: %zu PASS, %d FAIL; wrote %s/stability.json, stability.csv, report.html\n",
        cases.size(), cases.size() - static_cast<std::size_t>(failed), failed, out.c_str());
  } else {
    for (const auto& c : cases)
      if (!c.pass) std::printf("FAIL %s: %s\n", c.name.c_str(), c.reason.c_str());
  }
  return 0;
}

int Convergence(const Args& args, sites::Site* site, const std::string& out) {
  RejectOptions(args, "convergence",
                {{"rocks", "use --rock-counts LIST, e.g. --rock-counts 100,300,1000"},
                 {"cases", "a stability option"},
                 {"observations", "a reach option"},
                 {"points", "a reach option"},
                 {"design", "a reach option"}});
  calibrate::ConvergenceOptions opt;
  if (args.Has("steps-per-contact"))
    opt.steps_per_contact = IntegerList(args, "steps-per-contact", 4, 100000);
  if (args.Has("rock-counts"))
    opt.rock_counts = IntegerList(args, "rock-counts", 1, core::kMaxRocks);
  opt.target = args.Number("target", opt.target, 1e-9, 10.0);
  opt.bootstrap = static_cast<int>(args.Integer("bootstrap", opt.bootstrap, 20, 1000000));
  if (args.Has("seed"))
    opt.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  opt.threads = static_cast<int>(args.Integer("threads", opt.threads, 0, 1024));
  std::string error;
  if (!opt.IsValid(&error)) throw InputError("arguments", error);

  RankOutputDir dir(out, args.Flag("force"), RunInputs().Add(*site).Origin("study convergence"));
  calibrate::ConvergenceResult result;
  {
    Progress progress("convergence", args.Flag("quiet"));
    opt.progress = [&](int done, int total, const std::string& what) {
      progress.Update(done, total, what);
    };
    result = calibrate::RunConvergence(site->scene, opt);
  }
  const std::string& name = site->scene.name;
  reports::WriteConvergenceFiles(dir.folder(), ReportInput(*site), result);
  dir.Commit();
  if (!args.Flag("quiet")) {
    std::printf("%s: convergence study, %d threads\n", name.c_str(), result.threads);
    std::fputs(calibrate::ConvergenceReport(result).c_str(), stdout);
    std::printf("wrote %s/convergence.json, convergence.csv, convergence.svg, report.html\n",
                out.c_str());
  } else {
    std::printf("recommendation: %s\n", result.recommendation.c_str());
  }
  return 0;
}

int Reach(const Args& args, sites::Site* site, const std::string& out) {
  RejectOptions(args, "reach",
                {{"steps-per-contact", "a convergence option"},
                 {"rock-counts", "a convergence option; --rocks N sets the rocks per point"},
                 {"target", "a convergence option"},
                 {"bootstrap", "a convergence option"},
                 {"cases", "a stability option"}});
  const std::string& site_path = args.positionals()[1];
  core::Scene& scene = site->scene;
  if (args.Has("rocks"))
    scene.SetTotalRocks(static_cast<int>(args.Integer("rocks", 0, 1, 100000000)));
  if (args.Has("seed"))
    scene.options.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  scene.options.threads = static_cast<int>(args.Integer("threads", scene.options.threads, 0, 1024));
  calibrate::ReachOptions opt;
  opt.seed = scene.options.seed;
  if (args.Has("points")) opt.points = static_cast<int>(args.Integer("points", 0, 2, 100000));
  const std::string design = args.Get("design", calibrate::DesignKindToString(opt.design));
  if (!calibrate::StringToDesignKind(design, &opt.design))
    throw InputError("argument --design", "unknown design '" + design +
                                              "' (allowed: " + calibrate::DesignKindNames() + ")");
  std::string error;
  if (!opt.IsValid(&error)) throw InputError("arguments", error);
  if (!scene.options.IsValid(&error)) throw InputError(site_path, error);
  if (site->calibrate.empty())
    throw InputError(site_path,
                     "no \"calibrate\" bounds: the reach check samples the calibration box, so "
                     "give at least one material a \"calibrate\" object, e.g. \"calibrate\": "
                     "{\"hardness\": [0.1, 0.6]}");
  const calibrate::ParameterSpace space = calibrate::ParameterSpace::FromSite(*site);
  const observations::Observations obs =
      observations::LoadObservations(args.Get("observations"), scene);

  RankOutputDir dir(out, args.Flag("force"), RunInputs().Add(*site).Add(obs).Origin("study reach"));
  const calibrate::Objective objective(scene, space, obs, observations::MisfitOptions{});
  calibrate::ReachResult result;
  {
    Progress progress("reach", args.Flag("quiet"));
    opt.progress = [&](int done, int total, const std::string& what) {
      progress.Update(done, total, what);
    };
    result = calibrate::RunReach(objective, opt);
  }
  const std::string& name = scene.name;
  reports::WriteReachFiles(dir.folder(), ReportInput(*site), result);
  dir.Commit();
  if (!args.Flag("quiet")) {
    std::printf("%s: reach check, %d parameters\n", name.c_str(), space.size());
    std::fputs(result.FullReport().c_str(), stdout);
    std::printf("wrote %s/reach.json, reach.csv, report.html\n", out.c_str());
  } else {
    for (const std::string& w : calibrate::OutOfReachWarnings(result, false))
      std::printf("OUT OF REACH: %s\n", w.c_str());
    if (const std::string advice = calibrate::OutOfReachAdvice(result); !advice.empty())
      std::printf("  %s\n", advice.c_str());
  }
  return 0;
}

}  // namespace

int Study(const std::vector<std::string>& argv) {
  const Args args(argv, FlagsOf("study"));
  const auto& pos = args.positionals();
  if (pos.empty() || (pos[0] != "stability" && pos[0] != "convergence" && pos[0] != "reach"))
    throw InputError("arguments", "expected the study (" + std::string(kStudies) + ")" +
                                      (pos.empty() ? "" : ", found '" + pos[0] + "'"));
  if (pos.size() != 2)
    throw InputError("arguments", "expected the study and exactly one SITE.json (found " +
                                      std::to_string(pos.size() - 1) + " files)");
  sites::Site site = sites::LoadSite(pos[1]);
  for (const std::string& kv : args.All("set")) sites::ApplySetting(kv, &site);
  std::string error;
  if (!site.scene.IsValid(&error)) throw InputError(pos[1], error);
  const std::string out = OutFolder(args, pos[1], pos[0]);
  if (pos[0] == "stability") return Stability(args, &site, out);
  if (pos[0] == "convergence") return Convergence(args, &site, out);
  return Reach(args, &site, out);
}

}  // namespace rockcal::cli
