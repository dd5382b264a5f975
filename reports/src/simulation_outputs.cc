#include "rockcal/reports/simulation_outputs.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

#include "rockcal/core/format.h"
#include "rockcal/core/material_field.h"
#include "rockcal/reports/forest_outputs.h"
#include "rockcal/reports/output_dir.h"

namespace rockcal::reports {
namespace {

using core::FormatNumber;

nlohmann::json StatsJson(const core::Stats& s, double scale = 1.0) {
  return {{"mean", s.mean * scale},
          {"p50", s.p50 * scale},
          {"p90", s.p90 * scale},
          {"p95", s.p95 * scale},
          {"max", s.max * scale}};
}

// A figure over every rock (core::BeyondStats): a number, or the string
// "beyond" where it falls among the rocks that left the terrain.
nlohmann::json BeyondValue(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json("beyond");
}

nlohmann::json BeyondJson(const core::BeyondStats& s) {
  return {{"min", BeyondValue(s.min)}, {"p10", BeyondValue(s.p10)}, {"p50", BeyondValue(s.p50)},
          {"p90", BeyondValue(s.p90)}, {"p95", BeyondValue(s.p95)}, {"max", BeyondValue(s.max)}};
}

// A value of `file` (rock `rock`, column `column`); a non-finite one is an
// internal failure, never written as "inf" or "nan".
std::string FiniteNumber(double v, const char* file, long rock, const std::string& column) {
  if (!std::isfinite(v)) {
    throw std::runtime_error("internal failure: " + std::string(file) + " rock " +
                             std::to_string(rock) + " column " + column + " is " + FormatNumber(v) +
                             ", not a finite number; nothing written");
  }
  return FormatNumber(v);
}

// Throws (an internal failure) at the first non-finite number in `j`, naming
// `file` and its JSON path.
void CheckFinite(const nlohmann::json& j, const std::string& file, const std::string& path) {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    throw std::runtime_error("internal failure: " + file + " " + path + " is " +
                             FormatNumber(j.get<double>()) +
                             ", not a finite number; nothing written");
  }
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it) CheckFinite(*it, file, path + "." + it.key());
  if (j.is_array())
    for (std::size_t k = 0; k < j.size(); ++k)
      CheckFinite(j[k], file, path + "[" + std::to_string(k) + "]");
}

// summary.json's "barriers" (SI; a percentile null when no rock reached).
nlohmann::json BarriersJson(const core::Scene& scene, const core::SimulationResult& result) {
  nlohmann::json out = nlohmann::json::array();
  for (const core::BarrierStats& b : core::ComputeBarriers(scene, result)) {
    const core::Partition& part = scene.partitions[b.partition];
    auto value = [&](double v) {
      return b.check.passed > 0 ? nlohmann::json(v) : nlohmann::json(nullptr);
    };
    out.push_back({{"id", part.id},
                   {"height_m", part.height},
                   {"capacity_kj", part.capacity * 1e-3},
                   {"stops", part.stops},
                   {"reaching", b.check.passed},
                   {"passing_over", b.check.over},
                   {"centre_above", b.check.over_by_centre},
                   {"exceeding_capacity", b.check.over_capacity},
                   {"stopped", b.stopped},
                   {"lowest_point_m", {{"p95", value(b.lowest_p95)}, {"p99", value(b.lowest_p99)}}},
                   {"centre_m", {{"p95", value(b.centre_p95)}, {"p99", value(b.centre_p99)}}},
                   {"energy_kj",
                    {{"p95", value(b.energy_p95 * 1e-3)}, {"p99", value(b.energy_p99 * 1e-3)}}}});
  }
  return out;
}

bool AnyBarrier(const core::Scene& scene) {
  for (const core::Partition& p : scene.partitions)
    if (p.kind == core::Partition::Kind::kLine) return true;
  return false;
}

}  // namespace

std::string BarriersCsv(const core::Scene& scene, const core::SimulationResult& result,
                        sites::Units units) {
  const std::string u = units == sites::Units::kUS ? "ft" : "m";
  const double to_file = 1.0 / sites::LengthToSI(1.0, units);
  std::ostringstream out;
  out << "id,height_" << u << ",capacity_kj,stops,reaching,passing_over,centre_above,"
      << "exceeding_capacity,stopped,lowest_point_p95_" << u << ",lowest_point_p99_" << u
      << ",centre_p95_" << u << ",centre_p99_" << u << ",energy_p95_kj,energy_p99_kj\n";
  for (const core::BarrierStats& b : core::ComputeBarriers(scene, result)) {
    const core::Partition& part = scene.partitions[b.partition];
    // A percentile; empty when no rock reached the barrier.
    auto value = [&](double v, double scale) {
      if (b.check.passed == 0) return std::string();
      if (!std::isfinite(v)) {
        throw std::runtime_error("internal failure: barriers.csv barrier " + part.id + " holds " +
                                 FormatNumber(v) + ", not a finite number; nothing written");
      }
      return FormatNumber(v * scale);
    };
    out << core::CsvField(part.id) << ',' << FormatNumber(part.height * to_file) << ','
        << FormatNumber(part.capacity * 1e-3) << ',' << (part.stops ? "true" : "false") << ','
        << b.check.passed << ',' << b.check.over << ',' << b.check.over_by_centre << ','
        << b.check.over_capacity << ',' << b.stopped << ',' << value(b.lowest_p95, to_file) << ','
        << value(b.lowest_p99, to_file) << ',' << value(b.centre_p95, to_file) << ','
        << value(b.centre_p99, to_file) << ',' << value(b.energy_p95, 1e-3) << ','
        << value(b.energy_p99, 1e-3) << '\n';
  }
  return out.str();
}

