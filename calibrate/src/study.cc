#include "rockcal/calibrate/study.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/core/name_table.h"
#include "rockcal/core/random.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using text::Num;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

// ---- Small helpers -------------------------------------------------------------

std::string Percent(double fraction) {
  if (!std::isfinite(fraction)) return "unknown";
  return core::FormatNumber(100.0 * fraction, fraction < 0.001 ? "%.2g %%" : "%.3g %%");
}

// Applies `f` to every material of the scene.
template <typename F>
void ForEachMaterial(core::Scene* scene, F f) {
  for (auto& m : scene->materials) f(&m);
}

// Index of the material whose contact law has the highest (hard) or lowest
// (soft) restitution; the first on ties. `rough_only` prefers materials with
// roughness > 0 when there are any.
int PickMaterial(const core::Scene& scene, bool hard, bool rough_only) {
  int best = -1;
  double best_e = 0.0;
  for (int pass = 0; pass < 2 && best < 0; ++pass) {
    for (std::size_t k = 0; k < scene.materials.size(); ++k) {
      const core::Material& m = scene.materials[k];
      if (pass == 0 && rough_only && !(m.roughness_m > 0.0)) continue;
      const double e = core::DeriveContactLaw(m, scene.hardness_model).restitution;
      if (best < 0 || (hard ? e > best_e : e < best_e)) {
        best = static_cast<int>(k);
        best_e = e;
      }
    }
  }
  return std::max(best, 0);
}

// ---- Stability variants ----------------------------------------------------------

const char* const kSite = "site";
const char* const kHardness0 = "hardness_0";
const char* const kHardness1 = "hardness_1";
const char* const kStiff = "contact_time_0.05ms";
const char* const kSoft = "contact_time_50ms";
const char* const kSizes = "sizes_1cm_10m";
const char* const kCliff = "vertical_cliff";
const char* const kFace = "near_vertical_face";
const char* const kFlat = "flat_runout";
const char* const kSmooth = "roughness_0";
const char* const kRoughest = "roughness_max";
const char* const kFast = "fast_release_hard";

// Cliff height of the synthetic cliff and face [m], face angle, flat runout
// release speed [m/s], fast release speed [m/s].
constexpr double kCliffHeight = 30.0;
constexpr double kFaceAngleDeg = 80.0;
constexpr double kRunoutSpeed = 10.0;
constexpr double kFastSpeed = 50.0;

// The site's scene prepared for a stability case: few rocks, bounded time,
// only the energy check recorded.
core::Scene BaseScene(const core::Scene& site, const StabilityOptions& opt) {
  core::Scene s = site;
  s.options.max_time = std::min(site.options.max_time, opt.max_time);
  if (opt.seed) s.options.seed = *opt.seed;
  s.options.threads = opt.threads;
  s.options.record = core::RecordOptions{};
  s.options.record.partitions = false;
  s.options.record.energy_check = true;
  s.partitions.clear();
  s.SetTotalRocks(opt.rocks);
  return s;
}

// Hardness h on every material, restitution and friction from the hardness
// model (overrides cleared).
void SetHardness(double h, core::Scene* s) {
  ForEachMaterial(s, [h](core::Material* m) {
    m->hardness = h;
    m->restitution.reset();
    m->friction.reset();
  });
}

// A strip along x, `width` m across, nodes every `spacing`, with elevation
// z(i) and material material(i) of node column i.
core::HeightGrid Strip(double spacing, int nx, double width, const std::function<double(int)>& z,
                       const std::function<int(int)>& material) {
  core::HeightGrid g;
  g.spacing = spacing;
  g.nx = nx;
  g.ny = std::max(3, static_cast<int>(std::ceil(width / spacing)) + 1);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      g.z.push_back(z(i));
      g.material.push_back(material(i));
    }
  return g;
}

// Replaces every group's release by a thin band across the strip at x, from
// rest or with `velocity`.
void ReleaseAcross(const core::HeightGrid& g, double x, const Eigen::Vector3d& velocity,
                   core::Scene* s) {
  const double half_x = 0.1 * g.spacing;
  const double width = (g.ny - 1) * g.spacing;
  const double y0 = 0.3 * width, y1 = 0.7 * width;
  for (auto& group : s->groups) {
    group.release = core::Release{};
    group.release.zone = {{x - half_x, y0}, {x + half_x, y0}, {x + half_x, y1}, {x - half_x, y1}};
    group.release.height = 0.0;
    group.release.velocity = velocity;
  }
}

