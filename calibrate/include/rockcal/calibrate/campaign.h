// Joint calibration of several sites (a campaign): materials of different
// sites that carry the same class share one value per calibrated parameter,
// optionally with a per-site offset under a Gaussian prior, and all the
// sites' observations are fitted at once. The search is Calibrate's own
// (SearchMethods over an ObjectiveFunction, with its methods, evaluation log
// and resume); only the objective differs: CampaignObjective maps the joint
// vector to each site's physical values and joins the sites' residuals.
#ifndef ROCKCAL_CALIBRATE_CAMPAIGN_H_
#define ROCKCAL_CALIBRATE_CAMPAIGN_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rockcal/calibrate/calibration.h"
#include "rockcal/calibrate/calibration_run.h"
#include "rockcal/calibrate/objective.h"
#include "rockcal/calibrate/parameter_space.h"
#include "rockcal/calibrate/posterior.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/observations/observations.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// One site of a campaign.
struct CampaignSite {
  std::string name;  // unique in the campaign ("name", or the site's own name)
  sites::Site site;
  observations::Observations observations;
  // Rocks per evaluation of this site; 0: the run's CalibrationOptions::rocks
  // (and when that is 0 too, the site's counts) [0], >= 0.
  int rocks = 0;
  // The weight of its misfit in the joint misfit (its residuals are scaled by
  // sqrt(weight)) [1], > 0.
  double weight = 1.0;
};

// A per-site offset of a shared parameter: every site calibrating
// `parameter` of class `class_name` gets a value of its own, the shared one
// plus an offset that a Gaussian prior N(0, sigma^2) pulls to 0 (a residual
// offset / sigma joins the misfit). The offsets of the S sites sum to zero:
// the first S - 1 are joint parameters, searched within +-3 sigma, the last
// is minus their sum. With one sigma for all, that is where free offsets
// under the prior have their optimum (the shared value the mean of the
// sites'), without the direction (shared value up, every offset down) that
// only the prior sees and that a Monte Carlo Jacobian loses in its noise.
// With one site, the offset is 0.
struct OffsetPrior {
  std::string class_name;
  std::string parameter;  // a core::MaterialFields() name: "hardness", "roughness", ...
  double sigma = 0.0;     // SI (roughness m, contact time s), > 0
};

struct Campaign {
  std::string path;  // the campaign file ("" for one built in memory)
  std::string name;
  sites::Units units = sites::Units::kSI;  // for the tables' display
  std::vector<CampaignSite> sites;
  std::vector<OffsetPrior> offsets;
  // The classes shared between sites; empty: every class. A class not
  // shared is calibrated per site (its parameters named "<site>:<material>").
  std::vector<std::string> shared;
  // Every file the campaign was read from: the campaign file, then each
  // site's files and observations files.
  std::vector<std::string> inputs;
};

// Reads a campaign file (the site and observations files of docs/design.md, listed in
// a JSON file; paths relative to it):
//   {"name": "...", "units": "si" | "us",
//    "sites": [{"site": "a/site.json", "observations": "a/observations.json",
//               "name": "a", "rocks": 300, "weight": 1.0}, ...],
//    "shared": ["talus", ...],
//    "offsets": [{"class": "talus", "parameter": "hardness", "sigma": 0.05}]}
// "name", "rocks", "weight", "shared" and "offsets" are optional; a
// roughness sigma is in the file's units. Throws InputError naming the file,
// the JSON path, the value and what was expected (an unknown key, a missing
// file, two sites of one name, a class or parameter no site calibrates, and
// shared bounds that leave no common interval: JointSpace's errors).
Campaign LoadCampaign(const std::string& path);

// The joint parameters of a campaign and their map to each site's
// parameters. A joint parameter is one (class, parameter) shared by the
// sites (its bounds the intersection of theirs), one per site and material
// of a class not shared, or a per-site offset (OffsetPrior). A site's value
// is its joint value plus its offset, clamped to the site's own bounds.
class JointSpace final {
 public:
  JointSpace() = default;
  // Throws InputError (where: `campaign.path`) when two sites' bounds of a
  // shared parameter have no common interval, a shared class or an offset
  // names nothing any site calibrates, or a site has nothing to calibrate.
  explicit JointSpace(const Campaign& campaign);