void WriteBarriersFile(const std::string& folder, const core::Scene& scene,
                       const core::SimulationResult& result, sites::Units units) {
  if (!AnyBarrier(scene)) return;
  WriteFileAtomically(folder + "/barriers.csv", BarriersCsv(scene, result, units));
}

nlohmann::json SummaryJson(const core::Scene& scene, const core::SimulationResult& result) {
  const core::ResultStats stats = core::ComputeStats(scene, result);
  nlohmann::json partitions = nlohmann::json::array();
  for (const auto& p : stats.partitions) {
    partitions.push_back({{"id", p.id},
                          {"passed", p.passed},
                          {"height_m", StatsJson(p.height)},
                          {"velocity_mps", StatsJson(p.velocity)},
                          {"energy_kj", StatsJson(p.energy, 1e-3)}});
  }
  nlohmann::json j = {
      {"site", scene.name},
      {"rocks", static_cast<int>(result.rocks.size())},
      {"seed", scene.options.seed},
      {"wall_seconds", result.wall_seconds},
      {"steps", result.figures.steps},
      {"dt_seconds", result.figures.dt_min},
      {"outcomes",
       {{"stopped", result.count(core::Outcome::kStopped)},
        {"left", result.count(core::Outcome::kLeft)},
        {"timeout", result.count(core::Outcome::kTimeout)}}},
      {"partitions", partitions},
      {"runout",
       {{"rocks", stats.runout.rocks},
        {"beyond_edge", stats.runout.beyond_edge},
        {"distance_m", BeyondJson(stats.runout.distance_m)},
        {"travel_angle_deg", BeyondJson(stats.runout.travel_angle_deg)},
        {"x_m", StatsJson(stats.runout_x)}}},
      {"energy_check", {{"max_relative_gain", result.figures.max_relative_energy_gain}}}};
  if (AnyBarrier(scene)) j["barriers"] = BarriersJson(scene, result);
  if (!scene.forest.empty()) j["forest"] = ForestSummaryJson(scene, result);
  return j;
}

std::vector<DiagnosticFigure> DiagnosticFigures(const core::Scene& scene,
                                                const core::SimulationResult& result) {
  using Check = DiagnosticFigure::Check;
  const core::RunFigures& f = result.figures;
  const core::SimulationOptions& opt = scene.options;
  auto count = [](long v) { return static_cast<double>(v); };
  return {
      {"dt_min_seconds", "smallest contact time step [s]", f.dt_min, false},
      {"dt_max_seconds", "largest contact time step [s]", f.dt_max, false},
      {"steps_per_contact", "steps per contact duration (N_c)", count(opt.steps_per_contact), true},
      {"rocks_with_step_shrunk_for_stability",
       "rocks whose step was cut below t_c/N_c for stability", count(f.dt_shrunk), true},
      {"gentle_steps_per_contact", "steps per contact duration in gentle contact (N_g; 0: off)",
       count(opt.gentle_steps_per_contact), true},
      {"contact_steps", "contact steps", count(f.steps), true},
      {"gentle_steps", "of which at the gentle-contact step", count(f.gentle_steps), true},
      {"retried_steps", "gentle steps taken back and redone short (an impact began)",
       count(f.retried_steps), true},
      {"flights", "exact free flights", count(f.flights), true},
      {"max_penetration_over_radius",
       "deepest overlap / element radius (about impact speed x t_c / pi)", f.max_penetration, false,
       Check::kBelow, 0.5},
      {"max_relative_energy_gain",
       "largest rise of mechanical energy / largest kinetic energy of the rock",
       f.max_relative_energy_gain, false, Check::kBelow, 1e-3},
      {"non_finite_rocks", "rocks whose state became non-finite", count(f.non_finite), true,
       Check::kZero},
      {"tunneled_rocks", "rocks that fell through the terrain", count(f.tunneled), true,
       Check::kZero},
  };
}

nlohmann::json DiagnosticsJson(const core::Scene& scene, const core::SimulationResult& result) {
  nlohmann::json j = nlohmann::json::object();
  for (const DiagnosticFigure& f : DiagnosticFigures(scene, result))
    j[f.key] =
        f.integer ? nlohmann::json(static_cast<long long>(f.value)) : nlohmann::json(f.value);
  // Scanned shapes (docs/rock-shapes.md): each clump's worst fit to its hull.
  const std::vector<core::ShapeUse> shapes = scene.ScannedShapes();
  if (!shapes.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const core::ShapeUse& u : shapes)
      list.push_back({{"name", u.name},
                      {"file", u.file},
                      {"bodies", u.uses},
                      {"spheres", u.spheres},
                      {"max_volume_error", u.volume_error},
                      {"max_moment_error", u.moment_error},
                      {"max_side_error", u.side_error}});
    j["scanned_shapes"] = list;
  }
  return j;
}

