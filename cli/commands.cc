#include "commands.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "args.h"
#include "progress.h"
#include "rockcal/core/error.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/observations.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/sites/site.h"

namespace rockcal::cli {

// ---- Args ----------------------------------------------------------------

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& flags,
           const std::set<std::string>& options, const std::set<std::string>& multi) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.rfind("--", 0) != 0) {
      positionals_.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (flags.count(name)) {
      if (inline_value) throw InputError("argument " + a, "--" + name + " takes no value");
      flags_.insert(name);
    } else if (options.count(name)) {
      if (!inline_value) {
        if (i + 1 >= argv.size()) throw InputError("argument " + a, "--" + name + " needs a value");
        value = argv[++i];
      }
      if (values_.count(name) && !multi.count(name))
        throw InputError("argument " + a, "--" + name + " given twice");
      values_.emplace(name, value);
    } else {
      std::string list;
      for (const auto& f : flags) list += " --" + f;
      for (const auto& o : options) list += " --" + o;
      throw InputError("argument " + a, "unknown option (allowed:" + list + ")");
    }
  }
}

std::string Args::Get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw InputError("arguments", "missing required --" + name);
  return it->second;
}

std::string Args::Get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

std::vector<std::string> Args::All(const std::string& name) const {
  std::vector<std::string> out;
  auto range = values_.equal_range(name);
  for (auto it = range.first; it != range.second; ++it) out.push_back(it->second);
  return out;
}

long Args::Integer(const std::string& name, long fallback, long lo, long hi) const {
  if (!Has(name)) return fallback;
  const std::string v = Get(name);
  char* end = nullptr;
  const long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || x < lo || x > hi)
    throw InputError("argument --" + name, "'" + v + "' is not a whole number in [" +
                                               std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return x;
}

double Args::Number(const std::string& name, double fallback, double lo, double hi) const {
  if (!Has(name)) return fallback;
  const std::string v = Get(name);
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !std::isfinite(x) || x < lo || x > hi) {
    std::ostringstream s;
    s << "'" << v << "' is not a number in [" << lo << ", " << hi << "]";
    throw InputError("argument --" + name, s.str());
  }
  return x;
}

namespace {

std::string OnePositional(const Args& args, const char* what) {
  if (args.positionals().size() != 1)
    throw InputError("arguments", std::string("expected exactly one ") + what + " (found " +
                                      std::to_string(args.positionals().size()) + ")");
  return args.positionals()[0];
}

// Spreads `total` rocks over the groups in proportion to their counts
// (largest remainder), keeping the groups' order.
void ScaleRockCount(long total, core::Scene* scene) {
  const int old_total = scene->total_rocks();
  std::vector<double> exact;
  long assigned = 0;
  for (auto& g : scene->groups) {
    exact.push_back(static_cast<double>(total) * g.count / old_total);
    g.count = static_cast<int>(std::floor(exact.back()));
    assigned += g.count;
  }
  while (assigned < total) {
    std::size_t best = 0;
    double best_frac = -1.0;
    for (std::size_t k = 0; k < exact.size(); ++k) {
      const double frac = exact[k] - scene->groups[k].count;
      if (frac > best_frac) {
        best_frac = frac;
        best = k;
      }
    }
    ++scene->groups[best].count;
    exact[best] = scene->groups[best].count;  // taken
    ++assigned;
  }
}

}  // namespace

// ---- simulate --------------------------------------------------------------

