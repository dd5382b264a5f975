#include "command_flags.h"

#include <stdexcept>

namespace rockcal::cli {

const std::vector<CommandFlags>& AllCommandFlags() {
  static const std::vector<CommandFlags> table = {
      {"simulate",
       {"force", "quiet", "rasters", "point-values", "no-forest", "compare-bare"},
       {"rocks", "seed", "set", "parameters", "draws", "class-values", "trajectories",
        "sample-seconds", "threads", "out"},
       {"set"}},
      {"calibrate",
       {"force", "quiet", "resume", "rasters", "posterior", "posterior-log-sigma", "no-forest"},
       {"observations",
        "method",
        "methods",
        "max-evals",
        "max-seconds",
        "rocks",
        "refine",
        "race",
        "seed",
        "threads",
        "loss",
        "estimate",
        "holdout",
        "reach",
        "noise-raise",
        "out",
        "posterior-points",
        "posterior-rounds",
        "posterior-stage",
        "predictive"},
       {}},
      {"campaign",
       {"force", "quiet", "resume", "posterior", "posterior-log-sigma"},
       {"method", "methods", "max-evals", "max-seconds", "rocks", "seed", "threads", "loss",
        "estimate", "out", "posterior-points", "posterior-rounds", "predictive"},
       {}},
      {"score",
       {"force", "quiet"},
       {"observations", "parameters", "rocks", "seed", "threads", "out"},
       {}},
      {"sensitivity",
       {"force", "quiet"},
       {"method", "samples", "observations", "rocks", "seed", "set", "threads", "out"},
       {"set"}},
      // One reader for the three studies; each study refuses the others'
      // options by name (study.cc).
      {"study",
       {"force", "quiet"},
       {"rocks", "seed", "set", "cases", "steps-per-contact", "rock-counts", "target", "bootstrap",
        "threads", "observations", "points", "design", "out"},
       {"set"}},
      {"table", {"force", "include-at-bound", "quiet"}, {"about", "bound-tolerance", "out"}, {}},
      {"validate", {}, {"observations", "write-impacts"}, {}},
  };
  return table;
}

const CommandFlags& FlagsOf(const std::string& command) {
  for (const CommandFlags& c : AllCommandFlags())
    if (c.command == command) return c;
  throw std::logic_error("no flag table for the command '" + command + "'");
}

}  // namespace rockcal::cli
