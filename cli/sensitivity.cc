// rockcal sensitivity: which calibrated parameters move which simulated
// quantities, by Morris elementary effects or Sobol indices, against the
// Monte Carlo noise of one run. See calibrate/STUDIES.md.
#include "sensitivity.h"

#include <cstdio>
#include <optional>
#include <string>

#include "args.h"
#include "commands.h"
#include "progress.h"
#include "rockcal/calibrate/sensitivity.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/result_files.h"
#include "rockcal/sites/site.h"
#include "run_inputs.h"

namespace rockcal::cli {

int Sensitivity(const std::vector<std::string>& argv) {
  const Args args(argv, FlagsOf("sensitivity"));
  const std::string site_path = args.OnlyPositional("SITE.json");
  calibrate::SensitivityOptions opt;
  const std::string method = args.Get("method", calibrate::SensitivityMethodToString(opt.method));
  if (!calibrate::StringToSensitivityMethod(method, &opt.method))
    throw InputError("argument --method", "unknown method '" + method + "' (allowed: " +
                                              calibrate::SensitivityMethodNames() + ")");
  const bool morris = opt.method == calibrate::SensitivityMethod::kMorris;
  if (args.Has("samples"))
    opt.samples = static_cast<int>(args.Integer("samples", 0, morris ? 2 : 4, 100000));
  if (args.Has("seed"))
    opt.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  opt.threads = static_cast<int>(args.Integer("threads", opt.threads, 0, 1024));
  std::string error;
  if (!opt.IsValid(&error)) throw InputError("arguments", error);

  sites::Site site = sites::LoadSite(site_path);
  for (const std::string& kv : args.All("set")) sites::ApplySetting(kv, &site);
  if (args.Has("rocks"))
    site.scene.SetTotalRocks(static_cast<int>(args.Integer("rocks", 0, 1, core::kMaxRocks)));
  if (!site.scene.IsValid(&error)) throw InputError(site_path, error);
  if (site.calibrate.empty())
    throw InputError(site_path,
                     "no \"calibrate\" bounds: the sensitivity study varies the calibrated "
                     "parameters, so give at least one material a \"calibrate\" object, e.g. "
                     "\"calibrate\": {\"hardness\": [0.1, 0.6]}");
  (void)calibrate::ParameterSpace::FromSite(site);  // the bounds can be searched
  std::optional<observations::Observations> obs;
  if (args.Has("observations"))
    obs = observations::LoadObservations(args.Get("observations"), site.scene);

  const std::string out = OutFolder(args, site_path, "sensitivity");
  RunInputs inputs;
  inputs.Add(site);
  if (obs) inputs.Add(*obs);
  RankOutputDir dir(out, args.Flag("force"), inputs.Origin("sensitivity"));
  calibrate::SensitivityResult result;
  {
    Progress progress("sensitivity " + method, args.Flag("quiet"));
    opt.progress = [&](int done, int total, const std::string& what) {
      progress.Update(done, total, what);
    };
    result = calibrate::RunSensitivity(site, obs ? &*obs : nullptr, opt);
  }
  const std::string& name = site.scene.name;
  reports::StudyReportInput report;
  report.scene = &site.scene;
  report.site_file = site.path;
  report.units = site.units;
  report.notes = site.notes;
  reports::WriteSensitivityFiles(dir.folder(), report, result);
  dir.Commit();
  if (!args.Flag("quiet")) {
    std::printf("%s: sensitivity study (%s), %zu parameters, %zu outputs, %d rocks per run\n",
                name.c_str(), method.c_str(), result.parameters.size(), result.outputs.size(),
                result.rocks);
    std::fputs(calibrate::SensitivityReport(result).c_str(), stdout);
    std::printf("wrote %s/sensitivity.json, sensitivity.csv, report.html\n", out.c_str());
  } else {
    std::printf("%s\n", result.summary.c_str());
  }
  return 0;
}

}  // namespace rockcal::cli
