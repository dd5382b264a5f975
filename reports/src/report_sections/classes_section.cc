// The section of a site whose materials took values from a class table
// (sites/class_table.h): per material the class, the table, each value
// taken (its median and the interval drawn from, how many sites and values
// support it), the site's own values that override the class's, and that a
// calibration against field data would narrow them (docs/default-table.md).
#include "sections.h"

namespace rockcal::reports::sections {

std::string ClassesSection(const Context& c) {
  const ClassRun& run = *c.in.classes;
  std::string s =
      "<p>These materials have no values of their own: they name a class, and take its values "
      "from a table that rockcal built from calibrations of real sites (" +
      std::string(run.drawn ? "drawn within each value's interval, a parameter set per draw "
                              "(section <i>Draws from the class table and bands</i>)"
                            : "its medians (--class-values median)") +
      "). <b>The values are a class's, not this site's: a calibration of this site against "
      "field data (rockcal calibrate) would narrow them.</b> The interval is the envelope of the "
      "calibrations' posterior 5–95 % intervals where the table has them, else the range of the "
      "calibrated values.</p>";
  s += "<table><thead><tr>" + Th("material") + Th("class") + Th("table") + Th("parameter") +
       Th("median (used" + std::string(run.drawn ? " by --class-values median)" : ")")) +
       Th("interval" + std::string(run.drawn ? " (drawn in)" : "")) + Th("sites") + Th("values") +
       "</tr></thead><tbody>";
  for (const sites::ClassMaterial& m : *run.materials) {
    for (const sites::ClassRow& r : m.from_table) {
      const core::MaterialFieldInfo* f = core::FindMaterialField(r.parameter);
      const char* unit = f ? core::SiUnitName(f->unit) : "";
      const std::string u = *unit ? std::string(" ") + unit : std::string();
      s += "<tr>" + Td(Escape(m.material)) + Td(Escape(m.material_class)) + Td(Escape(m.table)) +
           Td(Escape(f ? f->label : r.parameter)) + Td(Escape(FormatNumber(r.median, "%.4g") + u)) +
           Td(r.low ? Escape(FormatNumber(*r.low, "%.4g") + " – " + FormatNumber(*r.high, "%.4g") +
                             u + " (" + r.interval + ")")
                    : std::string("none (one value)")) +
           Td(Int(r.sites)) + Td(Int(r.values)) + "</tr>";
    }
  }
  s += "</tbody></table>";
  for (const sites::ClassMaterial& m : *run.materials) {
    if (!m.description.empty())
      s += "<p>Class <b>" + Escape(m.material_class) + "</b>: " + Escape(m.description) + "</p>";
    if (!m.explicit_fields.empty()) {
      std::string list;
      for (const std::string& f : m.explicit_fields) list += (list.empty() ? "" : ", ") + f;
      s += "<p>Material " + Escape(m.material) + ": the site's own " + Escape(list) +
           " override the class's.</p>";
    }
    for (const std::string& n : m.notes)
      s += "<p>Material " + Escape(m.material) + ": " + Escape(n) + ".</p>";
  }
  return s;
}

}  // namespace rockcal::reports::sections
