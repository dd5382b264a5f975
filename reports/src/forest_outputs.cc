#include "rockcal/reports/forest_outputs.h"

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rockcal/core/format.h"

namespace rockcal::reports {
namespace {

using core::FormatNumber;

std::string Finite(double v, const core::RockRecord& r, const char* column) {
  if (!std::isfinite(v))
    throw std::runtime_error("internal failure: tree_impacts.csv rock " + std::to_string(r.rock) +
                             " column " + column + " is " + FormatNumber(v) +
                             ", not a finite number; nothing written");
  return FormatNumber(v);
}

}  // namespace

nlohmann::json ForestSummaryJson(const core::Scene& scene, const core::SimulationResult& result) {
  nlohmann::json j = {{"stems", scene.forest.stems.size()}};
  if (!result.strikes_recorded) return j;
  long strikes = 0, breaks = 0;
  int struck = 0, stopped = 0;
  double absorbed = 0.0;
  std::set<int> broken;
  for (const core::RockRecord& r : result.rocks) {
    strikes += static_cast<long>(r.strikes.size());
    struck += !r.strikes.empty();
    stopped += !r.strikes.empty() && r.outcome == core::Outcome::kStopped;
    for (const core::TreeStrike& s : r.strikes) {
      absorbed += s.absorbed;
      if (s.broken) {
        ++breaks;
        broken.insert(s.tree);
      }
    }
  }
  j["strikes"] = strikes;
  j["rocks_struck"] = struck;
  j["rocks_stopped_after_strike"] = stopped;
  j["energy_absorbed_j"] = absorbed;
  j["breaks"] = breaks;
  j["stems_broken"] = broken.size();
  return j;
}

std::string TreeImpactsCsv(const core::SimulationResult& result, double to_site) {
  std::ostringstream out;
  out << "rock,tree,x,y,height,speed,energy,absorbed,broken\n";
  for (const core::RockRecord& r : result.rocks)
    for (const core::TreeStrike& s : r.strikes)
      out << r.rock << ',' << s.tree << ',' << Finite(s.point.x() * to_site, r, "x") << ','
          << Finite(s.point.y() * to_site, r, "y") << ',' << Finite(s.height * to_site, r, "height")
          << ',' << Finite(s.speed * to_site, r, "speed") << ',' << Finite(s.energy, r, "energy")
          << ',' << Finite(s.absorbed, r, "absorbed") << ',' << (s.broken ? 1 : 0) << '\n';
  return out.str();
}

std::string TreesCsv(const core::Forest& forest, std::size_t first, double to_site) {
  std::ostringstream out;
  out << "x,y,dbh_cm,species,height\n";
  for (std::size_t k = first; k < forest.stems.size(); ++k) {
    const core::Stem& s = forest.stems[k];
    out << FormatNumber(s.x * to_site) << ',' << FormatNumber(s.y * to_site) << ','
        << FormatNumber(s.dbh * 100.0) << ',' << core::SpeciesClassName(s.species) << ','
        << FormatNumber(s.height * to_site) << '\n';
  }
  return out.str();
}

}  // namespace rockcal::reports