  const ParameterSpace& space() const { return space_; }
  int site_count() const { return static_cast<int>(sites_.size()); }
  // The site's own parameters (ParameterSpace::FromSite).
  const ParameterSpace& site_space(int site) const;
  // The site's physical values at the joint values `joint`.
  std::vector<double> SiteValues(int site, const std::vector<double>& joint) const;
  // The joint values from each site's own values: a shared parameter takes
  // the mean over the materials that share it (clamped into its bounds),
  // an offset 0.
  std::vector<double> FromSiteValues(const std::vector<std::vector<double>>& site_values) const;
  // The prior residuals, offset / sigma, one per site with an offset
  // (observation "prior", quantity "<site>:<class>.<parameter>_offset").
  std::vector<observations::Residual> PriorResiduals(const std::vector<double>& joint) const;
  int prior_count() const { return static_cast<int>(offsets_.size()); }
  // Where the shared bounds were narrowed to the sites' intersection, one
  // line each ("class talus hardness: [0.2, 0.6] (intersection of ...)").
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  static constexpr std::size_t kNoOffset = static_cast<std::size_t>(-1);
  struct Term {
    int value = -1;                  // joint index of the value
    std::size_t offset = kNoOffset;  // index into offsets_
  };
  // A site's offset: a sum of joint values with signs (+ its own parameter,
  // or - every other site's for the last site), and its prior's sigma.
  struct Offset {
    std::vector<std::pair<int, double>> terms;
    double sigma = 0.0;
    observations::ResidualId id;  // its prior residual's (a kPrior of its site)
    double Value(const std::vector<double>& joint) const;
  };
  // The constructor's work in progress, and its steps (campaign.cc): each
  // site's values joined, the joint bounds checked, the offsets added.
  struct Builder;
  void AddSites(const Campaign& campaign, Builder* b);
  void CheckBounds(const Campaign& campaign, const Builder& b);
  void AddOffsets(const Campaign& campaign, Builder* b);
  ParameterSpace space_;
  std::vector<ParameterSpace> site_spaces_;
  std::vector<std::vector<Term>> sites_;  // per site, per site parameter
  std::vector<Offset> offsets_;
  std::vector<std::string> notes_;
};

// The joint objective of a campaign: each site's Objective at its values
// (JointSpace::SiteValues), the residuals joined in site order (each site's
// scaled by sqrt(weight), its observations named "<site>: ...") and the
// prior residuals last; the misfit is half their sum of squares. Under
// mpirun the site simulations of one evaluation, and of all the points of
// EvaluateAll, are spread over the ranks as (point, site) tasks
// (parallel::Map), each simulated whole on one rank: bit-identical at any
// rank count.
class CampaignObjective final : public ObjectiveFunction {
 public:
  // `scenes` (one per site, with the run's rocks and seed) as RunScene makes
  // them.
  CampaignObjective(const Campaign& campaign, std::vector<core::Scene> scenes,
                    const observations::MisfitOptions& misfit);

  const ParameterSpace& space() const override { return joint_.space(); }
  int residual_count() const override { return residual_count_; }
  observations::Misfit Evaluate(const std::vector<double>& physical) const override;
  std::vector<observations::Misfit> EvaluateAll(
      const std::vector<std::vector<double>>& points,
      const std::function<void(int, const observations::Misfit&)>& done = nullptr) const override;
  // Block diagonal: each site's (Objective::ResidualCorrelation at its
  // values, seeded by `seed` + its index; the identity for a site that
  // cannot tell), then the identity for the prior residuals. Different sites
  // are different rocks.
  Eigen::MatrixXd ResidualCorrelation(const std::vector<double>& physical, int replicates,
                                      std::uint64_t seed) const override;

  const JointSpace& joint() const { return joint_; }
  const Objective& site(int k) const { return *sites_[static_cast<std::size_t>(k)]; }
  int site_count() const { return static_cast<int>(sites_.size()); }
  // Each task (site index, that site's physical values) evaluated on the
  // site's Objective, spread over the ranks; misfits in task order.
  std::vector<observations::Misfit> EvaluateSites(
      const std::vector<std::pair<int, std::vector<double>>>& tasks,
      const std::function<void(int, const observations::Misfit&)>& done = nullptr) const;
  // The joint misfit at `joint` from the sites' misfits there (site order).
  observations::Misfit Join(const std::vector<double>& joint,
                            const std::vector<observations::Misfit>& sites) const;
  // The sites' misfits (site order) joined without the prior residuals:
  // what the sites show, each residual's observation named "<site>: ...".
  observations::Misfit JoinSites(const std::vector<observations::Misfit>& sites) const;
  // Every site simulated at its values of `joint`, joined by JoinSites.
  observations::Misfit EvaluateSitesAt(const std::vector<double>& joint) const;
  // The task of each site (EvaluateSites) at the joint values `joint`.
  std::vector<std::pair<int, std::vector<double>>> SiteTasks(
      const std::vector<double>& joint) const;

