#include "rockcal/calibrate/campaign.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/material_field.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::calibrate {
namespace {

namespace fs = std::filesystem;
using core::FormatNumber;

std::string Interval(double lower, double upper) {
  return "[" + FormatNumber(lower) + ", " + FormatNumber(upper) + "]";
}

// A file named at `node`, relative to the campaign file's folder; a missing
// one is an InputError at the node.
std::string ResolveFile(const sites::JsonNode& node, const fs::path& dir, const char* what) {
  const std::string name = node.String();
  const fs::path p = fs::path(name).is_absolute() ? fs::path(name) : dir / name;
  std::error_code ec;
  if (!fs::exists(p, ec))
    node.Fail(std::string("no such file: ") + p.string() + "; expected " + what +
              " (relative to the campaign file)");
  const std::string problem = sites::InputFileProblem(p.string(), what);
  if (!problem.empty()) node.Fail(problem);
  return p.string();
}

// Rocks per evaluation of a site.
int SiteRocks(const CampaignSite& site, const CalibrationOptions& options) {
  return site.rocks > 0 ? site.rocks : options.rocks;
}

}  // namespace

// ---- the campaign file -------------------------------------------------------

Campaign LoadCampaign(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(path, "no such file; expected a campaign file (JSON listing the sites)");
  const nlohmann::json json = sites::ReadJsonFile(path);
  const sites::JsonNode root(&json, path, "$");
  if (!root.is_object()) root.Fail("expected a JSON object (a campaign file)");
  root.Keys({"name", "units", "sites", "shared", "offsets"});
  Campaign c;
  c.path = path;
  c.name = root.Has("name") ? root.Get("name").String() : fs::path(path).stem().string();
  c.units = sites::ReadUnits(root.Get("units"));
  c.inputs.push_back(path);
  const fs::path dir = fs::path(path).parent_path();
  const std::vector<sites::JsonNode> list = root.Get("sites").Array(1);
  for (const sites::JsonNode& node : list) {
    if (!node.is_object()) node.Fail("expected an object {\"site\": ..., \"observations\": ...}");
    node.Keys({"site", "observations", "name", "rocks", "weight"});
    CampaignSite s;
    s.site = sites::LoadSite(ResolveFile(node.Get("site"), dir, "a site file"));
    const std::string obs = ResolveFile(node.Get("observations"), dir, "an observations file");
    s.observations = observations::LoadObservations(obs, s.site.scene);
    s.name = node.Has("name") ? node.Get("name").String() : s.site.scene.name;
    if (s.name.empty()) node.Fail("the site has no name: give the campaign's site a \"name\"");
    for (const CampaignSite& other : c.sites)
      if (other.name == s.name)
        (node.Has("name") ? node.Get("name") : node)
            .Fail("two sites named '" + s.name +
                  "': give each site of the campaign a unique \"name\"");
    if (node.Has("rocks"))
      s.rocks = static_cast<int>(node.Get("rocks").Integer(1, core::kMaxRocks));
    if (node.Has("weight")) s.weight = node.Get("weight").Positive();
    for (const std::string& f :
         s.site.inputs.empty() ? std::vector<std::string>{s.site.path} : s.site.inputs)
      c.inputs.push_back(f);
    for (const std::string& f :
         s.observations.inputs.empty() ? std::vector<std::string>{obs} : s.observations.inputs)
      c.inputs.push_back(f);
    c.sites.push_back(std::move(s));
  }
  if (const auto shared = root.Find("shared"))
    for (const sites::JsonNode& name : shared->Array(1)) {
      const std::string cls = name.String();
      if (std::find(c.shared.begin(), c.shared.end(), cls) != c.shared.end())
        name.Fail("class '" + cls + "' listed twice");
      c.shared.push_back(cls);
    }
  if (const auto offsets = root.Find("offsets"))
    for (const sites::JsonNode& node : offsets->Array(1)) {
      if (!node.is_object())
        node.Fail("expected an object {\"class\": ..., \"parameter\": ..., \"sigma\": ...}");
      node.Keys({"class", "parameter", "sigma"});
      OffsetPrior o;
      o.class_name = node.Get("class").String();
      const sites::JsonNode parameter = node.Get("parameter");
      o.parameter = parameter.String();
      const core::MaterialFieldInfo* field = core::FindMaterialField(o.parameter);
      if (!field) parameter.Fail("unknown parameter (allowed: " + core::MaterialFieldNames() + ")");
      o.sigma = node.Get("sigma").Positive();
      o.sigma = sites::FieldToSI(o.sigma, field->unit, c.units);
      for (const OffsetPrior& other : c.offsets)
        if (other.class_name == o.class_name && other.parameter == o.parameter)
          node.Fail("a second offset of class '" + o.class_name + "' " + o.parameter);
      c.offsets.push_back(o);
    }
  JointSpace{c};  // its errors now, before anything runs
  return c;
}

