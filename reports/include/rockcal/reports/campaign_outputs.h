// The record of a joint calibration of several sites (calibrate::RunCampaign):
// summary.json, the per-site fit (sites.csv) and parameters.md. The joint
// table (parameters.json, .csv), trace.csv and the comparison of methods are
// calibration_outputs.h's writers on CampaignSummary::calibration.
#ifndef ROCKCAL_REPORTS_CAMPAIGN_OUTPUTS_H_
#define ROCKCAL_REPORTS_CAMPAIGN_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>

#include "rockcal/calibrate/campaign.h"

namespace rockcal::reports {

// summary.json (SI): the campaign, the best method and its budget, the joint
// misfit before and after, the joint parameters per class with standard
// errors (parameters.json's rows), the uncertainty's correlations and
// message, the bounds notes, and per site its weight, rocks, misfit at its
// own start and at the joint values, and its materials' values at both.
nlohmann::json CampaignJson(const calibrate::CampaignSummary& summary);
// sites.csv: site,site_file,weight,rocks,residuals,misfit_own_start,
// misfit_joint,outside_2_sigma_joint.
std::string CampaignSitesCsv(const calibrate::CampaignSummary& summary);
// parameters.md: the joint table (ParametersMarkdown), the bounds notes, the
// per-site fit and each site's values at the joint calibration.
std::string CampaignMarkdown(const calibrate::CampaignSummary& summary);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_CAMPAIGN_OUTPUTS_H_