std::string RocksCsv(const core::Scene& scene, const core::SimulationResult& result) {
  std::ostringstream out;
  out << "rock,group,shape,size_m,mass_kg,outcome,stop_x,stop_y,stop_z";
  for (const auto& p : scene.partitions)
    out << ',' << p.id << ".height_m," << p.id << ".velocity_mps," << p.id << ".energy_kj";
  out << '\n';
  for (const auto& r : result.rocks) {
    const char* f = "rocks.csv";
    out << r.rock << ',' << r.group << ',' << core::ShapeToString(r.shape) << ','
        << FiniteNumber(r.size, f, r.rock, "size_m") << ','
        << FiniteNumber(r.mass, f, r.rock, "mass_kg") << ',' << core::OutcomeName(r.outcome) << ','
        << FiniteNumber(r.stop.x(), f, r.rock, "stop_x") << ','
        << FiniteNumber(r.stop.y(), f, r.rock, "stop_y") << ','
        << FiniteNumber(r.stop.z(), f, r.rock, "stop_z");
    for (std::size_t p = 0; p < scene.partitions.size(); ++p) {
      if (p < r.crossings.size() && r.crossings[p].crossed) {
        const auto& c = r.crossings[p];
        const std::string& id = scene.partitions[p].id;
        out << ',' << FiniteNumber(c.height, f, r.rock, id + ".height_m") << ','
            << FiniteNumber(c.speed, f, r.rock, id + ".velocity_mps") << ','
            << FiniteNumber(c.energy * 1e-3, f, r.rock, id + ".energy_kj");
      } else {
        out << ",,,";
      }
    }
    out << '\n';
  }
  return out.str();
}

std::string TrajectoriesCsv(const core::SimulationResult& result) {
  std::ostringstream out;
  out << "rock,t,x,y,z,vx,vy,vz,wx,wy,wz\n";
  for (const auto& r : result.rocks) {
    for (const auto& s : r.trajectory) {
      out << r.rock << ',' << FiniteNumber(s.t, "trajectories.csv", r.rock, "t");
      for (const Eigen::Vector3d* v : {&s.x, &s.v, &s.w})
        for (int k = 0; k < 3; ++k)
          out << ',' << FiniteNumber((*v)[k], "trajectories.csv", r.rock, "x/v/w");
      out << '\n';
    }
  }
  return out.str();
}

nlohmann::json ClassValuesJson(const std::vector<sites::ClassMaterial>& materials, bool drawn) {
  nlohmann::json list = nlohmann::json::array();
  for (const sites::ClassMaterial& m : materials) {
    nlohmann::json values = nlohmann::json::array();
    for (const sites::ClassRow& r : m.from_table) {
      const core::MaterialFieldInfo* f = core::FindMaterialField(r.parameter);
      values.push_back({{"parameter", r.parameter},
                        {"unit", f ? core::SiUnitName(f->unit) : ""},
                        {"median", r.median},
                        {"interval", r.low ? nlohmann::json{{"low", *r.low},
                                                            {"high", *r.high},
                                                            {"kind", r.interval}}
                                           : nlohmann::json(nullptr)},
                        {"drawn", drawn && r.low.has_value()},
                        {"sites", r.sites},
                        {"values", r.values}});
    }
    list.push_back({{"material", m.material},
                    {"class", m.material_class},
                    {"table", m.table},
                    {"description", m.description},
                    {"values", values},
                    {"site_overrides", m.explicit_fields},
                    {"notes", m.notes}});
  }
  return {{"use", drawn ? "draws" : "medians"},
          {"materials", list},
          {"note",
           "values of a class from a table of other sites' calibrations, not of this site: a "
           "calibration against field data from this site would narrow them"}};
}

void WriteSimulationFiles(const std::string& folder, const core::Scene& scene,
                          const core::SimulationResult& result, const nlohmann::json& parameters,
                          const nlohmann::json& classes) {
  // Everything is built and checked before anything is written.
  nlohmann::json summary = SummaryJson(scene, result);
  if (!parameters.is_null()) summary["parameters"] = parameters;
  if (!classes.is_null()) summary["classes"] = classes;
  const nlohmann::json diagnostics = DiagnosticsJson(scene, result);
  CheckFinite(summary, "summary.json", "$");
  CheckFinite(diagnostics, "diagnostics.json", "$");
  const std::string rocks = RocksCsv(scene, result);
  WriteFileAtomically(folder + "/summary.json", summary.dump(2) + "\n");
  WriteFileAtomically(folder + "/diagnostics.json", diagnostics.dump(2) + "\n");
  WriteFileAtomically(folder + "/rocks.csv", rocks);
  if (scene.options.record.trajectories > 0)
    WriteFileAtomically(folder + "/trajectories.csv", TrajectoriesCsv(result));
}

}  // namespace rockcal::reports
