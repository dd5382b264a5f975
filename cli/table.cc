// rockcal table: pool the calibrated parameters of many sites into a default
// table per material class (median, range, count of sites).
#include "table.h"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "args.h"
#include "commands.h"
#include "rockcal/calibrate/default_table.h"
#include "rockcal/core/error.h"
#include "rockcal/reports/default_table_outputs.h"
#include "rockcal/reports/output_dir.h"
#include "run_inputs.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;

// A calibration folder that a killed run left incomplete: it has the
// evaluation log but not calibration.json, written after every other file
// when the calibration finishes (a --resume removes it until then).
void CheckComplete(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(fs::path(dir) / "evaluations.jsonl", ec) &&
      !fs::exists(fs::path(dir) / "calibration.json", ec))
    throw InputError(dir,
                     "incomplete calibration: no calibration.json, so the calibration did not "
                     "finish (expected a finished rockcal calibrate folder; continue it with "
                     "--resume)");
}

}  // namespace

int Table(const std::vector<std::string>& argv) {
  const Args args(argv, FlagsOf("table"));
  const std::vector<std::string>& dirs = args.positionals();
  if (dirs.empty())
    throw InputError("arguments",
                     "expected at least one RESULT_DIR (the --out folder of a "
                     "rockcal calibrate run)");
  calibrate::DefaultTableOptions options;
  options.bound_fraction = args.Number("bound-tolerance", options.bound_fraction, 0.0, 0.5);
  options.include_at_bound = args.Flag("include-at-bound");
  std::string error;
  if (!options.IsValid(&error))
    throw InputError("argument --bound-tolerance",
                     "'" + args.Get("bound-tolerance") +
                         "' is not in [0, 0.5) (the share of a parameter's range within which "
                         "a value counts as at its bound)");
  const std::string out = OutFolder(args, "", "table");
  // --force must never replace a calibration with its table.
  RunInputs inputs;
  for (const std::string& d : dirs) inputs.Add(d);
  if (args.Has("about")) inputs.Add(args.Get("about"));
  reports::CheckOutputAgainstInputs(out, inputs.paths());
  for (const std::string& d : dirs) CheckComplete(d);

  // Read and check everything before anything is written.
  std::vector<calibrate::CalibratedSite> sites;
  for (const std::string& d : dirs) sites.push_back(calibrate::ReadCalibratedSite(d));
  const calibrate::DefaultTable table =
      args.Has("about")
          ? calibrate::BuildDefaultTable(sites, options, calibrate::ReadTableAbout(args.Get("about")))
          : calibrate::BuildDefaultTable(sites, options);

  RankOutputDir dir(out, args.Flag("force"),
                    inputs.Origin("table"));  // under mpirun: rank 0 writes
  const std::string markdown = reports::DefaultTableMarkdown(table);
  reports::WriteFileAtomically(dir.File("table.json"),
                               reports::DefaultTableJson(table).dump(2) + "\n");
  reports::WriteFileAtomically(dir.File("table.csv"), reports::DefaultTableCsv(table));
  reports::WriteFileAtomically(dir.File("values.csv"), reports::DefaultTableValuesCsv(table));
  reports::WriteFileAtomically(dir.File("table.md"), markdown);
  dir.Commit();
  if (!args.Flag("quiet")) {
    std::printf(
        "%s\nwrote %s/: table.json, table.csv, values.csv, table.md (%zu rows from %zu "
        "result folders)\n",
        markdown.c_str(), out.c_str(), table.rows.size(), sites.size());
  }
  return 0;
}

}  // namespace rockcal::cli
