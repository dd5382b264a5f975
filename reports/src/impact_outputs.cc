#include "rockcal/reports/impact_outputs.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "rockcal/core/format.h"

namespace rockcal::reports {
namespace {

using core::FormatNumber;

std::string GroupName(const core::Scene& scene, int group) {
  const std::size_t g = static_cast<std::size_t>(group);
  if (g < scene.groups.size() && !scene.groups[g].id.empty()) return scene.groups[g].id;
  return std::to_string(group);
}

// A CSV field: the number, or empty when it is not finite.
std::string Field(double v) { return std::isfinite(v) ? FormatNumber(v, "%.6g") : ""; }

}  // namespace

std::string ImpactsCsv(const observations::Misfit& misfit, const core::Scene& scene,
                       double to_site) {
  std::ostringstream out;
  out << "id,group,incidence_deg,vx_out,vy_out,vz_out,vx_sim,vy_sim,vz_sim,speed_sd,"
         "normal_ratio,normal_ratio_sim,normal_ratio_spread,tangential_ratio,"
         "tangential_ratio_sim,tangential_ratio_spread,draws,left\n";
  for (const observations::ImpactFit& f : misfit.impacts) {
    std::string id = f.id;
    for (char& ch : id)
      if (ch == ',' || ch == '\n') ch = ';';
    const bool tangential = std::isfinite(f.tangential_observed) && f.tangential_sigma > 0;
    out << id << ',' << GroupName(scene, f.group) << ',' << Field(f.incidence_deg);
    for (int k = 0; k < 3; ++k) out << ',' << Field(f.observed[k] * to_site);
    for (int k = 0; k < 3; ++k) out << ',' << Field(f.simulated[k] * to_site);
    out << ',' << Field(f.speed_sd * to_site) << ',' << Field(f.normal_observed) << ','
        << Field(f.normal_simulated) << ',' << Field(f.normal_spread) << ','
        << Field(f.tangential_observed) << ','
        << (tangential ? Field(f.tangential_simulated) : std::string()) << ','
        << (tangential ? Field(f.tangential_spread) : std::string()) << ',' << f.draws << ','
        << f.left << '\n';
  }
  return out.str();
}

}  // namespace rockcal::reports