// A slope ending in a drop of kCliffHeight (vertical: between two neighbouring
// nodes; or a face at kFaceAngleDeg), then a flat foot. The slope and the face
// take the site's hardest material, the foot its softest.
core::Scene CliffScene(const core::Scene& base, bool vertical) {
  core::Scene s = base;
  const double sp = base.grid.spacing;
  const int hard = PickMaterial(base, true, false), soft = PickMaterial(base, false, false);
  // 30-degree approach of at least 8 m, the face, a foot of at least 40 m.
  const int n_top = std::max(2, static_cast<int>(std::ceil(8.0 / sp)));
  const double face_run = vertical ? sp : kCliffHeight / std::tan(kFaceAngleDeg * kPi / 180.0);
  const int n_face = std::max(1, static_cast<int>(std::ceil(face_run / sp - 1e-9)));
  const int n_foot = std::max(10, static_cast<int>(std::ceil(40.0 / sp)));
  const int edge = n_top, bottom = n_top + n_face;
  const double slope = std::tan(30.0 * kPi / 180.0);
  auto z = [=](int i) {
    if (i <= edge) return kCliffHeight + (edge - i) * sp * slope;
    if (i >= bottom) return 0.0;
    // Face nodes: on the straight face from (edge, H) at the face angle.
    return std::max(0.0, kCliffHeight * (1.0 - (i - edge) * sp / face_run));
  };
  auto material = [=](int i) { return i < bottom ? hard : soft; };
  s.grid = Strip(sp, bottom + n_foot + 1, std::max(20.0, 4.0 * sp), z, material);
  ReleaseAcross(s.grid, 0.5 * sp, Eigen::Vector3d(2.0, 0.0, 0.0), &s);
  return s;
}

// A long flat of the site's softest rough material; rocks arrive at 10 m/s.
core::Scene FlatScene(const core::Scene& base, double max_time) {
  core::Scene s = base;
  const double sp = base.grid.spacing;
  const int soft = PickMaterial(base, false, true);
  const int nx = std::max(40, static_cast<int>(std::ceil(200.0 / sp))) + 1;
  s.grid = Strip(
      sp, nx, std::max(20.0, 4.0 * sp), [](int) { return 0.0; }, [=](int) { return soft; });
  ReleaseAcross(s.grid, 2.0 * sp, Eigen::Vector3d(kRunoutSpeed, 0.0, 0.0), &s);
  s.options.max_time = max_time;
  return s;
}

// The smallest contact step the engine will choose for any rock of the scene.
double SmallestStep(const core::Scene& s) {
  double dt = kInf;
  for (const auto& g : s.groups) {
    const core::GroupExtent extent = core::GroupBodies(g, s.gravity);
    for (const core::RockBody& body : {extent.lightest, extent.heaviest}) {
      for (const auto& m : s.materials)
        dt = std::min(dt, core::ContactTimeStep(body, core::DeriveContactLaw(m, s.hardness_model),
                                                s.options));
    }
  }
  return dt;
}

// Limits a scene's simulated time to `steps` contact steps of `dt` per rock;
// a shorter stop duration keeps stopping possible.
void CapTime(long steps, double dt, core::Scene* s) {
  const double cap = static_cast<double>(steps) * dt;
  if (!(cap < s->options.max_time)) return;
  s->options.max_time = cap;
  s->options.stop_duration = std::min(s->options.stop_duration, 0.5 * cap);
}

}  // namespace

// ---- Stability -------------------------------------------------------------------

bool StabilityOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
    *error = "stability." + field + " = " + value + ": " + rule;
    return false;
  };
  if (rocks < 1) return fail("rocks", std::to_string(rocks), "must be >= 1");
  if (!(max_time > 0 && std::isfinite(max_time)))
    return fail("max_time", Num(max_time), "must be > 0");
  if (!(energy_tolerance >= 0 && std::isfinite(energy_tolerance)))
    return fail("energy_tolerance", Num(energy_tolerance), "must be >= 0");
  if (!(penetration_limit > 0 && std::isfinite(penetration_limit)))
    return fail("penetration_limit", Num(penetration_limit), "must be > 0");
  if (max_case_steps < 1000)
    return fail("max_case_steps", std::to_string(max_case_steps), "must be >= 1000");
  if (threads < 0) return fail("threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  for (const StabilityCaseId c : cases)
    if (!*StabilityCaseToString(c))
      return fail("cases", std::to_string(static_cast<int>(c)),
                  "unknown case (allowed: " + StabilityCaseNames() + ")");
  return true;
}

