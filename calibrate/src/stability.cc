// The stability suite of `rockcal study stability` (study.h): the site's
// scene and its stiff and extreme variants, each run and judged against the
// engine's limits.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/calibrate/study.h"
#include "rockcal/core/name_table.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/random.h"
#include "rockcal/core/rock_shape.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"
#include "rockcal/parallel/parallel.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

using text::Num;
using text::Percent;

using core::kPi;

// ---- Small helpers -------------------------------------------------------------

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
  return {
      "every material hardness 0: restitution at its lower clamp, softest friction "
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
  return {std::string("rocks of 1 cm and of 10 m (") + core::ShapeToString(small.shape) +
              ", 9 small to 1 huge) released together from the first group's release",
          s};
}

CaseScene CliffCase(const core::Scene& base, const StabilityOptions&) {
  return {
      "synthetic strip: 30-degree approach, a 30 m drop between two neighbouring nodes "
      "(the steepest a height grid holds), flat foot; site's hardest and softest materials",
      CliffScene(base, true)};
}

CaseScene FaceCase(const core::Scene& base, const StabilityOptions&) {
  return {
      "synthetic strip: 30-degree approach, a 30 m face at 80 degrees (no overhang), flat "
      "foot; site's hardest and softest materials",
      CliffScene(base, false)};
}

CaseScene FlatCase(const core::Scene& base, const StabilityOptions& opt) {
  core::Scene s = FlatScene(base, opt.max_time);
  const core::Material& m = s.materials[static_cast<std::size_t>(s.grid.material.front())];
  std::string description =
      "synthetic flat of " + Num((s.grid.nx - 1) * base.grid.spacing, "%.0f") + " m of material '" +
      m.id + "' (the site's softest" + (m.roughness_m > 0 ? " rough" : ", smooth") +
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
  return {
      "released straight down at 50 m/s onto the hardest material of the suite (hardness 1, "
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
  const double site_dt = core::SmallestContactStep(base);
  std::vector<StabilityVariant> out;
  for (const CaseInfo& info : kCases) {
    const bool wanted = opt.cases.empty() ||
                        std::find(opt.cases.begin(), opt.cases.end(), info.id) != opt.cases.end();
    if (!wanted) continue;
    CaseScene c = info.make(base, opt);
    const double dt = core::SmallestContactStep(c.scene);
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

}  // namespace rockcal::calibrate
