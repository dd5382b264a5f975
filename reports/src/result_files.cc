#include "rockcal/reports/result_files.h"

#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "rockcal/core/format.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/reach_report.h"

namespace rockcal::reports {
namespace {

using core::CsvField;

// A number of a CSV table: empty for NaN, "inf" / "-inf" for infinities.
std::string Num(double v, const char* format = "%.6g") {
  return std::isnan(v) ? "" : core::FormatNumber(v, format);
}

const char* Bool(bool b) { return b ? "true" : "false"; }

// Writes (name, text) pairs into `folder`, after all were built.
void WriteAll(const std::string& folder,
              const std::vector<std::pair<const char*, std::string>>& files) {
  for (const auto& [name, text] : files) WriteFileAtomically(folder + "/" + name, text);
}

}  // namespace

std::string StabilityCsv(const calibrate::StabilityStudy& study) {
  std::ostringstream out;
  out << "case,rocks,max_time_s,dt_min_s,dt_max_s,dt_shrunk,rocks_with_step_shrunk,steps,flights,"
         "wall_seconds,"
         "stopped,left,timeout,max_relative_energy_gain,max_penetration_over_radius,"
         "non_finite_rocks,tunneled_rocks,must_stop,result,reason,warning\n";
  for (const calibrate::StabilityCase& c : study.cases) {
    const core::RunFigures& f = c.figures;
    out << CsvField(c.name) << ',' << f.rocks << ',' << Num(c.max_time) << ',' << Num(f.dt_min)
        << ',' << Num(f.dt_max) << ',' << Bool(f.dt_shrunk > 0) << ',' << f.dt_shrunk << ','
        << f.steps << ',' << f.flights << ',' << Num(c.wall_seconds, "%.4g") << ',' << c.stopped
        << ',' << c.left << ',' << c.timeout << ',' << Num(f.max_relative_energy_gain) << ','
        << Num(f.max_penetration) << ',' << f.non_finite << ',' << f.tunneled << ','
        << Bool(c.must_stop) << ',' << (c.pass ? "PASS" : "FAIL") << ',' << CsvField(c.reason)
        << ',' << CsvField(c.warning) << '\n';
  }
  return out.str();
}

std::string ConvergenceCsv(const calibrate::ConvergenceResult& result) {
  std::ostringstream out;
  out << "steps_per_contact,rocks,dt_min_s,wall_seconds,steps,quantity,value,count,total_error,"
         "mc_error,discretisation_error,discretisation_noise,estimate,meets_target,reference,"
         "recommended\n";
  for (std::size_t k = 0; k < result.rows.size(); ++k) {
    const calibrate::ConvergenceRow& r = result.rows[k];
    const std::string head = std::to_string(r.steps_per_contact) + ',' + std::to_string(r.rocks) +
                             ',' + Num(r.figures.dt_min) + ',' + Num(r.wall_seconds, "%.4g") + ',' +
                             std::to_string(r.figures.steps) + ',';
    const std::string tail = std::string(",") + Bool(r.meets_target) + ',' +
                             Bool(static_cast<int>(k) == result.reference) + ',' +
                             Bool(static_cast<int>(k) == result.recommended) + '\n';
    for (const calibrate::QuantityError& q : r.quantities)
      out << head << CsvField(q.name) << ',' << Num(q.value) << ',' << q.count << ','
          << Num(q.total_error) << ',' << Num(q.mc_error) << ',' << Num(q.discretisation_error)
          << ',' << Num(q.discretisation_noise) << ',' << Num(q.estimate) << tail;
    out << head << "max,,," << Num(r.max_total_error) << ',' << Num(r.max_mc_error) << ','
        << Num(r.max_discretisation_error) << ',' << Num(r.max_discretisation_noise) << ','
        << Num(r.max_estimate) << tail;
  }
  return out.str();
}

std::string SensitivityCsv(const calibrate::SensitivityResult& r) {
  const bool morris = r.method == calibrate::SensitivityMethod::kMorris;
  std::ostringstream out;
  out << "method,parameter,output,unit,value,noise,";
  out << (morris ? "mu,mu_star,sigma,effects,"
                 : "first,first_low,first_high,total,total_low,"
                   "total_high,variance,rows,");
  out << "effect_over_noise\n";
  for (const calibrate::SensitivityEntry& e : r.entries) {
    const std::size_t o = static_cast<std::size_t>(e.output);
    const calibrate::SensitivityOutputInfo& output = r.outputs[o];
    out << calibrate::SensitivityMethodToString(r.method) << ','
        << CsvField(r.parameters[static_cast<std::size_t>(e.parameter)].label()) << ','
        << CsvField(output.name) << ',' << CsvField(output.unit) << ',' << Num(output.value) << ','
        << Num(output.noise) << ',';
    if (morris) {
      out << Num(e.morris.mu) << ',' << Num(e.morris.mu_star) << ',' << Num(e.morris.sigma) << ','
          << e.morris.effects << ',';
    } else {
      out << Num(e.sobol.first) << ',' << Num(e.sobol.first_low) << ',' << Num(e.sobol.first_high)
          << ',' << Num(e.sobol.total) << ',' << Num(e.sobol.total_low) << ','
          << Num(e.sobol.total_high) << ',' << Num(r.sobol.variance[o]) << ',' << r.sobol.rows[o]
          << ',';
    }
    out << Num(e.effect_over_noise) << '\n';
  }
  return out.str();
}

std::string ReachCsv(const calibrate::ReachResult& r) {
  std::ostringstream out;
  out << "statistic,observation,quantity,observed,sigma,min,max,min_point,max_point,"
         "closest_point,closest_simulated,closest_sigmas,points_with_value,verdict,at_edge\n";
  for (const calibrate::ReachStatistic& s : r.statistics)
    out << CsvField(s.name()) << ',' << CsvField(s.id.observation()) << ','
        << CsvField(s.id.quantity()) << ',' << Num(s.observed, "%.10g") << ','
        << Num(s.sigma, "%.10g") << ',' << Num(s.min, "%.10g") << ',' << Num(s.max, "%.10g") << ','
        << s.min_point << ',' << s.max_point << ',' << s.closest_point << ','
        << Num(s.closest_simulated, "%.10g") << ',' << Num(s.closest_sigmas, "%.10g") << ','
        << s.points_with_value << ',' << calibrate::ReachVerdictText(s.verdict) << ','
        << Bool(s.at_edge()) << '\n';
  return out.str();
}

void WriteStabilityFiles(const std::string& folder, const StudyReportInput& in,
                         const calibrate::StabilityStudy& study) {
  WriteAll(folder, {{"stability.json", JsonText(study)},
                    {"stability.csv", StabilityCsv(study)},
                    {"report.html", StabilityHtmlReport(in, study)}});
}

void WriteConvergenceFiles(const std::string& folder, const StudyReportInput& in,
                           const calibrate::ConvergenceResult& result) {
  WriteAll(folder, {{"convergence.json", JsonText(result)},
                    {"convergence.csv", ConvergenceCsv(result)},
                    {"convergence.svg", ConvergenceSvg(result)},
                    {"report.html", ConvergenceHtmlReport(in, result)}});
}

void WriteSensitivityFiles(const std::string& folder, const StudyReportInput& in,
                           const calibrate::SensitivityResult& result) {
  WriteAll(folder, {{"sensitivity.json", JsonText(result)},
                    {"sensitivity.csv", SensitivityCsv(result)},
                    {"report.html", SensitivityHtmlReport(in, result)}});
}

void WriteReachFiles(const std::string& folder, const StudyReportInput& in,
                     const calibrate::ReachResult& result) {
  WriteAll(folder, {{"reach.json", JsonText(result)},
                    {"reach.csv", ReachCsv(result)},
                    {"report.html", ReachHtmlReport(in, result)}});
}

void WriteScoreFile(const std::string& folder, const calibrate::ScoreResult& score) {
  WriteAll(folder, {{"score.json", JsonText(score)}});
}

}  // namespace rockcal::reports