namespace {

// ---- The table of stability cases: a name and how its scene is made --------

// A case's scene made from the base scene (BaseScene).
struct CaseScene {
  std::string description;
  core::Scene scene;
  bool must_stop = false;
};
using CaseMaker = CaseScene (*)(const core::Scene& base, const StabilityOptions& opt);

CaseScene SiteCase(const core::Scene& base, const StabilityOptions&) {
  return {"the site's scene as given", base};
}

CaseScene Hardness0Case(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  SetHardness(0.0, &s);
  return {"every material hardness 0: restitution at its lower clamp, softest friction "
          "(heavily overdamped contact)",
          s};
}

CaseScene Hardness1Case(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  SetHardness(1.0, &s);
  return {"every material hardness 1: restitution at its upper clamp, hardest friction", s};
}

CaseScene StiffCase(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  ForEachMaterial(&s, [](core::Material* m) { m->contact_time_s = 5e-5; });
  return {"every material contact time 0.05 ms (stiff: k_n/m 10^4 times the default)", s};
}

CaseScene SoftCase(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  ForEachMaterial(&s, [](core::Material* m) { m->contact_time_s = 0.05; });
  return {"every material contact time 50 ms (soft)", s};
}

CaseScene SizesCase(const core::Scene& base, const StabilityOptions& opt) {
  core::Scene s = base;
  core::RockGroup small = base.groups.front();
  small.size_min = small.size_max = 0.01;
  core::RockGroup huge = small;
  huge.size_min = huge.size_max = 10.0;
  // A huge rock touches tens of virtual spheres at once and costs far more
  // per step: a tenth of the rocks (at least one of each size).
  huge.count = std::max(1, opt.rocks / 10);
  small.count = std::max(1, opt.rocks - huge.count);
  s.groups = {small, huge};
  return {std::string("rocks of 1 cm and of 10 m (") + core::ShapeName(small.shape) +
              ", 9 small to 1 huge) released together from the first group's release",
          s};
}

CaseScene CliffCase(const core::Scene& base, const StabilityOptions&) {
  return {"synthetic strip: 30-degree approach, a 30 m drop between two neighbouring nodes "
          "(the steepest a height grid holds), flat foot; site's hardest and softest materials",
          CliffScene(base, true)};
}

CaseScene FaceCase(const core::Scene& base, const StabilityOptions&) {
  return {"synthetic strip: 30-degree approach, a 30 m face at 80 degrees (no overhang), flat "
          "foot; site's hardest and softest materials",
          CliffScene(base, false)};
}

CaseScene FlatCase(const core::Scene& base, const StabilityOptions& opt) {
  core::Scene s = FlatScene(base, opt.max_time);
  const core::Material& m = s.materials[static_cast<std::size_t>(s.grid.material.front())];
  std::string description = "synthetic flat of " +
                            Num((s.grid.nx - 1) * base.grid.spacing, "%.0f") + " m of material '" +
                            m.id + "' (the site's softest" +
                            (m.roughness_m > 0 ? " rough" : ", smooth") +
                            " material); rocks arrive at 10 m/s and must all stop";
  return {std::move(description), s, /*must_stop=*/true};
}

CaseScene SmoothCase(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  ForEachMaterial(&s, [](core::Material* m) { m->roughness_m = 0.0; });
  return {"every material roughness 0 (rocks touch the terrain facets)", s};
}

CaseScene RoughestCase(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  const double sp = base.grid.spacing;
  ForEachMaterial(&s, [sp](core::Material* m) { m->roughness_m = 0.5 * sp; });
  return {"every material roughness s/2 = " + Num(0.5 * sp, "%.3g") +
              " m (virtual spheres of radius s/2, the roughest)",
          s};
}

CaseScene FastCase(const core::Scene& base, const StabilityOptions&) {
  core::Scene s = base;
  SetHardness(1.0, &s);
  ForEachMaterial(&s, [](core::Material* m) { m->contact_time_s = 5e-5; });
  for (auto& g : s.groups) g.release.velocity = Eigen::Vector3d(0.0, 0.0, -kFastSpeed);
  return {"released straight down at 50 m/s onto the hardest material of the suite (hardness 1, "
          "contact time 0.05 ms)",
          s};
}

// The cases' one table, in StabilityCaseId order: name, and how its scene is made.
struct CaseInfo {
  StabilityCaseId id;
  const char* name;
  CaseMaker make;
};
const CaseInfo kCases[] = {{StabilityCaseId::kSite, kSite, SiteCase},
                           {StabilityCaseId::kHardness0, kHardness0, Hardness0Case},
                           {StabilityCaseId::kHardness1, kHardness1, Hardness1Case},
                           {StabilityCaseId::kStiff, kStiff, StiffCase},
                           {StabilityCaseId::kSoft, kSoft, SoftCase},
                           {StabilityCaseId::kSizes, kSizes, SizesCase},
                           {StabilityCaseId::kCliff, kCliff, CliffCase},
                           {StabilityCaseId::kFace, kFace, FaceCase},
                           {StabilityCaseId::kFlat, kFlat, FlatCase},
                           {StabilityCaseId::kSmooth, kSmooth, SmoothCase},
                           {StabilityCaseId::kRoughest, kRoughest, RoughestCase},
                           {StabilityCaseId::kFast, kFast, FastCase}};

}  // namespace

const char* StabilityCaseToString(StabilityCaseId id) { return core::NameOf(kCases, id); }
bool StringToStabilityCase(const std::string& name, StabilityCaseId* id) {
  return core::IdOf(kCases, name, id);
}
std::string StabilityCaseNames() { return core::NameList(kCases); }
const std::vector<StabilityCaseId>& AllStabilityCases() {
  static const std::vector<StabilityCaseId> all = core::IdList(kCases);
  return all;
}

