// rockcal: the command line. Exit status 0 on success, 2 on bad input, 1 on
// any other failure.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "commands.h"
#include "rockcal/core/error.h"
#include "rockcal/parallel/parallel.h"
#include "sensitivity.h"
#include "study.h"
#include "table.h"

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  rockcal simulate SITE.json [--rocks N] [--seed S] [--parameters parameters.json]\n"
    "                   [--set KEY=VALUE ...]\n"
    "                   [--trajectories N --sample-seconds DT] [--rasters] [--threads N]\n"
    "                   [--force] [--quiet] --out DIR\n"
    "  rockcal calibrate SITE.json --observations OBS.json [--method M | --methods M1,M2,...]\n"
    "                   [--max-evals N] [--max-seconds T] [--rocks N | --refine F [--race N]]\n"
    "                   [--seed S] [--threads N]\n"
    "                   [--loss none|huber|cauchy] [--estimate lowest|smoothed]\n"
    "                   [--holdout K] [--reach N] [--rasters] [--resume | --force] [--quiet]\n"
    "                   --out DIR\n"
    "  rockcal campaign CAMPAIGN.json [--method M | --methods M1,M2,...] [--max-evals N]\n"
    "                   [--max-seconds T] [--rocks N] [--seed S] [--threads N]\n"
    "                   [--loss none|huber|cauchy] [--estimate lowest|smoothed]\n"
    "                   [--resume | --force] [--quiet] --out DIR\n"
    "  rockcal score SITE.json --observations OBS.json [--parameters parameters.json]\n"
    "                   [--rocks N] [--seed S] [--threads N] [--force] [--quiet] --out DIR\n"
    "  rockcal sensitivity SITE.json [--method morris|sobol] [--samples N] [--observations OBS.json]\n"
    "                   [--rocks N] [--seed S] [--set K=V ...] [--threads N]\n"
    "                   [--force] [--quiet] --out DIR\n"
    "  rockcal study stability SITE.json [--rocks N] [--seed S] [--cases A,B,...] [--set K=V ...]\n"
    "                   [--threads N] [--force] [--quiet] --out DIR\n"
    "  rockcal study convergence SITE.json [--steps-per-contact LIST] [--rock-counts LIST]\n"
    "                   [--target F] [--bootstrap N] [--seed S] [--set K=V ...] [--threads N]\n"
    "                   [--force] [--quiet] --out DIR\n"
    "  rockcal study reach SITE.json --observations OBS.json [--points N] [--design lhs|halton]\n"
    "                   [--rocks N] [--seed S] [--set K=V ...] [--threads N]\n"
    "                   [--force] [--quiet] --out DIR\n"
    "  rockcal table RESULT_DIR... [--include-at-bound] [--bound-tolerance F]\n"
    "                   [--force] [--quiet] --out DIR\n"
    "  rockcal validate SITE.json [--observations OBS.json]\n"
    "\n"
    "Under mpirun -np N (or srun), every command spreads its simulations over the N\n"
    "ranks (OMP_NUM_THREADS or --threads: threads per rank) with results identical\n"
    "to a single process; only rank 0 writes and prints. ROCKCAL_RANK_TIMEOUT\n"
    "(seconds) bounds the wait for a rank before it is reported dead or hung.\n"
    "\n"
    "KEY for --set: material.<id>.hardness | .roughness | .contact_time | .rolling_resistance\n"
    "               | .friction | .vegetation (site units: ft or m, lbf/ft^2 or kPa)\n"
    "--rasters: also write DIR/rasters.tif (GeoTIFF, one band per map: passages,\n"
    "           reach_probability, stop_density, energy_max, energy_p95, height_max,\n"
    "           height_p95) and DIR/rasters/<band>.asc (ESRI ASCII grids), on the site grid\n"
    "           with the terrain's CRS; on by default for a site read from GIS files\n";

}  // namespace

int main(int argc, char** argv) {
  // Under mpirun, every rank runs the same command (parallel.h); only rank 0
  // writes and prints.
  const rockcal::parallel::Session session(&argc, &argv);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "simulate") return rockcal::cli::Simulate(args);
    if (command == "validate") return rockcal::cli::Validate(args);
    if (command == "calibrate") return rockcal::cli::Calibrate(args);
    if (command == "campaign") return rockcal::cli::Campaign(args);
    if (command == "score") return rockcal::cli::Score(args);
    if (command == "sensitivity") return rockcal::cli::Sensitivity(args);
    if (command == "study") return rockcal::cli::Study(args);
    if (command == "table") return rockcal::cli::Table(args);
    throw rockcal::InputError("", "unknown command '" + command +
                                      "' (available: simulate, calibrate, campaign, score, sensitivity, study, "
                                      "table, validate; see rockcal --help)");
  } catch (const rockcal::InputError& e) {
    std::fprintf(stderr, "rockcal: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rockcal: failed: %s\n", e.what());
    return 1;
  }
}