// ---- the joint space ----------------------------------------------------------

// A joint value: (site, class, kind); the site is empty for a shared class.
struct JointSpace::Builder {
  using Key = std::tuple<std::string, std::string, ParameterKind>;
  std::string where;  // the campaign file, for the errors
  std::map<Key, int> index;
  std::vector<Parameter> parameters;
  // Who contributed each value's bounds: "site 'a' material 'talus' [0.1, 0.6]".
  std::vector<std::vector<std::string>> sources;
  std::vector<std::pair<double, double>> first_bounds;
  // The sphere spacing of the site that first gave each value.
  std::vector<std::pair<std::string, double>> first_spacing;
};

namespace {

bool SharedClass(const Campaign& campaign, const std::string& cls) {
  return campaign.shared.empty() ||
         std::find(campaign.shared.begin(), campaign.shared.end(), cls) != campaign.shared.end();
}

}  // namespace

JointSpace::JointSpace(const Campaign& campaign) {
  Builder b;
  b.where = campaign.path.empty() ? std::string("campaign") : campaign.path;
  AddSites(campaign, &b);
  CheckBounds(campaign, b);
  AddOffsets(campaign, &b);
  space_ = ParameterSpace(std::move(b.parameters));
}

// Each site's parameters onto the joint values: a shared class's values
// once for all sites (their bounds intersected), another's once per site.
void JointSpace::AddSites(const Campaign& campaign, Builder* b) {
  for (std::size_t s = 0; s < campaign.sites.size(); ++s) {
    const CampaignSite& site = campaign.sites[s];
    site_spaces_.push_back(ParameterSpace::FromSite(site.site));
    std::vector<Term> terms;
    for (const Parameter& p : site_spaces_.back().parameters()) {
      const std::string& cls = p.class_name();
      const Builder::Key key{SharedClass(campaign, cls) ? std::string() : site.name, cls, p.kind};
      auto it = b->index.find(key);
      if (it == b->index.end()) {
        Parameter q;
        q.material = std::get<0>(key).empty() ? cls : site.name + ":" + cls;
        q.material_class = cls;
        q.site = std::get<0>(key);
        q.kind = p.kind;
        q.lower = p.lower;
        q.upper = p.upper;
        q.material_index = -1;
        it = b->index.emplace(key, static_cast<int>(b->parameters.size())).first;
        b->parameters.push_back(q);
        b->sources.emplace_back();
        b->first_bounds.emplace_back(p.lower, p.upper);
        b->first_spacing.emplace_back(site.name, site.site.scene.grid.spacing);
      } else {
        Parameter& q = b->parameters[static_cast<std::size_t>(it->second)];
        const auto& [first_site, spacing] = b->first_spacing[static_cast<std::size_t>(it->second)];
        const double here = site.site.scene.grid.spacing;
        if (p.kind == ParameterKind::kRoughness && std::abs(here - spacing) > 1e-9 * spacing)
          throw InputError(b->where, "class '" + cls +
                                         "' roughness is shared by sites whose virtual "
                                         "spheres are spaced differently ('" +
                                         first_site + "' " + FormatNumber(spacing) + " m, '" +
                                         site.name + "' " + FormatNumber(here) +
                                         " m); a roughness means one ground only "
                                         "at one sphere spacing: expected one "
                                         "surface.sphere_spacing for these sites, or the class "
                                         "left out of \"shared\"");
        q.lower = std::max(q.lower, p.lower);
        q.upper = std::min(q.upper, p.upper);
      }
      b->sources[static_cast<std::size_t>(it->second)].push_back(
          "site '" + site.name + "' material '" + p.material + "' " + Interval(p.lower, p.upper));
      terms.push_back({it->second, kNoOffset});
    }
    sites_.push_back(std::move(terms));
  }
}

