#include "run_inputs.h"

#include <algorithm>

namespace rockcal::cli {

RunInputs& RunInputs::Add(const std::string& path) {
  if (!path.empty() && std::find(paths_.begin(), paths_.end(), path) == paths_.end())
    paths_.push_back(path);
  return *this;
}

RunInputs& RunInputs::Add(const sites::Site& site) {
  Add(site.path);
  for (const std::string& f : site.inputs) Add(f);
  return *this;
}

RunInputs& RunInputs::Add(const observations::Observations& obs) {
  Add(obs.path);
  for (const std::string& f : obs.inputs) Add(f);
  return *this;
}

RunInputs& RunInputs::Add(const calibrate::Campaign& campaign) {
  Add(campaign.path);
  for (const std::string& f : campaign.inputs) Add(f);
  for (const calibrate::CampaignSite& s : campaign.sites) {
    Add(s.site);
    Add(s.observations);
  }
  return *this;
}

}  // namespace rockcal::cli
