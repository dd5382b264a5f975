// What a run through a forest writes (docs/reference/outputs.md): the
// strikes (tree_impacts.csv), the stems drawn from stands (trees.csv) and
// summary.json's "forest" figures.
#ifndef ROCKCAL_REPORTS_FOREST_OUTPUTS_H_
#define ROCKCAL_REPORTS_FOREST_OUTPUTS_H_

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "rockcal/core/simulate.h"

namespace rockcal::reports {

// summary.json's "forest" (SI): stems; strikes, rocks that struck a stem,
// rocks stopped after striking one, energy the trunks absorbed [J], strikes
// that broke their stem and stems broken by at least one rock. The strike
// figures need result.strikes_recorded (null otherwise: only "stems").
nlohmann::json ForestSummaryJson(const core::Scene& scene, const core::SimulationResult& result);

// tree_impacts.csv: rock,tree,x,y,height,speed,energy,absorbed,broken, one
// row per strike in rock order; x, y and height in the site's length
// (`to_site`: metres to the site's unit), speed in that unit per second,
// energy and absorbed in J, broken 0 or 1. A non-finite value throws
// std::runtime_error (an internal failure) naming the rock.
std::string TreeImpactsCsv(const core::SimulationResult& result, double to_site);

// trees.csv: the stems from index `first` on (those drawn from stands) as a
// tree file gives them: x,y,dbh_cm,species,height (site length unit).
std::string TreesCsv(const core::Forest& forest, std::size_t first, double to_site);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_FOREST_OUTPUTS_H_