 private:
  JointSpace joint_;
  std::vector<std::string> names_;
  std::vector<double> weights_;
  std::vector<std::unique_ptr<Objective>> sites_;
  int residual_count_ = 0;
};

// One site's fit in a campaign.
struct CampaignSiteFit {
  std::string name;
  std::string site_file;
  double weight = 1.0;
  int rocks = 0;                      // per evaluation
  ParameterSpace space;               // the site's own parameters
  std::vector<double> start;          // its own starting values (the site file's)
  std::vector<double> calibrated;     // its values at the joint calibration
  observations::Misfit misfit_start;  // at its own starting values
  observations::Misfit misfit_joint;  // at the joint calibrated values
  double grid_spacing_m = 0.0;        // its terrain's (a roughness bound's limit)
  // With CalibrationOptions::posterior: the posterior of its own values
  // (its joint value plus its offset at each joint sample, MapPosterior)
  // and its observed statistics' predictive bands (the observation named
  // as in its own observations file).
  std::optional<PosteriorResult> posterior;
};

// The posterior of one site's offset (OffsetPrior) at the joint samples.
struct OffsetPosterior {
  std::string label;   // "<site>:<class>.<parameter>_offset"
  double sigma = 0.0;  // its prior's, SI
  // width_share: the 5-95 % interval over the prior's (2 x 1.645 sigma).
  ParameterPosterior posterior;
};

struct CampaignSummary {
  std::string name;
  std::string path;
  // The joint search, as a calibration records it: the joint space, the
  // methods with their traces, the best (its uncertainty always computed,
  // JacobianUncertaintyAt), the start and the joint misfits before and
  // after; rocks are all sites' per evaluation. No scene or simulation.
  CalibrationSummary calibration;
  std::vector<CampaignSiteFit> sites;
  std::vector<std::string> notes;  // JointSpace::notes()
  int prior_residuals = 0;
  // With CalibrationOptions::posterior: calibration.posterior is the joint
  // values' (their samples, the predictive bands of every site), each
  // site's is in its CampaignSiteFit, and every site's offset's here.
  std::vector<OffsetPosterior> offsets;

  std::string BriefReport() const;
};

// What determines a campaign's evaluations: the campaign file's bytes, the
// joint parameters (`joint`, the campaign's JointSpace, built once by the
// run), and per site (parts prefixed "<site>: ") what CalibrationFingerprint
// names.
Fingerprint CampaignFingerprint(const Campaign& campaign, const JointSpace& joint,
                                const CalibrationOptions& options);

// Throws the InputError RunCampaign would throw before its first
// evaluation (invalid options, options a campaign does not take, an
// invalid joint space).
void CheckCampaign(const Campaign& campaign, const CalibrationOptions& options);

// With options.resume: reads the log RunCampaign would resume, changing
// nothing and simulating nothing, and throws the InputError the resume
// would throw (a changed input or option, a log two runs wrote).
void CheckCampaignResume(const Campaign& campaign, const CalibrationOptions& options);

// Calibrates the campaign's sites jointly: SearchMethods on a
// CampaignObjective from JointSpace::FromSiteValues of the sites' own
// values, then the uncertainty at the best values and each site's fit there
// and at its own start. Takes CalibrationOptions' methods, method options,
// misfit, rocks, seed, threads, log_path and resume, and posterior (with its
// predictive_draws): the joint posterior (SamplePosterior on the joint
// objective, the search's evaluations reused, its own appended to the log
// as for a calibration), each site's and each offset's from it, and the
// predictive bands of every site's statistics from draws simulating every
// site; a reach check, a refining stage, a race or noise seeds are an
// InputError.
CampaignSummary RunCampaign(const Campaign& campaign, const CalibrationOptions& options,
                            const CalibrationCallbacks& callbacks = {});

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_CAMPAIGN_H_
