// A campaign's joint objective and its run (campaign.h).
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

// Rocks per evaluation of a site.
int SiteRocks(const CampaignSite& site, const CalibrationOptions& options) {
  return site.rocks > 0 ? site.rocks : options.rocks;
}

}  // namespace

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
    out.log_scale += weights_[s] * m.log_scale;
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

Eigen::MatrixXd CampaignObjective::ResidualCorrelation(const std::vector<double>& physical,
                                                       int replicates, std::uint64_t seed) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Identity(residual_count_, residual_count_);
  Eigen::Index at = 0;
  for (int s = 0; s < site_count(); ++s) {
    const Eigen::Index n = site(s).residual_count();
    const Eigen::MatrixXd block = site(s).ResidualCorrelation(
        joint_.SiteValues(s, physical), replicates, seed + static_cast<std::uint64_t>(s));
    if (block.rows() == n) out.block(at, at, n, n) = block;
    at += n;
  }
  return out;
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
// the search): the joint posterior on `objective` (its own design: the
// search's evaluations are not reused, docs/posterior.md step 3; the new
// ones appended to `log`, may be null), its
// predictive bands from draws simulating every site at seeds the search
// did not use, then each site's posterior and each offset's.
void CampaignPosterior(const Campaign& campaign, const CalibrationOptions& options,
                       const CampaignObjective& objective, EvaluationLog* log,
                       const CalibrationCallbacks& callbacks, CampaignSummary* summary) {
  CalibrationSummary& cal = summary->calibration;
  PosteriorOptions po = *options.posterior;
  po.mcmc.seed = cal.seed;
  cal.posterior =
      SamplePosterior(objective, {}, po, log, callbacks.posterior, cal.misfit_before.residuals);
  for (const CampaignSite& s : campaign.sites)
    if (const std::string points = PointReleaseWarning(s.site.scene); !points.empty())
      cal.posterior->message +=
          (cal.posterior->message.empty() ? "" : " ") + s.name + ": " + points + ".";
  PredictiveBands(CampaignDraw(campaign, options), cal.seed, cal.rocks, po.predictive_draws,
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
