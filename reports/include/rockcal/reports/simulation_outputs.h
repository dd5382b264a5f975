// The machine-readable record of a simulation: summary.json, rocks.csv,
// trajectories.csv and diagnostics.json (all SI units).
#ifndef ROCKCAL_REPORTS_SIMULATION_OUTPUTS_H_
#define ROCKCAL_REPORTS_SIMULATION_OUTPUTS_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rockcal/core/simulate.h"
#include "rockcal/sites/class_table.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::reports {

// summary.json (docs/reference/outputs.md#summaryjson): SI; `runout` gives
// the distance and travel angle over every rock, "beyond" where a figure
// falls among the rocks that left the terrain.
nlohmann::json SummaryJson(const core::Scene& scene, const core::SimulationResult& result);
// One figure of diagnostics.json: its key, what it is, its value and how
// the report judges it.
struct DiagnosticFigure {
  enum class Check {
    kNone,   // information
    kBelow,  // small is good: at most `limit`
    kZero,   // must be 0
  };
  const char* key;   // diagnostics.json's key
  const char* what;  // for the report's table
  double value = 0.0;
  bool integer = false;  // a count, written as a whole number
  Check check = Check::kNone;
  double limit = 0.0;  // of kBelow
};
// The run's numerical diagnostics from its core::RunFigures and the scene's
// steps per contact: time steps, shrunk steps, contact steps and flights,
// penetration, energy gain, non-finite and tunneled rocks; in the report's
// order.
std::vector<DiagnosticFigure> DiagnosticFigures(const core::Scene& scene,
                                                const core::SimulationResult& result);
// diagnostics.json: DiagnosticFigures, and the scanned shapes' fit.
nlohmann::json DiagnosticsJson(const core::Scene& scene, const core::SimulationResult& result);
// One row per rock; partition columns in site order (empty where not crossed).
// A non-finite value throws std::runtime_error (an internal failure) naming
// the file, the rock and the column; it is never written as "inf" or "nan".
std::string RocksCsv(const core::Scene& scene, const core::SimulationResult& result);
// rock,t,x,y,z,vx,vy,vz,wx,wy,wz for the rocks that recorded a trajectory.
std::string TrajectoriesCsv(const core::SimulationResult& result);
// barriers.csv (docs/reference/outputs.md#barrierscsv): one row per barrier
// (a Partition::Kind::kLine) in partition order, its figures
// (core::ComputeBarriers) in the site's length unit and kJ; the percentiles
// empty when no rock reached it. Only the header without barriers.
std::string BarriersCsv(const core::Scene& scene, const core::SimulationResult& result,
                        sites::Units units);
// Writes barriers.csv into `folder` (through a temporary file) when the
// scene has barriers; nothing otherwise.
void WriteBarriersFile(const std::string& folder, const core::Scene& scene,
                       const core::SimulationResult& result, sites::Units units);
// Writes summary.json, diagnostics.json, rocks.csv and (when recorded)
// trajectories.csv into `folder`, each through a temporary file. A
// non-finite value in any of them throws std::runtime_error (an internal
// failure, exit 1) naming the file and where, before anything is written.
// `parameters`, when not null, is summary.json's "parameters": which values
// the run took (rockcal simulate --parameters: point values or posterior
// draws, calibrate::PosteriorRunJson); `classes`, when not null, is its
// "classes" (ClassValuesJson).
// summary.json's "classes": the values a site's materials took from class
// tables (sites/class_table.h), per material its class, table, each value's
// median, interval and support, the site's own values overriding them and
// the notes; "use" "draws" or "medians"; and a "note" that a calibration
// against field data would narrow them (docs/reference/outputs.md).
nlohmann::json ClassValuesJson(const std::vector<sites::ClassMaterial>& materials, bool drawn);
void WriteSimulationFiles(const std::string& folder, const core::Scene& scene,
                          const core::SimulationResult& result,
                          const nlohmann::json& parameters = nullptr,
                          const nlohmann::json& classes = nullptr);

}  // namespace rockcal::reports

#endif  // ROCKCAL_REPORTS_SIMULATION_OUTPUTS_H_
