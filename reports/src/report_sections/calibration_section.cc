// The calibration section of report.html: the method, the calibrated
// parameters, their correlation, and the methods compared.
#include <algorithm>
#include <cmath>
#include <set>

#include "rockcal/sites/json_reader.h"
#include "sections.h"

namespace rockcal::reports::sections {
namespace {

// A parameter value in SI with US units beside it (as everywhere in the report).
std::string ParameterValue(const calibrate::Parameter& p, double v, sites::Units units) {
  switch (p.kind) {
    case calibrate::ParameterKind::kHardness:
      return FormatNumber(v, "%.3f");
    case calibrate::ParameterKind::kRoughness:
      return Length(v, units);
    case calibrate::ParameterKind::kContactTime:
      return Show(v) + " s (" + Show(v * 1e3) + " ms)";
    case calibrate::ParameterKind::kRollingResistance:
    case calibrate::ParameterKind::kFriction:
    case calibrate::ParameterKind::kCapacityFactor:
    case calibrate::ParameterKind::kTrunkRestitution:
    case calibrate::ParameterKind::kTrunkFriction:
      return FormatNumber(v, "%.3f");
    case calibrate::ParameterKind::kVegetation:
      return Show(v * 1e-3) + " kPa" +
             (units == sites::Units::kUS
                  ? " (" + Show(v / sites::StressToSI(1.0, sites::Units::kUS)) + " lbf/ft²)"
                  : "");
  }
  return Show(v);
}

// Where v lies within [lo, hi]: a small bar with a marker.
std::string BoundsBar(double v, double lo, double hi) {
  const double f = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
  const std::string x = Px(4 + 92 * f);
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"12\" viewBox=\"0 0 100 "
         "12\">"
         "<line x1=\"4\" y1=\"6\" x2=\"96\" y2=\"6\" stroke=\"#999\" stroke-width=\"2\"/>"
         "<line x1=\"4\" y1=\"2\" x2=\"4\" y2=\"10\" stroke=\"#999\"/><line x1=\"96\" y1=\"2\" "
         "x2=\"96\" y2=\"10\" "
         "stroke=\"#999\"/><circle cx=\"" +
         x + "\" cy=\"6\" r=\"4\" fill=\"" + kStopColour + "\"/></svg>";
}

// The method, why it stopped, the work, the misfit and the calibrated values.
std::string RunTable(const CalibrationSummary& rec) {
  const calibrate::MethodResult& best = rec.methods[static_cast<std::size_t>(rec.best)];
  const std::string cj = "calibration.json";
  std::string s = "<table class=\"kv\">";
  // Stages of one search (a first stage and the refining stage at more
  // rocks) are named as stages; only different methods are "the best of".
  const bool refined = rec.final_rocks > 0 && rec.final_rocks != rec.rocks;
  std::set<calibrate::Method> methods;
  for (const calibrate::MethodResult& m : rec.methods) methods.insert(m.stage.method);
  std::string which;
  if (refined)
    which =
        " (the refining stage, at " + Int(rec.final_rocks) + " rocks per evaluation, the last of " +
        Int(static_cast<long>(rec.methods.size())) + " stages" +
        (methods.size() > 1 ? ", of " + Int(static_cast<long>(methods.size())) + " methods" : "") +
        ", compared below)";
  else if (rec.methods.size() > 1)
    which =
        " (the best of " + Int(static_cast<long>(rec.methods.size())) + " methods, compared below)";
  s += Kv("Method", "<code>" + Escape(best.stage.name()) + "</code>" + which);
  s += Kv("Stopped because", "<span data-json=\"" + Ref(cj, "/termination") + "\" data-value=\"" +
                                 Escape(best.termination.message) + "\">" +
                                 Escape(best.termination.message) + "</span>");
  s += Kv("Evaluations", RefSpan(Ref(cj, "/evaluations"), best.evaluations, Int(best.evaluations)) +
                             " (" + Int(best.simulated) +
                             " simulated, the rest replayed from the log) in " +
                             Escape(Show(best.wall_seconds)) + " s");
  s += Kv(
      refined ? "Misfit (at " + Int(rec.final_rocks) + " rocks, the refining stage's)" : "Misfit",
      "at the start " +
          RefSpan(Ref(cj, "/misfit_before"), rec.misfit_before.value,
                  Label(rec.misfit_before.value, 4)) +
          ", at the calibrated values " +
          RefSpan(Ref(cj, "/methods/" + Int(rec.best) + "/misfit"), best.best_misfit,
                  Label(best.best_misfit, 4)) +
          ", lowest evaluated " +
          RefSpan(Ref(cj, "/methods/" + Int(rec.best) + "/lowest_misfit"), best.lowest_misfit,
                  Label(best.lowest_misfit, 4)) +
          ", this report's simulation " +
          RefSpan(Ref(cj, "/misfit_after"), rec.misfit_after.value,
                  Label(rec.misfit_after.value, 4)) +
          " (half the sum of the squared residuals, each in units of its uncertainty)");
  s += Kv("Calibrated values",
          best.smoothed.used
              ? "the smoothed estimate: " + Escape(best.smoothed.message) +
                    ", at its Gauss-Newton minimum (the lowest evaluation sits in a dip of the "
                    "Monte Carlo noise)"
              : "the lowest evaluation" +
                    (best.smoothed.message.empty()
                         ? std::string()
                         : " (smoothed estimate " + Escape(best.smoothed.message) + ")"));
  s += Kv("Each evaluation", Escape((refined ? Int(rec.rocks) + " rocks in the first stage, " +
                                                   Int(rec.final_rocks) + " in the refining stage"
                                             : Int(rec.rocks) + " rocks") +
                                    ", seed " + std::to_string(rec.seed) +
                                    " (the same random numbers at every evaluation of a stage)"));
  if (rec.race_winner >= 0) {
    // The race for the refining stage's start (CalibrationOptions::race_points).
    std::string race;
    for (std::size_t k = 0; k < rec.race.size(); ++k) {
      const auto& entry = rec.race[k];
      race += (k ? ", " : "") + Escape(entry.from) + " " +
              RefSpan(Ref(cj, "/race/candidates/" + Int(static_cast<long>(k)) + "/misfit"),
                      entry.misfit, Label(entry.misfit, 4)) +
              (static_cast<int>(k) == rec.race_winner ? " (won)" : "");
    }
    s += Kv("Refining start",
            "the lowest misfit at " + Int(rec.final_rocks) + " rocks of: " + race +
                " (the first stage's misfits, at fewer rocks, rank mostly their noise)");
  }
  s += Kv(
      "Whole calibration",
      RefSpan(Ref(cj, "/wall_seconds"), rec.wall_seconds, Show(rec.wall_seconds)) + " s wall time");
  s += "</table>";
  if (rec.misfit_after.penalised || rec.misfit_before.penalised)
    s += "<p class=\"warn\">" +
         Escape(rec.misfit_after.message.empty() ? rec.misfit_before.message
                                                 : rec.misfit_after.message) +
         "</p>";
  return s;
}

// The calibrated parameters with their errors, start and bounds.
std::string ParameterTable(const CalibrationSummary& rec) {
  const calibrate::MethodResult& best = rec.methods[static_cast<std::size_t>(rec.best)];
  const std::string cj = "calibration.json";
  const auto& ps = rec.space.parameters();
  const calibrate::Uncertainty& u = best.uncertainty;
  const bool have_se = u.computed && !u.rank_deficient;
  std::string s = "<h3>Calibrated parameters</h3><table><thead><tr>" + Th("material") +
                  Th("parameter") + Th("calibrated") + Th("std. error") + Th("start") +
                  Th("lower bound") + Th("upper bound") + Th("within bounds") +
                  "</tr></thead><tbody>";
  for (std::size_t k = 0; k < ps.size(); ++k) {
    const double v = k < best.best.size() ? best.best[k] : std::nan("");
    const double range = ps[k].upper - ps[k].lower;
    const bool at_bound =
        std::fabs(v - ps[k].lower) < 0.01 * range || std::fabs(ps[k].upper - v) < 0.01 * range;
    s += "<tr>" + Td(ps[k].material) + Td(ps[k].name()) + "<td class=\"n\" data-json=\"" +
         Ref(cj, "/calibrated/" + Int(static_cast<long>(k))) + "\" data-value=\"" + Exact(v) +
         "\">" + Escape(ParameterValue(ps[k], v, rec.units)) +
         (at_bound ? " <b>at a bound</b>" : "") + "</td>" +
         Td(have_se && k < u.std_error.size() ? ParameterValue(ps[k], u.std_error[k], rec.units)
                                              : "-",
            true) +
         Td(k < rec.start.size() ? ParameterValue(ps[k], rec.start[k], rec.units) : "-", true) +
         Td(ParameterValue(ps[k], ps[k].lower, rec.units), true) +
         Td(ParameterValue(ps[k], ps[k].upper, rec.units), true) + "<td>" +
         BoundsBar(v, ps[k].lower, ps[k].upper) + "</td></tr>";
  }
  s += "</tbody></table>";
  if (const std::string d = DeterminationSentence(rec); !d.empty())
    s += "<p><b>" + Escape(d) + "</b></p>";
  if (have_se) s += "<p class=\"note\">Standard errors: " + Escape(u.message) + ".</p>";
  return s;
}

// The correlation of the parameters, when the method computed it.
std::string CorrelationTable(const CalibrationSummary& rec) {
  const auto& ps = rec.space.parameters();
  const calibrate::Uncertainty& u = rec.methods[static_cast<std::size_t>(rec.best)].uncertainty;
  const bool have_se = u.computed && !u.rank_deficient;
  std::string s;
  if (have_se && u.correlation.size() == ps.size() && ps.size() > 1) {
    s += "<h3>Correlation of the parameters</h3><table><thead><tr><th></th>";
    for (const auto& p : ps) s += Th(p.label());
    s += "</tr></thead><tbody>";
    for (std::size_t a = 0; a < ps.size(); ++a) {
      s += "<tr><th>" + Escape(ps[a].label()) + "</th>";
      for (std::size_t b = 0; b < ps.size(); ++b)
        s += Td(FormatNumber(u.correlation[a][b], "%.2f"), true);
      s += "</tr>";
    }
    s += "</tbody></table>";
  }
  return s;
}

// The methods side by side, when there were several.
std::string MethodsTable(const CalibrationSummary& rec) {
  const std::string cj = "calibration.json";
  std::string s;
  if (rec.methods.size() > 1) {
    const double best_all = LowestMisfitOfAll(rec);
    s += "<h3>Methods compared</h3><table><thead><tr>" + Th("method") + Th("misfit") +
         Th("lowest evaluated") + Th("evaluations") + Th("simulated") + Th("wall s") +
         Th("s to within 10 % of the lowest") + Th("stopped because") + "</tr></thead><tbody>";
    for (std::size_t m = 0; m < rec.methods.size(); ++m) {
      const auto& mr = rec.methods[m];
      const double reach = calibrate::TimeToReach(mr, best_all, 0.1);
      s += "<tr" + std::string(static_cast<int>(m) == rec.best ? " class=\"best\"" : "") +
           "><td><code>" + Escape(mr.stage.name()) + "</code></td>" +
           RefCell(Ref(cj, "/methods/" + Int(static_cast<long>(m)) + "/misfit"), mr.best_misfit,
                   Label(mr.best_misfit, 4)) +
           RefCell(Ref(cj, "/methods/" + Int(static_cast<long>(m)) + "/lowest_misfit"),
                   mr.lowest_misfit, Label(mr.lowest_misfit, 4)) +
           Td(Int(mr.evaluations), true) + Td(Int(mr.simulated), true) +
           Td(Show(mr.wall_seconds), true) + Td(reach >= 0 ? Show(reach) : "never", true) +
           Td(mr.termination.message) + "</tr>";
    }
    s += "</tbody></table>";
  }
  return s;
}

}  // namespace

std::string CalibrationSection(const Context& c) {
  const CalibrationSummary& rec = *c.in.calibration;
  return RunTable(rec) + ParameterTable(rec) + CorrelationTable(rec) + MethodsTable(rec);
}

}  // namespace rockcal::reports::sections