// Every joint value has a common interval (narrowed ones noted), and every
// shared class is calibrated by some site.
void JointSpace::CheckBounds(const Campaign& campaign, const Builder& b) {
  for (std::size_t k = 0; k < b.parameters.size(); ++k) {
    const Parameter& q = b.parameters[k];
    std::string from;
    for (const std::string& s : b.sources[k]) from += (from.empty() ? "" : ", ") + s;
    if (!(q.lower < q.upper))
      throw InputError(b.where, "class '" + q.material_class + "' " + q.name() +
                                    ": the bounds of the sites sharing it have no common "
                                    "interval (" + from +
                                    "); expected overlapping \"calibrate\" bounds, or leave "
                                    "the class out of \"shared\"");
    if (q.lower != b.first_bounds[k].first || q.upper != b.first_bounds[k].second)
      notes_.push_back("class " + q.material_class + " " + q.name() + ": bounds " +
                       Interval(q.lower, q.upper) + ", the intersection of " + from);
  }
  for (const std::string& cls : campaign.shared) {
    bool found = false;
    for (const Parameter& q : b.parameters) found = found || q.material_class == cls;
    if (!found)
      throw InputError(b.where + ": $.shared",
                       "class '" + cls +
                           "': no site calibrates a material of this class; "
                           "expected a class of the sites' materials with \"calibrate\" bounds");
  }
}

// Each offset prior: a parameter per site calibrating the shared value but
// the last, whose offset is minus their sum (the offsets sum to zero).
void JointSpace::AddOffsets(const Campaign& campaign, Builder* b) {
  for (std::size_t o = 0; o < campaign.offsets.size(); ++o) {
    const OffsetPrior& prior = campaign.offsets[o];
    const std::string path = b->where + ": $.offsets[" + std::to_string(o) + "]";
    const core::MaterialFieldInfo* field = core::FindMaterialField(prior.parameter);
    if (!field)
      throw InputError(path + ".parameter",
                       "'" + prior.parameter +
                           "': unknown parameter (allowed: " + core::MaterialFieldNames() + ")");
    if (!(prior.sigma > 0))
      throw InputError(path + ".sigma", FormatNumber(prior.sigma) + ": expected a sigma > 0");
    if (!SharedClass(campaign, prior.class_name))
      throw InputError(path + ".class", "class '" + prior.class_name +
                                            "' is not shared (not in \"shared\"): an offset is a "
                                            "site's departure from a shared value");
    const auto it = b->index.find(Builder::Key{std::string(), prior.class_name, field->field});
    if (it == b->index.end())
      throw InputError(path, "class '" + prior.class_name + "' " + prior.parameter +
                                 ": no site calibrates it; expected a class and parameter of the "
                                 "sites' \"calibrate\" bounds");
    // The sites calibrating it, in order.
    std::vector<std::size_t> with;
    for (std::size_t s = 0; s < campaign.sites.size(); ++s)
      for (const Term& t : sites_[s])
        if (t.value == it->second) {
          with.push_back(s);
          break;
        }
    std::vector<int> free;
    for (std::size_t w = 0; w + 1 < with.size(); ++w) {
      Parameter q = b->parameters[static_cast<std::size_t>(it->second)];
      q.site = campaign.sites[with[w]].name;
      q.material = q.site + ":" + prior.class_name;
      q.offset = true;
      q.lower = -3.0 * prior.sigma;
      q.upper = 3.0 * prior.sigma;
      free.push_back(static_cast<int>(b->parameters.size()));
      b->parameters.push_back(q);
    }
    for (std::size_t w = 0; w < with.size() && with.size() > 1; ++w) {
      Offset offset;
      offset.sigma = prior.sigma;
      offset.id.kind = observations::ObservationKind::kPrior;
      offset.id.index = static_cast<int>(offsets_.size());
      offset.id.name = prior.class_name + "." + prior.parameter;
      offset.id.statistic = observations::Statistic::kOffset;
      offset.id.site = campaign.sites[with[w]].name;
      if (w + 1 < with.size())
        offset.terms = {{free[w], 1.0}};
      else
        for (int f : free) offset.terms.emplace_back(f, -1.0);
      for (Term& t : sites_[with[w]])
        if (t.value == it->second) t.offset = offsets_.size();
      offsets_.push_back(std::move(offset));
    }
  }
}

double JointSpace::Offset::Value(const std::vector<double>& joint) const {
  double v = 0.0;
  for (const auto& [index, sign] : terms) v += sign * joint[static_cast<std::size_t>(index)];
  return v;
}

