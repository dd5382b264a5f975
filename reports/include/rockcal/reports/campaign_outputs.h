// The record of a joint calibration of several sites (calibrate::RunCampaign):
// summary.json, the per-site fit (sites.csv) and parameters.md. The joint
// table (parameters.json, .csv), trace.csv and the comparison of methods are
// calibration_outputs.h's writers on CampaignSummary::calibration.
#ifndef ROCKCAL_REPORTS_CAMPAIGN_OUTPUTS_H_
#define ROCKCAL_REPORTS_CAMPAIGN_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/calibrate/campaign.h"

namespace rockcal::reports {

// summary.json (SI): the campaign, the best method and its budget, the joint
// misfit before and after, the joint parameters per class with standard
// errors (parameters.json's rows), the uncertainty's correlations and
// message, the bounds notes, and per site its weight, rocks, folder
// (CampaignSiteFolders), misfit at its own start and at the joint values,
// and its materials' values at both. With a posterior: "posterior", the
// joint one (calibrate::PosteriorJson) with "offsets" (per offset its
// label, sigma, median, p05, p95, width_share, undetermined), and per
// site its own ("parameters", "correlation", "max_rhat", "min_ess",
// "predictive").
nlohmann::json CampaignJson(const calibrate::CampaignSummary& summary);
// sites.csv: site,site_file,weight,rocks,residuals,misfit_own_start,
// misfit_joint,outside_2_sigma_joint, and with a posterior
// predictive_inside,predictive_bands.
std::string CampaignSitesCsv(const calibrate::CampaignSummary& summary);
// parameters.md: the joint table (ParametersMarkdown, with the joint
// posterior), the offsets' posterior, the bounds notes, the per-site fit
// (with its predictive check) and each site's values at the joint
// calibration (with their posterior).
std::string CampaignMarkdown(const calibrate::CampaignSummary& summary);

// Each site's folder in the campaign's output, relative to it:
// "sites/<name>" with the characters of the name other than letters,
// digits, '.', '-' and '_' as '_' (and "-2", "-3", ... after a name taken).
std::vector<std::string> CampaignSiteFolders(const calibrate::CampaignSummary& summary);
}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_CAMPAIGN_OUTPUTS_H_