std::vector<StabilityVariant> StabilityVariants(const core::Scene& site,
                                                const StabilityOptions& opt) {
  std::string error;
  if (!opt.IsValid(&error)) throw std::invalid_argument(error);
  if (site.groups.empty()) throw std::invalid_argument("the scene has no rock groups");
  const core::Scene base = BaseScene(site, opt);
  // Cases whose step is smaller than the site's get a budget of steps.
  const double site_dt = SmallestStep(base);
  std::vector<StabilityVariant> out;
  for (const CaseInfo& info : kCases) {
    const bool wanted = opt.cases.empty() ||
                        std::find(opt.cases.begin(), opt.cases.end(), info.id) != opt.cases.end();
    if (!wanted) continue;
    CaseScene c = info.make(base, opt);
    const double dt = SmallestStep(c.scene);
    if (dt < site_dt * (1.0 - 1e-9))
      CapTime(opt.max_case_steps / std::max(c.scene.total_rocks(), 1), dt, &c.scene);
    out.push_back({info.name, std::move(c.description), std::move(c.scene), c.must_stop});
  }
  return out;
}

namespace {

StabilityCase RunVariant(const StabilityVariant& v, const StabilityOptions& opt,
                         const core::ProgressFn& progress) {
  std::string error;
  if (!v.scene.options.IsValid(&error)) throw std::invalid_argument(v.name + ": " + error);
  const core::Terrain terrain = core::BuildTerrain(v.scene);
  const core::SimulationResult r = parallel::Simulate(v.scene, terrain, progress);
  StabilityCase c;
  c.name = v.name;
  c.description = v.description;
  c.max_time = v.scene.options.max_time;
  c.figures = r.figures;
  c.wall_seconds = r.wall_seconds;
  c.stopped = r.count(core::Outcome::kStopped);
  c.left = r.count(core::Outcome::kLeft);
  c.timeout = r.count(core::Outcome::kTimeout);
  c.must_stop = v.must_stop;
  const core::RunFigures& f = c.figures;
  std::vector<std::string> reasons;
  if (f.non_finite > 0) reasons.push_back(std::to_string(f.non_finite) + " rocks non-finite");
  if (f.tunneled > 0) reasons.push_back(std::to_string(f.tunneled) + " rocks tunneled");
  if (!(f.max_relative_energy_gain <= opt.energy_tolerance))
    reasons.push_back("energy gain " + Num(f.max_relative_energy_gain, "%.3g") + " > tolerance " +
                      Num(opt.energy_tolerance, "%.3g"));
  if (v.must_stop && c.stopped < f.rocks)
    reasons.push_back(std::to_string(f.rocks - c.stopped) + " of " + std::to_string(f.rocks) +
                      " rocks did not stop (" + std::to_string(c.left) + " left, " +
                      std::to_string(c.timeout) + " timeout)");
  for (const auto& reason : reasons) c.reason += (c.reason.empty() ? "" : "; ") + reason;
  c.pass = reasons.empty();
  if (f.max_penetration > opt.penetration_limit)
    c.warning = "overlap reached " + Num(f.max_penetration, "%.3g") +
                " element radii (advisory limit " + Num(opt.penetration_limit, "%.3g") + ")";
  return c;
}

}  // namespace

StabilityCase RunStabilityVariant(const StabilityVariant& v, const StabilityOptions& opt) {
  return RunVariant(v, opt, nullptr);
}

StabilityStudy RunStabilitySuite(const core::Scene& site, const StabilityOptions& opt) {
  const std::vector<StabilityVariant> variants = StabilityVariants(site, opt);
  int total = 0, done_before = 0;
  for (const auto& v : variants) total += v.scene.total_rocks();
  StabilityStudy study;
  study.site = site.name;
  study.seed = opt.seed.value_or(site.options.seed);
  study.limits = opt;
  for (const auto& v : variants) {
    core::ProgressFn progress;
    if (opt.progress)
      progress = [&](int done, int) { opt.progress(done_before + done, total, v.name); };
    study.cases.push_back(RunVariant(v, opt, progress));
    done_before += v.scene.total_rocks();
  }
  return study;
}

int StabilityStudy::passed() const {
  int n = 0;
  for (const StabilityCase& c : cases) n += c.pass ? 1 : 0;
  return n;
}

std::string StabilityReport(const std::vector<StabilityCase>& cases) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line, "%-20s %5s %10s %10s %6s %10s %8s %5s %5s %5s %9s %9s  %s\n",
                "case", "rocks", "dt_min_s", "dt_max_s", "shrunk", "steps", "wall_s", "stop",
                "left", "tout", "E_gain", "pen/r", "result");
  out << line;
  for (const auto& c : cases) {
    std::snprintf(
        line, sizeof line, "%-20s %5d %10.3g %10.3g %6d %10ld %8.3g %5d %5d %5d %9.2g %9.3g  %s\n",
        c.name.c_str(), c.figures.rocks, c.figures.dt_min, c.figures.dt_max, c.figures.dt_shrunk,
        c.figures.steps, c.wall_seconds, c.stopped, c.left, c.timeout,
        c.figures.max_relative_energy_gain, c.figures.max_penetration, c.pass ? "PASS" : "FAIL");
    out << line;
  }
  for (const auto& c : cases) {
    if (!c.pass) out << "FAIL " << c.name << ": " << c.reason << '\n';
    if (!c.warning.empty()) out << "warning " << c.name << ": " << c.warning << '\n';
  }
  return out.str();
}

