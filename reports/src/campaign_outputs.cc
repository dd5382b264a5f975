#include "rockcal/reports/campaign_outputs.h"

#include <sstream>

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

}  // namespace

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
  for (const CampaignSiteFit& fit : summary.sites)
    sites.push_back({{"name", fit.name},
                     {"site_file", fit.site_file},
                     {"weight", fit.weight},
                     {"rocks", fit.rocks},
                     {"misfit_own_start", fit.misfit_start.value},
                     {"misfit_joint", fit.misfit_joint.value},
                     {"fit_joint", observations::AssessFit(fit.misfit_joint).Sentence()},
                     {"parameters", SiteValuesJson(fit)}});
  nlohmann::json names = nlohmann::json::array();
  for (const auto& p : cal.space.parameters()) names.push_back(p.label());
  return {{"campaign", summary.name},
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
          {"parameters", ParametersJson(cal)["parameters"]},
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
}

std::string CampaignSitesCsv(const CampaignSummary& summary) {
  std::ostringstream out;
  out << "site,site_file,weight,rocks,residuals,misfit_own_start,misfit_joint,"
         "outside_2_sigma_joint\n";
  for (const CampaignSiteFit& fit : summary.sites) {
    const observations::FitVerdict v = observations::AssessFit(fit.misfit_joint);
    out << fit.name << ',' << fit.site_file << ',' << FormatNumber(fit.weight, "%.6g") << ','
        << fit.rocks << ',' << fit.misfit_joint.residuals.size() << ','
        << FormatNumber(fit.misfit_start.value, "%.8g") << ','
        << FormatNumber(fit.misfit_joint.value, "%.8g") << ',' << v.outside.size() << '\n';
  }
  return out.str();
}

std::string CampaignMarkdown(const CampaignSummary& summary) {
  std::ostringstream out;
  out << "# Campaign " << summary.name << ": joint calibration of " << summary.sites.size()
      << " sites\n\n"
      << ParametersMarkdown(summary.calibration);
  const calibrate::Uncertainty& u = summary.calibration.best_method().uncertainty;
  if (u.computed && !u.rank_deficient) out << "\nStandard errors: " << u.message << ".\n";
  if (!summary.notes.empty()) {
    out << "\nShared bounds narrowed to the sites' intersection:\n\n";
    for (const std::string& n : summary.notes) out << "- " << n << "\n";
  }
  out << "\n## Per-site fit\n\n"
      << "| site | weight | rocks | misfit at its own start | misfit at the joint values | fit |\n"
      << "|---|---|---|---|---|---|\n";
  for (const CampaignSiteFit& fit : summary.sites)
    out << "| " << fit.name << " | " << FormatNumber(fit.weight, "%.3g") << " | " << fit.rocks
        << " | " << FormatNumber(fit.misfit_start.value, "%.4g") << " | "
        << FormatNumber(fit.misfit_joint.value, "%.4g") << " | "
        << observations::AssessFit(fit.misfit_joint).Sentence() << " |\n";
  out << "\n## Each site's values (SI)\n\n"
      << "| site | material | class | parameter | own start | joint calibration |\n"
      << "|---|---|---|---|---|---|\n";
  for (const CampaignSiteFit& fit : summary.sites) {
    const auto& ps = fit.space.parameters();
    for (std::size_t k = 0; k < ps.size(); ++k)
      out << "| " << fit.name << " | " << ps[k].material << " | " << ps[k].class_name() << " | "
          << ps[k].name() << " | " << FormatNumber(fit.start[k], "%.4g") << " | "
          << (k < fit.calibrated.size() ? FormatNumber(fit.calibrated[k], "%.4g") : "-") << " |\n";
  }
  return out.str();
}

}  // namespace rockcal::reports
