// rockcal: the command line. Exit status 0 on success, 2 on bad input, 1 on
// any other failure.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "commands.h"
#include "help.h"
#include "rockcal/core/error.h"
#include "rockcal/parallel/parallel.h"
#include "sensitivity.h"
#include "study.h"
#include "table.h"

#ifndef ROCKCAL_VERSION
#define ROCKCAL_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  // Line by line into a pipe or a file too (a log, tee, a job scheduler's
  // output), not in blocks at exit: what a run says appears as it says it.
  std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);
  // Under mpirun, every rank runs the same command (parallel.h); only rank 0
  // writes and prints.
  const rockcal::parallel::Session session(&argc, &argv);
  std::vector<std::string> args(argv + 1, argv + argc);
  // The usage is docs/reference/commands.md, built in (help.h): rockcal
  // --help prints its overview, rockcal COMMAND --help the command's section.
  const std::string reference = rockcal::cli::CommandsReference();
  if (args.empty()) {
    std::fputs(rockcal::cli::ForTerminal(rockcal::cli::OverviewHelp(reference)).c_str(), stderr);
    return 2;
  }
  if (args[0] == "--version" || args[0] == "version") {
    std::printf("rockcal %s\n", ROCKCAL_VERSION);
    return 0;
  }
  if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    const std::string section =
        args.size() > 1 ? rockcal::cli::CommandHelp(reference, args[1]) : std::string();
    std::fputs(rockcal::cli::ForTerminal(section.empty() ? rockcal::cli::OverviewHelp(reference)
                                                         : section)
                   .c_str(),
               stdout);
    return 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (rockcal::cli::AsksForHelp(args)) {
    const std::string section = rockcal::cli::CommandHelp(reference, command);
    if (!section.empty()) {
      std::fputs(rockcal::cli::ForTerminal(section).c_str(), stdout);
      return 0;
    }
  }
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
  } catch (const std::bad_alloc&) {
    // docs/outputs-and-exit-codes.md: what ran out, and what to lower.
    std::fprintf(stderr,
                 "rockcal: failed: out of memory (the machine could not give rockcal the memory "
                 "this run needs); lower what the run holds: fewer rocks (--rocks, the site's "
                 "rocks), fewer --threads, a coarser surface resolution, fewer recorded "
                 "trajectories (a calibration keeps the evaluations logged so far: --resume "
                 "continues it)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rockcal: failed: %s\n", e.what());
    return 1;
  }
}