// ---- Convergence -----------------------------------------------------------------

namespace {

constexpr double kLevels[] = {0.5, 0.9, 0.95};
constexpr const char* kLevelNames[] = {"p50", "p90", "p95"};
constexpr int kLevelCount = 3;

// Per rock, the value of each source (partition heights, then runout travel),
// NaN where the rock has none.
struct RunSamples {
  std::vector<std::vector<double>> values;  // [source][rock]
};

RunSamples Samples(const core::Scene& scene, const core::SimulationResult& r) {
  const std::size_t np = scene.partitions.size();
  RunSamples s;
  s.values.assign(np + 1, std::vector<double>(r.rocks.size(), kNaN));
  for (std::size_t k = 0; k < r.rocks.size(); ++k) {
    const core::RockRecord& rock = r.rocks[k];
    for (std::size_t p = 0; p < np && p < rock.crossings.size(); ++p)
      if (rock.crossings[p].crossed) s.values[p][k] = rock.crossings[p].height;
    if (rock.outcome == core::Outcome::kStopped) s.values[np][k] = rock.stop.x() - rock.start.x();
  }
  return s;
}

// Quantiles kLevels of the finite values of `v` picked by `pick` (all when
// empty); NaN when there are none. *count gets how many there were.
void SourceQuantiles(const std::vector<double>& v, const std::vector<std::size_t>& pick,
                     std::vector<double>* scratch, double out[kLevelCount], int* count) {
  scratch->clear();
  if (pick.empty()) {
    for (double x : v)
      if (!std::isnan(x)) scratch->push_back(x);
  } else {
    for (std::size_t k : pick)
      if (!std::isnan(v[k])) scratch->push_back(v[k]);
  }
  if (count) *count = static_cast<int>(scratch->size());
  if (scratch->empty()) {
    for (int l = 0; l < kLevelCount; ++l) out[l] = kNaN;
    return;
  }
  std::sort(scratch->begin(), scratch->end());
  for (int l = 0; l < kLevelCount; ++l) out[l] = core::Quantile(*scratch, kLevels[l]);
}

// Bootstrap replicates of every source quantile, resampling the run's rocks:
// [source * kLevelCount + level][resample], NaN where a resample had no
// value. Runs of the same rocks with the same stream draw the same resamples,
// so replicates of two such runs pair up.
std::vector<std::vector<double>> BootstrapReplicates(const RunSamples& s, int resamples,
                                                     std::uint64_t seed, std::uint64_t stream) {
  const std::size_t sources = s.values.size();
  const std::size_t n = sources ? s.values[0].size() : 0;
  std::vector<std::vector<double>> out(
      sources * kLevelCount, std::vector<double>(static_cast<std::size_t>(resamples), kNaN));
  if (n == 0) return out;
  core::RandomStream rng(seed, stream);
  std::vector<std::size_t> pick(n);
  std::vector<double> scratch;
  for (std::size_t b = 0; b < static_cast<std::size_t>(resamples); ++b) {
    for (auto& k : pick) k = static_cast<std::size_t>(rng.Uniform() * static_cast<double>(n)) % n;
    for (std::size_t src = 0; src < sources; ++src) {
      double q[kLevelCount];
      SourceQuantiles(s.values[src], pick, &scratch, q, nullptr);
      for (int l = 0; l < kLevelCount; ++l) out[src * kLevelCount + l][b] = q[l];
    }
  }
  return out;
}

// Half-width of the central `confidence` interval of the finite replicates;
// NaN when fewer than half of them are finite.
double HalfWidth(const std::vector<double>& replicates, double confidence) {
  std::vector<double> d;
  for (double x : replicates)
    if (std::isfinite(x)) d.push_back(x);
  if (d.empty() || 2 * d.size() < replicates.size()) return kNaN;
  std::sort(d.begin(), d.end());
  const double tail = 0.5 * (1.0 - confidence);
  return 0.5 * (core::Quantile(d, 1.0 - tail) - core::Quantile(d, tail));
}

struct RunData {
  int steps_per_contact = 0, rocks = 0;
  core::SimulationResult result;
  RunSamples samples;
  std::vector<double> values;                   // [source * kLevelCount + level]
  std::vector<int> counts;                      // [source]
  std::vector<std::vector<double>> replicates;  // BootstrapReplicates
};

}  // namespace

