// What measured impacts (observations' "impacts") add to a calibration's or
// a score's files (docs/reference/outputs.md#impactscsv): impacts.csv, one
// row per observed impact (the "impacts" of calibration.json and score.json
// is calibrate::ImpactsJson).
#ifndef ROCKCAL_REPORTS_IMPACT_OUTPUTS_H_
#define ROCKCAL_REPORTS_IMPACT_OUTPUTS_H_

#include <string>

#include "rockcal/core/scene.h"
#include "rockcal/observations/misfit.h"

namespace rockcal::reports {

// impacts.csv: id,group,incidence_deg,vx_out,vy_out,vz_out,vx_sim,vy_sim,
// vz_sim,speed_sd,normal_ratio,normal_ratio_sim,normal_ratio_spread,
// tangential_ratio,tangential_ratio_sim,tangential_ratio_spread,draws,left:
// per impact of misfit.impacts its observed rebound, the median of each
// component of its replays and the robust spread of their speed (in the
// site's length per second: `to_site` is metres to the site's unit), and its
// rebound ratios observed, the replays' median and robust spread (empty when
// undefined: a near-normal impact's tangential ratio); `group` is the rock
// group's id in `scene` (its index when it has none).
std::string ImpactsCsv(const observations::Misfit& misfit, const core::Scene& scene,
                       double to_site);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_IMPACT_OUTPUTS_H_