int Simulate(const std::vector<std::string>& argv) {
  const Args args(argv, {"force", "quiet"},
                  {"rocks", "seed", "set", "trajectories", "sample-seconds", "threads", "out"}, {"set"});
  const std::string site_path = OnePositional(args, "SITE.json");
  const std::string out = args.Get("out");
  sites::Site site = sites::LoadSite(site_path);
  for (const std::string& kv : args.All("set")) sites::ApplySetting(kv, &site);
  core::Scene& scene = site.scene;
  if (args.Has("rocks")) ScaleRockCount(args.Integer("rocks", 0, 1, 100000000), &scene);
  if (args.Has("seed"))
    scene.options.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, 1L << 62));
  scene.options.threads = static_cast<int>(args.Integer("threads", 0, 0, 1024));
  scene.options.record.trajectories = static_cast<int>(args.Integer("trajectories", 0, 0, 1000000));
  if (args.Has("sample-seconds") && !args.Has("trajectories"))
    throw InputError("argument --sample-seconds", "goes with --trajectories N");
  scene.options.record.sample_seconds = args.Number("sample-seconds", 0.05, 1e-6, 1e6);
  std::string error;
  if (!scene.options.IsValid(&error)) throw InputError(site_path, error);

  reports::OutputDir dir(out, args.Flag("force"));
  Progress progress("simulate", args.Flag("quiet"));
  const core::Terrain terrain = core::BuildTerrain(scene);
  const core::SimulationResult result =
      core::Simulate(scene, terrain, [&](int done, int total) { progress.Update(done, total); });
  reports::WriteFileAtomically(dir.File("summary.json"),
                               reports::SummaryJson(scene, result).dump(2) + "\n");
  reports::WriteFileAtomically(dir.File("diagnostics.json"),
                               reports::DiagnosticsJson(scene, result).dump(2) + "\n");
  reports::WriteFileAtomically(dir.File("rocks.csv"), reports::RocksCsv(scene, result));
  if (scene.options.record.trajectories > 0)
    reports::WriteFileAtomically(dir.File("trajectories.csv"), reports::TrajectoriesCsv(result));
  dir.Commit();
  if (!args.Flag("quiet")) {
    std::printf("%s: %zu rocks in %.2f s (%ld steps, %ld flights): %d stopped, %d left, %d timeout\n",
                scene.name.c_str(), result.rocks.size(), result.wall_seconds, result.steps,
                result.flights, result.count(core::Outcome::kStopped),
                result.count(core::Outcome::kLeft), result.count(core::Outcome::kTimeout));
    std::printf("wrote %s/summary.json, rocks.csv, diagnostics.json%s\n", out.c_str(),
                scene.options.record.trajectories > 0 ? ", trajectories.csv" : "");
  }
  if (result.non_finite > 0) {
    std::fprintf(stderr, "rockcal: failed: %d rocks reached a non-finite state\n", result.non_finite);
    return 1;
  }
  return 0;
}

// ---- validate --------------------------------------------------------------

int Validate(const std::vector<std::string>& argv) {
  const Args args(argv, {}, {"observations"});
  const std::string site_path = OnePositional(args, "SITE.json");
  const sites::Site site = sites::LoadSite(site_path);
  const core::Scene& scene = site.scene;
  std::printf("site '%s' (%s): OK\n", scene.name.c_str(), site_path.c_str());
  for (const std::string& note : site.notes) std::printf("  %s\n", note.c_str());
  const core::Terrain terrain = core::BuildTerrain(scene);
  std::printf("materials:\n");
  std::vector<int> nodes(scene.materials.size(), 0);
  for (std::size_t n = 0; n < scene.grid.z.size(); ++n)
    if (!std::isnan(scene.grid.z[n])) ++nodes[static_cast<std::size_t>(scene.grid.material[n])];
  for (std::size_t k = 0; k < scene.materials.size(); ++k) {
    const core::Material& m = scene.materials[k];
    const core::ContactLaw law = core::DeriveContactLaw(m, scene.hardness_model);
    std::printf(
        "  %-12s %7d nodes  hardness %.3f  roughness %.3f m (sphere r %.3g m)  e %.3f  f %.3f  "
        "t_c %.4g s  zeta %.3f (eq. 13: %.3f)\n",
        m.id.c_str(), nodes[k], m.hardness, m.roughness_m,
        core::VirtualSphereRadius(m.roughness_m, scene.grid.spacing), law.restitution, law.friction,
        law.contact_time, law.damping_ratio, law.eq13_damping_ratio);
  }
  std::printf("partitions:\n");
  for (const auto& p : scene.partitions)
    std::printf("  %-10s %s = %.3f m\n", p.id.c_str(),
                p.kind == core::Partition::Kind::kX ? "x" : "z", p.value);
  std::printf("rock groups:\n");
  for (const auto& g : scene.groups) {
    const core::RockBody lo = core::MakeRockBody(g.shape, g.size_min, g.unit_weight, scene.gravity);
    const core::RockBody hi = core::MakeRockBody(g.shape, g.size_max, g.unit_weight, scene.gravity);
    double dt = INFINITY;
    bool shrunk = false;
    for (const auto& m : scene.materials) {
      bool sh = false;
      dt = std::min(dt, core::ContactTimeStep(lo, core::DeriveContactLaw(m, scene.hardness_model),
                                              scene.options, &sh));
      shrunk = shrunk || sh;
    }
    std::printf("  %5d %-11s size %.3f-%.3f m  mass %.4g-%.4g kg  contact step %.3g s%s\n", g.count,
                core::ShapeName(g.shape), g.size_min, g.size_max, lo.mass, hi.mass, dt,
                shrunk ? " (shrunk for stability)" : "");
  }
  if (args.Has("observations")) {
    const observations::Observations obs =
        observations::LoadObservations(args.Get("observations"), scene);
    std::printf("observations '%s': OK\n", args.Get("observations").c_str());
    for (const std::string& note : obs.notes) std::printf("  %s\n", note.c_str());
  }
  return 0;
}

}  // namespace rockcal::cli
