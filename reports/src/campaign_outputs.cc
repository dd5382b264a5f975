#include "rockcal/reports/campaign_outputs.h"

#include <cctype>
#include <set>
#include <sstream>

#include "rockcal/calibrate/parameters_file.h"
#include "rockcal/core/format.h"
#include "rockcal/observations/misfit.h"
#include "rockcal/reports/calibration_outputs.h"

namespace rockcal::reports {
namespace {

using calibrate::CampaignSiteFit;
using calibrate::CampaignSummary;
using core::FormatNumber;

nlohmann::json SiteValuesJson(const CampaignSiteFit& fit) {
  nlohmann::json out = nlohmann::json::array();
  const auto& ps = fit.space.parameters();
  for (std::size_t k = 0; k < ps.size(); ++k)
    out.push_back({{"material", ps[k].material},
                   {"class", ps[k].class_name()},
                   {"name", ps[k].name()},
                   {"start", fit.start[k]},
                   {"calibrated", k < fit.calibrated.size() ? nlohmann::json(fit.calibrated[k])
                                                            : nlohmann::json(nullptr)},
                   {"lower", ps[k].lower},
                   {"upper", ps[k].upper}});
  return out;
}

// A site's posterior in summary.json: PosteriorJson less what a posterior
// mapped from the joint one has not of its own (the emulator, the design).
nlohmann::json SitePosteriorJson(const calibrate::PosteriorResult& post) {
  nlohmann::json j = calibrate::PosteriorJson(post);
  nlohmann::json out = nlohmann::json::object();
  for (const char* key :
       {"parameters", "correlation", "samples", "max_rhat", "min_ess", "predictive"})
    out[key] = j[key];
  return out;
}

nlohmann::json OffsetsJson(const std::vector<calibrate::OffsetPosterior>& offsets) {
  nlohmann::json out = nlohmann::json::array();
  for (const calibrate::OffsetPosterior& o : offsets)
    out.push_back({{"label", o.label},
                   {"sigma", o.sigma},
                   {"median", o.posterior.median},
                   {"p05", o.posterior.p05},
                   {"p95", o.posterior.p95},
                   {"width_share", o.posterior.width_share},
                   {"undetermined", o.posterior.undetermined}});
  return out;
}

std::string FolderName(const std::string& name) {
  std::string out;
  for (char c : name)
    out +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_' ? c : '_';
  if (out.empty() || out == "." || out == "..") out = "site";
  return out;
}

}  // namespace

std::vector<std::string> CampaignSiteFolders(const CampaignSummary& summary) {
  std::vector<std::string> out;
  std::set<std::string> taken;
  for (const CampaignSiteFit& fit : summary.sites) {
    const std::string base = FolderName(fit.name);
    std::string name = base;
    for (int k = 2; taken.count(name); ++k) name = base + "-" + std::to_string(k);
    taken.insert(name);
    out.push_back("sites/" + name);
  }
  return out;
}

nlohmann::json CampaignJson(const CampaignSummary& summary) {
  const CalibrationSummary& cal = summary.calibration;
  const calibrate::MethodResult& best = cal.best_method();
  nlohmann::json methods = nlohmann::json::array();
  for (const calibrate::MethodResult& m : cal.methods)
    methods.push_back({{"method", m.stage.name()},
                       {"termination", m.termination.message},
                       {"misfit", m.best_misfit},
                       {"lowest_misfit", m.lowest_misfit},
                       {"evaluations", m.evaluations},
                       {"simulated", m.simulated},
                       {"wall_seconds", m.wall_seconds}});
  const calibrate::Uncertainty& u = best.uncertainty;
  nlohmann::json sites = nlohmann::json::array();
  const std::vector<std::string> folders = CampaignSiteFolders(summary);
  for (std::size_t k = 0; k < summary.sites.size(); ++k) {
    const CampaignSiteFit& fit = summary.sites[k];
    sites.push_back({{"name", fit.name},
                     {"site_file", fit.site_file},
                     {"folder", folders[k]},
                     {"weight", fit.weight},
                     {"rocks", fit.rocks},
                     {"misfit_own_start", fit.misfit_start.value},
                     {"misfit_joint", fit.misfit_joint.value},
                     {"fit_joint", observations::AssessFit(fit.misfit_joint).Sentence()},
                     {"parameters", SiteValuesJson(fit)}});
    if (fit.posterior) sites.back()["posterior"] = SitePosteriorJson(*fit.posterior);
  }
  nlohmann::json names = nlohmann::json::array();
  for (const auto& p : cal.space.parameters()) names.push_back(p.label());
  nlohmann::json out = {{"campaign", summary.name},
                        {"file", summary.path},
                        {"method", best.stage.name()},
                        {"termination", best.termination.message},
                        {"evaluations", best.evaluations},
                        {"wall_seconds", cal.wall_seconds},
                        {"rocks_per_evaluation", cal.rocks},
                        {"seed", cal.seed},
                        {"misfit_before", cal.misfit_before.value},
                        {"misfit_after", cal.misfit_after.value},
                        {"prior_residuals", summary.prior_residuals},
                        {"parameter_names", names},
                        {"start", cal.start},
                        {"calibrated", best.best},
                        {"parameters", calibrate::ParameterListJson(calibrate::CalibratedSiteOf(cal))},
                        {"uncertainty",
                         {{"computed", u.computed},
                          {"rank_deficient", u.rank_deficient},
                          {"message", u.message},
                          {"std_error", u.std_error},
                          {"correlation", u.correlation},
                          {"singular_values", u.singular_values}}},
                        {"notes", summary.notes},
                        {"sites", sites},
                        {"methods", methods}};
  if (cal.posterior) {
    out["posterior"] = calibrate::PosteriorJson(*cal.posterior);
    out["posterior"]["offsets"] = OffsetsJson(summary.offsets);
  }
  return out;
}

std::string CampaignSitesCsv(const CampaignSummary& summary) {
  std::ostringstream out;
  const bool post = summary.calibration.posterior.has_value();
  out << "site,site_file,weight,rocks,residuals,misfit_own_start,misfit_joint,"
         "outside_2_sigma_joint"
      << (post ? ",predictive_inside,predictive_bands" : "") << "\n";
  for (const CampaignSiteFit& fit : summary.sites) {
    const observations::FitVerdict v = observations::AssessFit(fit.misfit_joint);
    out << fit.name << ',' << fit.site_file << ',' << FormatNumber(fit.weight, "%.6g") << ','
        << fit.rocks << ',' << fit.misfit_joint.residuals.size() << ','
        << FormatNumber(fit.misfit_start.value, "%.8g") << ','
        << FormatNumber(fit.misfit_joint.value, "%.8g") << ',' << v.outside.size();
    if (post && fit.posterior)
      out << ',' << fit.posterior->BandsInside() << ',' << fit.posterior->bands.size();
    out << '\n';
  }
  return out.str();
}

namespace {

// parameters.md's posterior of each site's offset.
void OffsetsMarkdown(const std::vector<calibrate::OffsetPosterior>& offsets, std::ostream& out) {
  if (offsets.empty()) return;
  out << "\n## Each site's offset: posterior (SI)\n\n"
      << "| offset | prior sigma | median | 5 % | 95 % | interval / prior's | determined by the "
         "data |\n"
      << "|---|---|---|---|---|---|---|\n";
  for (const calibrate::OffsetPosterior& o : offsets)
    out << "| " << o.label << " | " << FormatNumber(o.sigma, "%.4g") << " | "
        << FormatNumber(o.posterior.median, "%.4g") << " | "
        << FormatNumber(o.posterior.p05, "%.4g") << " | " << FormatNumber(o.posterior.p95, "%.4g")
        << " | " << FormatNumber(o.posterior.width_share, "%.2f") << " | "
        << (o.posterior.undetermined ? "no (about as wide as the prior)" : "yes") << " |\n";
  out << "\nThe interval against the prior's own 5-95 % interval (2 x 1.645 sigma): near 1, "
         "the data say little of the site's departure from the shared value.\n";
}

// parameters.md's table of each site's values, with their posterior.
void SiteValuesMarkdown(const CampaignSummary& summary, std::ostream& out) {
  const bool post = summary.calibration.posterior.has_value();
  out << "\n## Each site's values (SI)\n\n"
      << "| site | material | class | parameter | own start | joint calibration |"
      << (post ? " posterior median | 5 % | 95 % | determined |" : "") << "\n"
      << "|---|---|---|---|---|---|" << (post ? "---|---|---|---|" : "") << "\n";
  for (const CampaignSiteFit& fit : summary.sites) {
    const auto& ps = fit.space.parameters();
    for (std::size_t k = 0; k < ps.size(); ++k) {
      out << "| " << fit.name << " | " << ps[k].material << " | " << ps[k].class_name() << " | "
          << ps[k].name() << " | " << FormatNumber(fit.start[k], "%.4g") << " | "
          << (k < fit.calibrated.size() ? FormatNumber(fit.calibrated[k], "%.4g") : "-") << " |";
      if (post && fit.posterior) {
        const calibrate::ParameterPosterior& q = fit.posterior->parameters[k];
        out << " " << FormatNumber(q.median, "%.4g") << " | " << FormatNumber(q.p05, "%.4g")
            << " | " << FormatNumber(q.p95, "%.4g") << " | " << (q.undetermined ? "no" : "yes")
            << " |";
      }
      out << "\n";
    }
  }
}

}  // namespace

std::string CampaignMarkdown(const CampaignSummary& summary) {
  std::ostringstream out;
  const bool post = summary.calibration.posterior.has_value();
  out << "# Campaign " << summary.name << ": joint calibration of " << summary.sites.size()
      << " sites\n\n"
      << ParametersMarkdown(summary.calibration);
  const calibrate::Uncertainty& u = summary.calibration.best_method().uncertainty;
  if (u.computed && !u.rank_deficient) out << "\nStandard errors: " << u.message << ".\n";
  OffsetsMarkdown(summary.offsets, out);
  if (!summary.notes.empty()) {
    out << "\nShared bounds narrowed to the sites' intersection:\n\n";
    for (const std::string& n : summary.notes) out << "- " << n << "\n";
  }
  out << "\n## Per-site fit\n\n"
      << "| site | weight | rocks | misfit at its own start | misfit at the joint values | fit |"
      << (post ? " predictive check |" : "") << "\n"
      << "|---|---|---|---|---|---|" << (post ? "---|" : "") << "\n";
  for (const CampaignSiteFit& fit : summary.sites) {
    out << "| " << fit.name << " | " << FormatNumber(fit.weight, "%.3g") << " | " << fit.rocks
        << " | " << FormatNumber(fit.misfit_start.value, "%.4g") << " | "
        << FormatNumber(fit.misfit_joint.value, "%.4g") << " | "
        << observations::AssessFit(fit.misfit_joint).Sentence() << " |";
    if (post && fit.posterior)
      out << " " << fit.posterior->BandsInside() << " of " << fit.posterior->bands.size()
          << " inside the 5-95 % band of a new observation |";
    out << "\n";
  }
  if (post)
    out << "\nPredictive check: each site's observed statistics against the 5-95 % band of a "
           "new observation (90 % or a little more inside when the model holds) from "
        << summary.calibration.posterior->band_draws
        << " joint posterior draws, every site simulated at each draw's own seed.\n";
  SiteValuesMarkdown(summary, out);
  return out.str();
}

}  // namespace rockcal::reports
