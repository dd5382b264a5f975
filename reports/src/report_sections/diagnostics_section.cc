// The numerical diagnostics section of report.html (diagnostics.json).
#include "rockcal/reports/simulation_outputs.h"
#include "sections.h"

namespace rockcal::reports::sections {

std::string DiagnosticsSection(const Context& c) {
  const nlohmann::json d = DiagnosticsJson(c.scene, c.result);
  struct Row {
    const char* key;
    const char* what;
    int verdict;  // 0: information, 1: must be 0, 2: small is good (below limit)
    double limit;
  };
  const Row rows[] = {
      {"dt_min_seconds", "smallest contact time step [s]", 0, 0},
      {"dt_max_seconds", "largest contact time step [s]", 0, 0},
      {"steps_per_contact", "steps per contact duration (N_c)", 0, 0},
      {"rocks_with_step_shrunk_for_stability",
       "rocks whose step was cut below t_c/N_c for stability", 0, 0},
      {"gentle_steps_per_contact", "steps per contact duration in gentle contact (N_g; 0: off)", 0,
       0},
      {"contact_steps", "contact steps", 0, 0},
      {"gentle_steps", "of which at the gentle-contact step", 0, 0},
      {"retried_steps", "gentle steps taken back and redone short (an impact began)", 0, 0},
      {"flights", "exact free flights", 0, 0},
      {"max_penetration_over_radius",
       "deepest overlap / element radius (about impact speed x t_c / pi)", 2, 0.5},
      {"max_relative_energy_gain",
       "largest rise of mechanical energy / largest kinetic energy of the rock", 2, 1e-3},
      {"non_finite_rocks", "rocks whose state became non-finite", 1, 0},
      {"tunneled_rocks", "rocks that fell through the terrain", 1, 0},
  };
  std::string s =
      "<p>The numerical health of the run (diagnostics.json): the engine picks its own stable step "
      "and "
      "reports where it had to work hard.</p><table><thead><tr>" +
      Th("quantity") + Th("value") + Th("check") + "</tr></thead><tbody>";
  for (const Row& row : rows) {
    if (!d.contains(row.key)) continue;
    const double v = d[row.key].get<double>();
    std::string verdict = "";
    if (row.verdict == 1) verdict = v == 0 ? "OK" : "FAILED: must be 0";
    if (row.verdict == 2)
      verdict = v <= row.limit ? "OK (below " + Label(row.limit) + ")"
                               : "check: above " + Label(row.limit);
    const bool integer = d[row.key].is_number_integer();
    s += "<tr>" + Td(row.what) +
         RefCell(Ref("diagnostics.json", std::string("/") + row.key), v,
                 integer ? Int(static_cast<long>(v)) : Label(v, 3)) +
         "<td class=\"" +
         (verdict.rfind("OK", 0) == 0 ? "ok"
          : verdict.empty()           ? ""
                                      : "bad") +
         "\">" + Escape(verdict) + "</td></tr>";
  }
  s += "</tbody></table>";
  if (c.timeout > 0)
    s += "<p class=\"warn\">" + Int(c.timeout) + " rocks were still moving at the time limit of " +
         Label(c.scene.options.max_time) + " s; a longer limit may move their stop points.</p>";
  return s;
}

}  // namespace rockcal::reports::sections
