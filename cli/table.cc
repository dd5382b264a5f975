// rockcal table: pool the calibrated parameters of many sites into a default
// table per material class (median, range, count of sites).
#include "table.h"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "args.h"
#include "rockcal/calibrate/default_table.h"
#include "rockcal/core/error.h"
#include "rockcal/reports/default_table_outputs.h"
#include "rockcal/reports/output_dir.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;

// Two spellings of one folder ("out", "./out/", a link to it).
bool SamePath(const std::string& a, const std::string& b) {
  auto normal = [](const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (!p.has_filename()) p = p.parent_path();
    return p;
  };
  return normal(a) == normal(b);
}

}  // namespace

int Table(const std::vector<std::string>& argv) {
  const Args args(argv, {"force", "include-at-bound", "quiet"}, {"bound-tolerance", "out"});
  const std::vector<std::string>& dirs = args.positionals();
  if (dirs.empty())
    throw InputError("arguments",
                     "expected at least one RESULT_DIR (the --out folder of a "
                     "rockcal calibrate run)");
  const std::string out = args.Get("out");
  calibrate::DefaultTableOptions options;
  options.bound_fraction = args.Number("bound-tolerance", options.bound_fraction, 0.0, 0.5);
  options.include_at_bound = args.Flag("include-at-bound");
  std::string error;
  if (!options.IsValid(&error))
    throw InputError("argument --bound-tolerance",
                     "'" + args.Get("bound-tolerance") +
                         "' is not in [0, 0.5) (the share of a parameter's range within which "
                         "a value counts as at its bound)");
  for (const std::string& d : dirs) {
    // --force must never replace a calibration with its table.
    if (SamePath(d, out))
      throw InputError("argument --out " + out,
                       "is one of the result folders read; expected a new folder");
  }

  // Read and check everything before anything is written.
  std::vector<calibrate::CalibratedSite> sites;
  for (const std::string& d : dirs) sites.push_back(calibrate::ReadCalibratedSite(d));
  const calibrate::DefaultTable table = calibrate::BuildDefaultTable(sites, options);

  reports::OutputDir dir(out, args.Flag("force"));
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