const ParameterSpace& JointSpace::site_space(int site) const {
  return site_spaces_[static_cast<std::size_t>(site)];
}

std::vector<double> JointSpace::SiteValues(int site, const std::vector<double>& joint) const {
  const std::vector<Term>& terms = sites_[static_cast<std::size_t>(site)];
  const std::vector<Parameter>& own = site_space(site).parameters();
  std::vector<double> x(terms.size());
  for (std::size_t k = 0; k < terms.size(); ++k) {
    double v = joint[static_cast<std::size_t>(terms[k].value)];
    if (terms[k].offset != kNoOffset) v += offsets_[terms[k].offset].Value(joint);
    x[k] = std::clamp(v, own[k].lower, own[k].upper);
  }
  return x;
}

std::vector<double> JointSpace::FromSiteValues(
    const std::vector<std::vector<double>>& site_values) const {
  const std::size_t n = static_cast<std::size_t>(space_.size());
  std::vector<double> sum(n, 0.0);
  std::vector<int> count(n, 0);
  for (std::size_t s = 0; s < sites_.size(); ++s)
    for (std::size_t k = 0; k < sites_[s].size(); ++k) {
      const std::size_t j = static_cast<std::size_t>(sites_[s][k].value);
      sum[j] += site_values[s][k];
      ++count[j];
    }
  std::vector<double> joint(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const Parameter& p = space_.parameters()[j];
    if (!p.offset && count[j] > 0) joint[j] = std::clamp(sum[j] / count[j], p.lower, p.upper);
  }
  return joint;
}

std::vector<observations::Residual> JointSpace::PriorResiduals(
    const std::vector<double>& joint) const {
  std::vector<observations::Residual> out;
  for (const Offset& o : offsets_) {
    observations::Residual r;
    r.id = o.id;
    r.simulated = o.Value(joint);
    r.observed = 0.0;
    r.sigma = o.sigma;
    r.value = r.simulated / o.sigma;
    out.push_back(r);
  }
  return out;
}

// ---- the joint objective ---------------------------------------------------------

CampaignObjective::CampaignObjective(const Campaign& campaign, std::vector<core::Scene> scenes,
                                     const observations::MisfitOptions& misfit)
    : joint_(campaign) {
  for (std::size_t s = 0; s < campaign.sites.size(); ++s) {
    const CampaignSite& site = campaign.sites[s];
    names_.push_back(site.name);
    weights_.push_back(site.weight);
    sites_.push_back(std::make_unique<Objective>(
        std::move(scenes[s]), joint_.site_space(static_cast<int>(s)), site.observations, misfit));
    residual_count_ += sites_.back()->residual_count();
  }
  residual_count_ += joint_.prior_count();
}

std::vector<observations::Misfit> CampaignObjective::EvaluateSites(
    const std::vector<std::pair<int, std::vector<double>>>& tasks,
    const std::function<void(int, const observations::Misfit&)>& done) const {
  return MapMisfits(
      static_cast<int>(tasks.size()),
      [&](int k) {
        const auto& [s, x] = tasks[static_cast<std::size_t>(k)];
        return site(s).Evaluate(x);
      },
      done);
}

observations::Misfit CampaignObjective::Join(const std::vector<double>& joint,
                                             const std::vector<observations::Misfit>& sites) const {
  observations::Misfit out = JoinSites(sites);
  for (observations::Residual& r : joint_.PriorResiduals(joint)) {
    out.value += 0.5 * r.value * r.value;
    out.residuals.push_back(std::move(r));
  }
  return out;
}

observations::Misfit CampaignObjective::JoinSites(
    const std::vector<observations::Misfit>& sites) const {
  observations::Misfit out;
  out.value = 0.0;
  for (std::size_t s = 0; s < sites.size(); ++s) {
    const observations::Misfit& m = sites[s];
    const double scale = std::sqrt(weights_[s]);
    out.value += weights_[s] * m.value;
    if (m.penalised) {
      out.penalised = true;
      out.message += (out.message.empty() ? "" : "; ") + names_[s] + ": " + m.message;
    }
    for (observations::Residual r : m.residuals) {
      r.id.site = names_[s];
      r.value *= scale;
      out.residuals.push_back(std::move(r));
    }
  }
  return out;
}

std::vector<std::pair<int, std::vector<double>>> CampaignObjective::SiteTasks(
    const std::vector<double>& joint) const {
  std::vector<std::pair<int, std::vector<double>>> tasks;
  for (int s = 0; s < site_count(); ++s) tasks.emplace_back(s, joint_.SiteValues(s, joint));
  return tasks;
}