bool ConvergenceOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, const std::string& value, const std::string& rule) {
    *error = "convergence." + field + " = " + value + ": " + rule;
    return false;
  };
  if (steps_per_contact.empty()) return fail("steps_per_contact", "[]", "needs at least one value");
  for (int n : steps_per_contact)
    if (n < 4 || n > 100000)
      return fail("steps_per_contact", std::to_string(n), "each must be in [4, 100000]");
  if (rock_counts.empty()) return fail("rock_counts", "[]", "needs at least one value");
  for (int n : rock_counts)
    if (n < 1) return fail("rock_counts", std::to_string(n), "each must be >= 1");
  if (!(target > 0 && target <= 10)) return fail("target", Num(target), "must be in (0, 10]");
  if (bootstrap < 20 || bootstrap > 1000000)
    return fail("bootstrap", std::to_string(bootstrap), "must be in [20, 1000000]");
  if (!(confidence > 0.5 && confidence < 1))
    return fail("confidence", Num(confidence), "must be in (0.5, 1)");
  if (min_values < 2) return fail("min_values", std::to_string(min_values), "must be >= 2");
  if (threads < 0) return fail("threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  return true;
}

namespace {

// The table of settings: N_c and rock counts, each ascending without repeats.
struct ConvergenceGrid {
  std::vector<int> ncs, counts;
  std::size_t index(std::size_t count_index, std::size_t nc_index) const {
    return count_index * ncs.size() + nc_index;
  }
};

ConvergenceGrid MakeGrid(const ConvergenceOptions& opt) {
  ConvergenceGrid grid{opt.steps_per_contact, opt.rock_counts};
  for (std::vector<int>* v : {&grid.ncs, &grid.counts}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return grid;
}

// The runner: every setting of the grid on `base`, rock count major so each
// count's N_c series shares its rocks; runs[grid.index(count, nc)].
std::vector<RunData> RunConvergenceGrid(const core::Scene& base, const core::Terrain& terrain,
                                        const ConvergenceGrid& grid,
                                        const ConvergenceOptions& opt) {
  const std::vector<int>& ncs = grid.ncs;
  const std::size_t sources = base.partitions.size() + 1;
  long total_work = 0;
  for (int n : grid.counts) total_work += static_cast<long>(n) * static_cast<long>(ncs.size());
  long done_before = 0;
  std::string error;
  std::vector<RunData> runs;
  for (int n : grid.counts) {
    core::Scene scene = base;
    scene.SetTotalRocks(n);
    for (int nc : ncs) {
      scene.options.steps_per_contact = nc;
      // The gentle-contact step is refined with the impact step, in the
      // site's ratio N_g / N_c (10 / 50 by default; 0 stays off).
      const int ng = base.options.gentle_steps_per_contact;
      if (ng > 0)
        scene.options.gentle_steps_per_contact = std::max(
            2, static_cast<int>(std::lround(static_cast<double>(ng) * nc /
                                            base.options.steps_per_contact)));
      if (!scene.options.IsValid(&error)) throw std::invalid_argument(error);
      RunData run;
      run.steps_per_contact = nc;
      run.rocks = scene.total_rocks();
      const std::string what = "N_c " + std::to_string(nc) + ", " + std::to_string(n) + " rocks";
      core::ProgressFn progress;
      if (opt.progress) {
        progress = [&](int done, int) {
          const long total = std::min<long>(total_work, std::numeric_limits<int>::max());
          opt.progress(static_cast<int>(std::min(done_before + done, total)),
                       static_cast<int>(total), what);
        };
      }
      run.result = parallel::Simulate(scene, terrain, progress);
      done_before += run.rocks;
      run.samples = Samples(scene, run.result);
      run.values.assign(sources * kLevelCount, kNaN);
      run.counts.assign(sources, 0);
      std::vector<double> scratch;
      for (std::size_t src = 0; src < sources; ++src)
        SourceQuantiles(run.samples.values[src], {}, &scratch, &run.values[src * kLevelCount],
                        &run.counts[src]);
      // One bootstrap stream per rock count: the N_c series of a count
      // resample the same rocks (paired differences, equal errors for equal runs).
      const std::size_t count_index = runs.size() / ncs.size();
      run.replicates = BootstrapReplicates(run.samples, opt.bootstrap, base.options.seed,
                                           (std::uint64_t{1} << 48) + count_index);
      runs.push_back(std::move(run));
    }
  }
  return runs;
}

// A quantity the study measures: present at the reference with enough
// values and a non-zero value.
struct Quantity {
  std::size_t index;  // source * kLevelCount + level
  std::string name;
  double scale;
};

// The quantities of the reference run `ref`; out->quantities and notes on
// those left out.
std::vector<Quantity> MeasuredQuantities(const core::Scene& base, const RunData& ref,
                                         const ConvergenceOptions& opt, ConvergenceResult* out) {
  const std::size_t sources = base.partitions.size() + 1;
  std::vector<Quantity> quantities;
  for (std::size_t src = 0; src < sources; ++src) {
    const bool runout = src + 1 == sources;
    const std::string source = runout ? "runout" : base.partitions[src].id + ".height";
    const int count = ref.counts[src];
    if (count < opt.min_values) {
      out->notes.push_back(source + ": left out, only " + std::to_string(count) +
                           (runout ? " stopped rocks" : " crossings") +
                           " in the reference run (need " + std::to_string(opt.min_values) + ")");
      continue;
    }
    for (int l = 0; l < kLevelCount; ++l) {
      const std::size_t i = src * kLevelCount + l;
      const double v = ref.values[i];
      const std::string name = source + "." + kLevelNames[l];
      if (!(std::abs(v) > 1e-9)) {
        out->notes.push_back(name +
                             ": left out, zero at the reference (no scale for a relative error)");
        continue;
      }
      quantities.push_back({i, name, std::abs(v)});
      out->quantities.push_back(name);
    }
  }
  if (quantities.empty())
    out->notes.push_back(
        "no summary quantity to measure: no partition crossings or stopped rocks "
        "enough at the reference");
  out->notes.push_back(
      "runout quantities are distances along x from each rock's release point to where it "
      "stopped (stopped rocks only); heights are rock-centre heights above the ground at each "
      "partition");
  return quantities;
}

// The errors of quantity q in `run`, against the reference `ref`, the run
// of the finest N_c with the same rocks (`finest`) and the run of the same
// N_c with the most rocks (`most`).
QuantityError ErrorOf(const Quantity& q, const RunData& run, const RunData& finest,
                      const RunData& most, const RunData& ref, const ConvergenceOptions& opt) {
  QuantityError e;
  e.name = q.name;
  e.value = run.values[q.index];
  e.count = run.counts[q.index / kLevelCount];
  const double fine = finest.values[q.index];
  const double hw = HalfWidth(run.replicates[q.index], opt.confidence);
  std::vector<double> diff(run.replicates[q.index].size());
  for (std::size_t b = 0; b < diff.size(); ++b)
    diff[b] = run.replicates[q.index][b] - finest.replicates[q.index][b];
  const double diff_hw = HalfWidth(diff, opt.confidence);
  e.total_error = std::isnan(e.value) ? kInf : std::abs(e.value - ref.values[q.index]) / q.scale;
  e.discretisation_error =
      std::isnan(e.value) || std::isnan(fine) ? kInf : std::abs(e.value - fine) / q.scale;
  e.mc_error = e.count < opt.min_values || std::isnan(hw) ? kInf : hw / q.scale;
  e.discretisation_noise = &run == &finest                                  ? 0.0
                           : e.count < opt.min_values || std::isnan(diff_hw) ? kInf
                                                                            : diff_hw / q.scale;
  const double most_value = most.values[q.index];
  const double discretisation =
      std::isnan(most_value) ? kInf : std::abs(most_value - ref.values[q.index]) / q.scale;
  e.estimate = discretisation + e.mc_error;
  return e;
}

// The reducer: one row of the result from its run (see ErrorOf).
ConvergenceRow RowOf(const RunData& run, const RunData& finest, const RunData& most,
                     const RunData& ref, const std::vector<Quantity>& quantities,
                     const ConvergenceOptions& opt) {
  ConvergenceRow row;
  row.steps_per_contact = run.steps_per_contact;
  row.rocks = run.rocks;
  row.figures = run.result.figures;
  row.wall_seconds = run.result.wall_seconds;
  row.stopped = run.result.count(core::Outcome::kStopped);
  row.left = run.result.count(core::Outcome::kLeft);
  row.timeout = run.result.count(core::Outcome::kTimeout);
  for (const Quantity& q : quantities) {
    const QuantityError e = ErrorOf(q, run, finest, most, ref, opt);
    row.max_total_error = std::max(row.max_total_error, e.total_error);
    row.max_mc_error = std::max(row.max_mc_error, e.mc_error);
    row.max_discretisation_error = std::max(row.max_discretisation_error, e.discretisation_error);
    row.max_discretisation_noise = std::max(row.max_discretisation_noise, e.discretisation_noise);
    row.max_estimate = std::max(row.max_estimate, e.estimate);
    row.quantities.push_back(e);
  }
  if (quantities.empty()) row.max_estimate = kInf;
  row.meets_target = row.max_estimate <= opt.target;
  return row;
}

// out->recommended (the cheapest row within the target) and the sentence
// that says it, or why there is none.
void Recommend(const ConvergenceOptions& opt, ConvergenceResult* out) {
  for (std::size_t k = 0; k < out->rows.size(); ++k) {
    const ConvergenceRow& row = out->rows[k];
    if (row.meets_target &&
        (out->recommended < 0 ||
         row.wall_seconds < out->rows[static_cast<std::size_t>(out->recommended)].wall_seconds))
      out->recommended = static_cast<int>(k);
  }
  const ConvergenceRow& reference = out->rows[static_cast<std::size_t>(out->reference)];
  std::ostringstream sentence;
  if (out->recommended >= 0) {
    const ConvergenceRow& r = out->rows[static_cast<std::size_t>(out->recommended)];
    sentence << "N_c = " << r.steps_per_contact << " with " << r.rocks << " rocks: error estimate "
             << Percent(r.max_estimate) << " <= target " << Percent(opt.target) << " in "
             << Num(r.wall_seconds, "%.3g")
             << " s (the reference, N_c = " << reference.steps_per_contact << " with "
             << reference.rocks << " rocks, took " << Num(reference.wall_seconds, "%.3g") << " s)";
  } else {
    int best = -1;
    for (std::size_t k = 0; k < out->rows.size(); ++k)
      if (best < 0 ||
          out->rows[k].max_estimate < out->rows[static_cast<std::size_t>(best)].max_estimate)
        best = static_cast<int>(k);
    const ConvergenceRow& b = out->rows[static_cast<std::size_t>(best)];
    sentence << "none: no setting's error estimate is within the target " << Percent(opt.target);
    if (std::isfinite(b.max_estimate))
      sentence << " (smallest " << Percent(b.max_estimate) << " at N_c = " << b.steps_per_contact
               << " with " << b.rocks << " rocks)";
    // The reference's error is all Monte Carlo; it falls as 1 / sqrt(rocks).
    if (std::isfinite(reference.max_mc_error) && reference.max_mc_error > 0) {
      const double ratio = reference.max_mc_error / opt.target;
      sentence << "; the Monte Carlo error alone would reach the target at about "
               << Num(std::ceil(reference.rocks * ratio * ratio / 100.0) * 100.0, "%.0f")
               << " rocks (if it falls as 1/sqrt(rocks))";
    }
  }
  out->recommendation = sentence.str();
}

}  // namespace

ConvergenceResult RunConvergence(const core::Scene& site, const ConvergenceOptions& opt) {
  std::string error;
  if (!opt.IsValid(&error)) throw std::invalid_argument(error);
  const ConvergenceGrid grid = MakeGrid(opt);

  core::Scene base = site;
  if (opt.seed) base.options.seed = *opt.seed;
  base.options.threads = opt.threads;
  base.options.record = core::RecordOptions{};
  base.options.record.partitions = !base.partitions.empty();
  base.options.record.energy_check = false;  // the stability study's business
  const core::Terrain terrain = core::BuildTerrain(base);

  ConvergenceResult out;
  out.site = site.name;
  out.target = opt.target;
  out.bootstrap = opt.bootstrap;
  out.confidence = opt.confidence;
  out.seed = base.options.seed;
  out.threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();

  const std::vector<RunData> runs = RunConvergenceGrid(base, terrain, grid, opt);
  auto run_at = [&](std::size_t count_index, std::size_t nc_index) -> const RunData& {
    return runs[grid.index(count_index, nc_index)];
  };
  const std::size_t last_nc = grid.ncs.size() - 1, last_count = grid.counts.size() - 1;
  const RunData& ref = run_at(last_count, last_nc);
  const std::vector<Quantity> quantities = MeasuredQuantities(base, ref, opt, &out);

  // Rows in N_c order, then rock count.
  for (std::size_t ni = 0; ni < grid.ncs.size(); ++ni) {
    for (std::size_t ci = 0; ci < grid.counts.size(); ++ci) {
      const RunData& run = run_at(ci, ni);
      // The discretisation error of this N_c does not depend on the rock
      // count: the estimate takes it where it is best resolved, at the most rocks.
      if (&run == &ref) out.reference = static_cast<int>(out.rows.size());
      out.rows.push_back(
          RowOf(run, run_at(ci, last_nc), run_at(last_count, ni), ref, quantities, opt));
    }
  }
  Recommend(opt, &out);
  return out;
}

std::string ConvergenceReport(const ConvergenceResult& result) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line, "%6s %7s %9s %9s %7s %9s %9s %9s %9s %9s %9s  %s\n", "N_c",
                "rocks", "dt_min_s", "dt_max_s", "shrunk", "wall_s", "total", "discr", "d.noise",
                "mc", "estimate", "");
  out << line;
  for (std::size_t k = 0; k < result.rows.size(); ++k) {
    const ConvergenceRow& r = result.rows[k];
    std::string mark = static_cast<int>(k) == result.reference ? "reference" : "";
    if (static_cast<int>(k) == result.recommended)
      mark += mark.empty() ? "recommended" : ", recommended";
    std::snprintf(line, sizeof line, "%6d %7d %9.3g %9.3g %7d %9.3g %9s %9s %9s %9s %9s  %s\n",
                  r.steps_per_contact, r.rocks, r.figures.dt_min, r.figures.dt_max,
                  r.figures.dt_shrunk, r.wall_seconds, Percent(r.max_total_error).c_str(),
                  Percent(r.max_discretisation_error).c_str(),
                  Percent(r.max_discretisation_noise).c_str(), Percent(r.max_mc_error).c_str(),
                  Percent(r.max_estimate).c_str(), mark.c_str());
    out << line;
  }
  for (const auto& note : result.notes) out << "note: " << note << '\n';
  out << "recommendation: " << result.recommendation << '\n';
  return out.str();
}

}  // namespace rockcal::calibrate
