// The machine-readable record of a simulation: summary.json, rocks.csv,
// trajectories.csv and diagnostics.json (all SI units).
#ifndef ROCKCAL_REPORTS_SIMULATION_OUTPUTS_H_
#define ROCKCAL_REPORTS_SIMULATION_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>

#include "rockcal/core/simulate.h"

namespace rockcal::reports {

// summary.json, exactly the schema of DESIGN.md.
nlohmann::json SummaryJson(const core::Scene& scene, const core::SimulationResult& result);
// Numerical diagnostics: time steps, flights, shrunk steps, penetration,
// energy gain, non-finite and tunneled rocks.
nlohmann::json DiagnosticsJson(const core::Scene& scene, const core::SimulationResult& result);
// One row per rock; partition columns in site order (empty where not crossed).
std::string RocksCsv(const core::Scene& scene, const core::SimulationResult& result);
// rock,t,x,y,z,vx,vy,vz,wx,wy,wz for the rocks that recorded a trajectory.
std::string TrajectoriesCsv(const core::SimulationResult& result);
// Writes summary.json, diagnostics.json, rocks.csv and (when recorded)
// trajectories.csv into `folder`, each through a temporary file.
void WriteSimulationFiles(const std::string& folder, const core::Scene& scene,
                          const core::SimulationResult& result);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_SIMULATION_OUTPUTS_H_