observations::Misfit CampaignObjective::Evaluate(const std::vector<double>& physical) const {
  return Join(physical, EvaluateSites(SiteTasks(physical)));
}

observations::Misfit CampaignObjective::EvaluateSitesAt(const std::vector<double>& joint) const {
  return JoinSites(EvaluateSites(SiteTasks(joint)));
}

std::vector<observations::Misfit> CampaignObjective::EvaluateAll(
    const std::vector<std::vector<double>>& points,
    const std::function<void(int, const observations::Misfit&)>& done) const {
  const std::size_t n = static_cast<std::size_t>(site_count());
  std::vector<std::pair<int, std::vector<double>>> tasks;
  for (const std::vector<double>& x : points)
    for (auto& task : SiteTasks(x)) tasks.push_back(std::move(task));
  // `done` per point once all its sites have finished (rank 0).
  std::vector<std::vector<observations::Misfit>> partial(points.size());
  std::vector<std::size_t> finished(points.size(), 0);
  const std::vector<observations::Misfit> misfits =
      EvaluateSites(tasks, [&](int k, const observations::Misfit& m) {
        if (!done) return;
        const std::size_t point = static_cast<std::size_t>(k) / n;
        std::vector<observations::Misfit>& parts = partial[point];
        if (parts.empty()) parts.resize(n);
        parts[static_cast<std::size_t>(k) % n] = m;
        if (++finished[point] == n) {
          done(static_cast<int>(point), Join(points[point], parts));
          parts.clear();
        }
      });
  std::vector<observations::Misfit> out;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const std::vector<observations::Misfit> sites(
        misfits.begin() + static_cast<std::ptrdiff_t>(p * n),
        misfits.begin() + static_cast<std::ptrdiff_t>((p + 1) * n));
    out.push_back(Join(points[p], sites));
  }
  return out;
}

// ---- the run ---------------------------------------------------------------------

std::string CampaignSummary::BriefReport() const {
  std::ostringstream out;
  out << name << ": " << sites.size() << " sites, " << calibration.space.size()
      << " joint parameters; " << calibration.BriefReport();
  return out.str();
}

Fingerprint CampaignFingerprint(const Campaign& campaign, const JointSpace& joint,
                                const CalibrationOptions& options) {
  Fingerprint f;
  if (!campaign.path.empty()) f.Add("campaign file", HashFile(campaign.path));
  std::ostringstream parameters;
  parameters.precision(17);
  for (const Parameter& p : joint.space().parameters())
    parameters << p.label() << " [" << p.lower << ", " << p.upper << "] ";
  f.Add("joint parameters", parameters.str());
  for (std::size_t s = 0; s < campaign.sites.size(); ++s) {
    const CampaignSite& site = campaign.sites[s];
    CalibrationOptions o = options;
    o.rocks = SiteRocks(site, options);
    const ParameterSpace& space = joint.site_space(static_cast<int>(s));
    for (const auto& [what, value] :
         CalibrationFingerprint(site.site, site.observations, o, space).parts)
      f.Add(site.name + ": " + what, value);
    std::ostringstream weight;
    weight.precision(17);
    weight << site.weight;
    f.Add(site.name + ": weight", weight.str());
  }
  return f;
}

namespace {

// CheckCampaign's checks but the joint space's (which the run's objective
// builds, throwing the same errors).
void CheckCampaignOptions(const Campaign& campaign, const CalibrationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("calibration options", error);
  const char* unsupported = options.reach_points > 0    ? "a reach check (reach_points)"
                            : options.refine_factor > 1 ? "a refining stage (refine_factor)"
                            : options.race_points > 0   ? "a race (race_points)"
                            : options.noise_seeds > 0   ? "noise seeds (noise_seeds)"
                            : !options.observations_subset.empty()
                                ? "a subset of the observations (observations_subset)"
                                : nullptr;
  if (unsupported)
    throw InputError("calibration options", std::string("a campaign takes no ") + unsupported +
                                                "; calibrate the sites alone for it");
  if (campaign.sites.empty())
    throw InputError(campaign.path.empty() ? std::string("campaign") : campaign.path,
                     "no sites; expected at least one in \"sites\"");
}

}  // namespace

