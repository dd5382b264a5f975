// The project and site section of report.html: the site tables and the run.
#include "sections.h"

namespace rockcal::reports::sections {

std::string SiteSection(const Context& c) {
  html::PartitionPassage passage;
  for (const auto& ps : c.stats.partitions) passage.passed.push_back(ps.passed);
  passage.rocks = Rocks(c);
  std::string s = html::SiteTables(c.scene, c.in.site_file, c.in.units, &passage);

  // The run.
  const core::SimulationOptions& opt = c.scene.options;
  const core::SimulationResult& r = c.result;
  const core::RunFigures& f = r.figures;
  s += "<h3>Simulation</h3><table class=\"kv\">";
  s += Kv("Random seed", RefSpan(Ref("summary.json", "/seed"), static_cast<double>(opt.seed),
                                 std::to_string(opt.seed)));
  s += Kv("Rocks",
          RefSpan(Ref("summary.json", "/rocks"), Rocks(c), Int(Rocks(c))) + ": " +
              RefSpan(Ref("summary.json", "/outcomes/stopped"), c.stopped, Int(c.stopped)) +
              " stopped, " + RefSpan(Ref("summary.json", "/outcomes/left"), c.left, Int(c.left)) +
              " left the slope, " +
              RefSpan(Ref("summary.json", "/outcomes/timeout"), c.timeout, Int(c.timeout)) +
              " still moving at the time limit");
  // The rest shortcut (SimulationOptions::rest_window) ends a still rock
  // at the time the rule would; the reader is told it was not simulated.
  const std::string rest =
      opt.rest_window > 0 && !opt.reference_path
          ? "; a rock still (every point slower than " + Label(0.1 * opt.stop_speed) +
                " m/s, no contact sliding) for " + Label(opt.rest_window) +
                " s is taken to stay so and ends then, at the time the rule would end it"
          : std::string();
  s += Kv("Stopping rule",
          Escape("speed below " + Label(opt.stop_speed) + " m/s for " + Label(opt.stop_duration) +
                 " s" + rest + "; time limit " + Label(opt.max_time) + " s per rock"));
  s += Kv("Contact time step",
          RefSpan(Ref("summary.json", "/dt_seconds"), f.dt_min, Label(f.dt_min, 3)) +
              (f.dt_max > f.dt_min ? " to " + Escape(Label(f.dt_max, 3)) : std::string()) +
              " s (at most t_c/" + Int(opt.steps_per_contact) + ", " + Escape(Label(opt.safety)) +
              " of the critical step); free flight advanced exactly");
  s += Kv("Work",
          RefSpan(Ref("summary.json", "/steps"), static_cast<double>(f.steps), Int(f.steps)) +
              " contact steps and " + Escape(Int(f.flights)) + " free flights");
  s += Kv(
      "Wall time",
      RefSpan(Ref("summary.json", "/wall_seconds"), r.wall_seconds, Show(r.wall_seconds)) + " s");
  s += Kv("Energy check",
          "largest rise of mechanical energy " +
              RefSpan(Ref("summary.json", "/energy_check/max_relative_gain"),
                      f.max_relative_energy_gain, Label(f.max_relative_energy_gain, 3)) +
              " of the rock's largest kinetic energy (see the diagnostics)");
  s += "</table>";
  s += html::SiteNotes(c.in.notes);
  return s;
}

}  // namespace rockcal::reports::sections
