// The numerical diagnostics section of report.html (diagnostics.json).
#include "rockcal/reports/simulation_outputs.h"
#include "sections.h"

namespace rockcal::reports::sections {

std::string DiagnosticsSection(const Context& c) {
  using Check = DiagnosticFigure::Check;
  std::string s =
      "<p>The numerical health of the run (diagnostics.json): the engine picks its own stable step "
      "and "
      "reports where it had to work hard.</p><table><thead><tr>" +
      Th("quantity") + Th("value") + Th("check") + "</tr></thead><tbody>";
  for (const DiagnosticFigure& f : DiagnosticFigures(c.scene, c.result)) {
    const double v = f.value;
    std::string verdict = "";
    if (f.check == Check::kZero) verdict = v == 0 ? "OK" : "FAILED: must be 0";
    if (f.check == Check::kBelow)
      verdict =
          v <= f.limit ? "OK (below " + Label(f.limit) + ")" : "check: above " + Label(f.limit);
    s += "<tr>" + Td(f.what) +
         RefCell(Ref("diagnostics.json", std::string("/") + f.key), v,
                 f.integer ? Int(static_cast<long>(v)) : Label(v, 3)) +
         "<td class=\"" +
         (verdict.rfind("OK", 0) == 0 ? "ok"
          : verdict.empty()           ? ""
                                      : "bad") +
         "\">" + Escape(verdict) + "</td></tr>";
  }
  s += "</tbody></table>";
  if (c.timeout > 0)
    s += "<p class=\"warn\">" + Int(c.timeout) + (c.timeout == 1 ? " rock was" : " rocks were") +
         " still moving at the time limit of " + Label(c.scene.options.max_time) +
         " s; a longer limit may move their stop points.</p>";
  return s;
}

}  // namespace rockcal::reports::sections