void CheckCampaign(const Campaign& campaign, const CalibrationOptions& options) {
  CheckCampaignOptions(campaign, options);
  JointSpace{campaign};
}

void CheckCampaignResume(const Campaign& campaign, const CalibrationOptions& options) {
  if (!options.resume || options.log_path.empty()) return;
  CheckCampaignOptions(campaign, options);
  const JointSpace joint(campaign);
  // The rocks and seed as RunCampaign takes them from its scenes.
  int rocks = 0;
  std::optional<std::uint64_t> seed;
  for (const CampaignSite& site : campaign.sites) {
    const core::Scene scene =
        RunScene(site.site, SiteRocks(site, options), options.seed, options.threads);
    rocks += scene.total_rocks();
    if (!seed) seed = scene.options.seed;
  }
  EvaluationLog::Check(options.log_path, joint.space(), *seed, rocks,
                       CampaignFingerprint(campaign, joint, options));
}

namespace {

// The predictive draws of a campaign: every site simulated anew at the
// draw's seed with its rocks, its residuals joined without the priors.
PredictiveDraw CampaignDraw(const Campaign& campaign, const CalibrationOptions& options) {
  return [&campaign, &options](const std::vector<double>& joint, std::uint64_t seed) {
    std::vector<core::Scene> scenes;
    for (const CampaignSite& site : campaign.sites)
      scenes.push_back(RunScene(site.site, SiteRocks(site, options), seed, options.threads));
    PredictiveOutcome out;
    out.misfit =
        CampaignObjective(campaign, std::move(scenes), options.misfit).EvaluateSitesAt(joint);
    return out;
  };
}

// The posterior of each site's values (the joint samples mapped) with the
// bands of its own statistics, and of each offset.
void SplitPosterior(const JointSpace& joint, double undetermined_share, CampaignSummary* summary) {
  const PosteriorResult& post = *summary->calibration.posterior;
  for (int s = 0; s < joint.site_count(); ++s) {
    CampaignSiteFit& fit = summary->sites[static_cast<std::size_t>(s)];
    PosteriorResult own = MapPosterior(
        post, fit.space, [&](const std::vector<double>& x) { return joint.SiteValues(s, x); },
        undetermined_share);
    for (PredictiveBand band : post.bands)
      if (band.id.site == fit.name && band.id.kind != observations::ObservationKind::kPrior) {
        band.id.site.clear();  // named as in the site's own observations
        own.bands.push_back(std::move(band));
      }
    own.band_draws = post.band_draws;
    own.band_rocks = post.band_draws > 0 ? fit.rocks : 0;
    fit.posterior = std::move(own);
  }
  std::vector<std::vector<double>> values(static_cast<std::size_t>(joint.prior_count()));
  std::vector<observations::Residual> priors;
  for (const std::vector<double>& x : post.samples) {
    priors = joint.PriorResiduals(x);
    for (std::size_t k = 0; k < priors.size(); ++k) values[k].push_back(priors[k].simulated);
  }
  // The Gaussian prior's 5-95 % width: 2 x 1.6449 sigma.
  for (std::size_t k = 0; k < priors.size(); ++k)
    summary->offsets.push_back(
        {priors[k].id.quantity(), priors[k].sigma,
         SummariseValues(values[k], post.chains, 2.0 * 1.6448536269514722 * priors[k].sigma,
                         undetermined_share)});
}

// The posterior stage of RunCampaign (CalibrationOptions::posterior, after
// the search): the joint posterior on `objective` (the search's
// evaluations reused, the new ones appended to `log`, may be null), its
// predictive bands from draws simulating every site at seeds the search
// did not use, then each site's posterior and each offset's.
void CampaignPosterior(const Campaign& campaign, const CalibrationOptions& options,
                       const CampaignObjective& objective, EvaluationLog* log,
                       const CalibrationCallbacks& callbacks, CampaignSummary* summary) {
  CalibrationSummary& cal = summary->calibration;
  std::vector<Evaluation> reused;
  for (const MethodResult& m : cal.methods)
    reused.insert(reused.end(), m.trace.begin(), m.trace.end());
  PosteriorOptions po = *options.posterior;
  po.mcmc.seed = cal.seed;
  cal.posterior =
      SamplePosterior(objective, reused, po, log, callbacks.posterior, cal.misfit_before.residuals);
  PredictiveBands(CampaignDraw(campaign, options), cal.seed, cal.rocks, options.predictive_draws,
                  &*cal.posterior, callbacks.posterior);
  SplitPosterior(objective.joint(), po.undetermined_share, summary);
}

}  // namespace

CampaignSummary RunCampaign(const Campaign& campaign, const CalibrationOptions& options,
                            const CalibrationCallbacks& callbacks) {
  const auto start_time = std::chrono::steady_clock::now();
  CheckCampaignOptions(campaign, options);
  std::vector<core::Scene> scenes;
  int rocks = 0;
  for (const CampaignSite& site : campaign.sites) {
    scenes.push_back(RunScene(site.site, SiteRocks(site, options), options.seed, options.threads));
    rocks += scenes.back().total_rocks();
  }
  const std::uint64_t seed = scenes.front().options.seed;
  const CampaignObjective objective(campaign, scenes, options.misfit);
  const JointSpace& joint = objective.joint();
  const int n_sites = objective.site_count();
  std::vector<std::vector<double>> own_start;  // each site's own starting values
  for (int s = 0; s < n_sites; ++s)
    own_start.push_back(joint.site_space(s).Current(objective.site(s).scene()));

  CampaignSummary summary;
  summary.name = campaign.name;
  summary.path = campaign.path;
  summary.notes = joint.notes();
  summary.prior_residuals = joint.prior_count();
  CalibrationSummary& cal = summary.calibration;
  cal.site = campaign.name;
  cal.units = campaign.units;
  cal.space = joint.space();
  cal.rocks = cal.final_rocks = rocks;
  cal.seed = seed;
  cal.start = cal.search_start = joint.FromSiteValues(own_start);

  // One round over the ranks: every site at the joint start, and at its own.
  std::vector<std::pair<int, std::vector<double>>> tasks = objective.SiteTasks(cal.start);
  for (int s = 0; s < n_sites; ++s) tasks.emplace_back(s, own_start[static_cast<std::size_t>(s)]);
  std::vector<observations::Misfit> misfits = objective.EvaluateSites(tasks);
  cal.misfit_before = objective.Join(
      cal.start, std::vector<observations::Misfit>(misfits.begin(), misfits.begin() + n_sites));
  for (int s = 0; s < n_sites; ++s) {
    const CampaignSite& site = campaign.sites[static_cast<std::size_t>(s)];
    CampaignSiteFit fit;
    fit.name = site.name;
    fit.site_file = site.site.path;
    fit.weight = site.weight;
    fit.rocks = scenes[static_cast<std::size_t>(s)].total_rocks();
    fit.space = joint.site_space(s);
    fit.grid_spacing_m = site.site.scene.grid.spacing;
    fit.start = own_start[static_cast<std::size_t>(s)];
    fit.misfit_start = misfits[static_cast<std::size_t>(n_sites + s)];
    summary.sites.push_back(std::move(fit));
  }
  if (callbacks.started) callbacks.started(cal);

  std::optional<EvaluationLog> log;
  if (!options.log_path.empty())
    log.emplace(options.log_path, options.resume, joint.space(), seed, rocks,
                CampaignFingerprint(campaign, joint, options), callbacks.log_opened);
  else if (callbacks.log_opened)
    callbacks.log_opened();
  MethodOptions method_options = options.method;
  method_options.seed = seed;
  SearchMethods(objective, cal.search_start, options.methods, method_options, log ? &*log : nullptr,
                callbacks, &cal);
  MethodResult& best = cal.methods[static_cast<std::size_t>(cal.best)];
  // The uncertainty of the joint values from central differences, whatever
  // the method (ceres has it; the NLopt methods' comes from their own
  // evaluations).
  if (!best.uncertainty.computed || best.uncertainty.from_search)
    best.uncertainty = JacobianUncertaintyAt(objective, best.best, best.best_misfit);
  cal.termination = best.termination;

  tasks = objective.SiteTasks(best.best);
  misfits = objective.EvaluateSites(tasks);
  cal.misfit_after = objective.Join(best.best, misfits);
  for (int s = 0; s < n_sites; ++s) {
    CampaignSiteFit& fit = summary.sites[static_cast<std::size_t>(s)];
    fit.calibrated = tasks[static_cast<std::size_t>(s)].second;
    fit.misfit_joint = misfits[static_cast<std::size_t>(s)];
  }
  if (options.posterior)
    CampaignPosterior(campaign, options, objective, log ? &*log : nullptr, callbacks, &summary);
  cal.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return summary;
}

}  // namespace rockcal::calibrate
