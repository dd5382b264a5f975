#include "rockcal/core/scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "rockcal/core/format.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/material.h"
#include "rockcal/core/simulate.h"

namespace rockcal::core {

bool CrossesLine(const std::vector<Eigen::Vector2d>& line, const Eigen::Vector2d& p0,
                 const Eigen::Vector2d& p1, double* f) {
  // p0 + t d = a + u e, solved by cross products; a path parallel to a
  // segment does not cross it.
  auto cross = [](const Eigen::Vector2d& v, const Eigen::Vector2d& w) {
    return v.x() * w.y() - v.y() * w.x();
  };
  const Eigen::Vector2d d = p1 - p0;
  bool found = false;
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    const Eigen::Vector2d e = line[k + 1] - line[k], w = line[k] - p0;
    const double denom = cross(d, e);
    if (denom == 0.0) continue;
    const double t = cross(w, e) / denom, u = cross(w, d) / denom;
    if (t > 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0 && (!found || t < *f)) {
      *f = t;
      found = true;
    }
  }
  return found;
}

bool SimulationOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, double value, const char* rule) {
    std::ostringstream s;
    s << "simulation." << field << " = " << value << ": " << rule;
    *error = s.str();
    return false;
  };
  if (!(max_time > 0 && std::isfinite(max_time))) return fail("max_time", max_time, "must be > 0");
  if (!(stop_speed > 0)) return fail("stop_speed", stop_speed, "must be > 0");
  if (!(stop_duration > 0)) return fail("stop_duration", stop_duration, "must be > 0");
  if (stop_duration >= max_time)
    return fail("stop_duration", stop_duration,
                ("must be below max_time (" + FormatNumber(max_time) + " s)").c_str());
  if (steps_per_contact < 4) return fail("steps_per_contact", steps_per_contact, "must be >= 4");
  if (gentle_steps_per_contact != 0 && gentle_steps_per_contact < 2)
    return fail("gentle_steps_per_contact", gentle_steps_per_contact, "must be 0 (off) or >= 2");
  if (!(safety > 0 && safety <= 1)) return fail("safety", safety, "must be in (0, 1]");
  if (!(gentle_safety > 0 && gentle_safety <= 1))
    return fail("gentle_safety", gentle_safety, "must be in (0, 1]");
  if (!(rest_window >= 0 && std::isfinite(rest_window)))
    return fail("rest_window", rest_window, "must be >= 0 (0: off)");
  if (threads < 0) return fail("threads", threads, "must be >= 0 (0: all cores)");
  if (record.trajectories < 0)
    return fail("record.trajectories", record.trajectories, "must be >= 0");
  const bool sampled = record.trajectories > 0 || !record.trajectory_rocks.empty() ||
                       !record.trajectory_groups.empty();
  if (sampled && !(record.sample_seconds > 0))
    return fail("record.sample_seconds", record.sample_seconds, "must be > 0");
  for (std::size_t k = 0; k < record.trajectory_rocks.size(); ++k)
    if (record.trajectory_rocks[k] < 0 ||
        (k > 0 && record.trajectory_rocks[k] <= record.trajectory_rocks[k - 1]))
      return fail("record.trajectory_rocks", record.trajectory_rocks[k],
                  "must be rock indices >= 0 in ascending order");
  for (std::size_t k = 0; k < record.trajectory_groups.size(); ++k)
    if (record.trajectory_groups[k] < 0 ||
        (k > 0 && record.trajectory_groups[k] <= record.trajectory_groups[k - 1]))
      return fail("record.trajectory_groups", record.trajectory_groups[k],
                  "must be group indices >= 0 in ascending order");
  // The observed impacts to replay (docs/physics.md, "Replayed impacts"); the
  // group's index is checked against the scene's groups by Scene::IsValid.
  for (std::size_t k = 0; k < record.impacts.size(); ++k) {
    const ImpactReplay& impact = record.impacts[k];
    const std::string name = "record.impacts[" + std::to_string(k) + "].";
    if (impact.group < 0) return fail(name + "group", impact.group, "must be a group index >= 0");
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(impact.centre[c]))
        return fail(name + "centre", impact.centre[c], "must be finite");
      if (!std::isfinite(impact.velocity_in[c]))
        return fail(name + "velocity_in", impact.velocity_in[c], "must be finite");
      if (impact.spin && !std::isfinite((*impact.spin)[c]))
        return fail(name + "spin", (*impact.spin)[c], "must be finite");
    }
    if (impact.draws < 1 || impact.draws > kMaxImpactDraws)
      return fail(name + "draws", impact.draws,
                  ("must be 1 to " + std::to_string(kMaxImpactDraws)).c_str());
  }
  return true;
}

double Scene::EstimatedSteps() const {
  const double dt = SmallestContactStep(*this);
  if (!std::isfinite(dt)) return 0.0;
  return static_cast<double>(total_rocks()) * options.max_time / dt;
}

bool Scene::IsValid(std::string* error) const {
  if (!options.IsValid(error)) return false;
  if (!forest.IsValid(error)) return false;
  const std::size_t group_count = groups.size();
  for (std::size_t k = 0; k < options.record.impacts.size(); ++k)
    if (static_cast<std::size_t>(options.record.impacts[k].group) >= group_count) {
      *error = "simulation.record.impacts[" + std::to_string(k) +
               "].group = " + std::to_string(options.record.impacts[k].group) +
               ": must be one of the " + std::to_string(group_count) + " rock groups (0 to " +
               std::to_string(static_cast<long>(group_count) - 1) + ")";
      return false;
    }
  for (int g : options.record.trajectory_groups)
    if (static_cast<std::size_t>(g) >= group_count) {
      *error = "simulation.record.trajectory_groups has " + std::to_string(g) +
               ": must be one of the " + std::to_string(group_count) + " rock groups (0 to " +
               std::to_string(static_cast<long>(group_count) - 1) + ")";
      return false;
    }
  for (const Partition& p : partitions) {  // a barrier's line, height and capacity
    if (p.kind != Partition::Kind::kLine) continue;
    bool finite = true;
    for (const Eigen::Vector2d& v : p.line) finite = finite && v.allFinite();
    const char* rule = p.line.size() < 2 ? "a line of at least 2 vertices"
                       : !finite         ? "finite vertices"
                       : !(p.height > 0 && std::isfinite(p.height))     ? "a finite height > 0"
                       : !(p.capacity > 0 && std::isfinite(p.capacity)) ? "a finite capacity > 0"
                                                                        : nullptr;
    if (rule) {
      *error = "barrier " + p.id + " (" + std::to_string(p.line.size()) + " vertices, height " +
               FormatNumber(p.height) + " m, capacity " + FormatNumber(p.capacity) +
               " J): expected " + rule;
      return false;
    }
  }
  const int rocks = total_rocks();
  if (rocks < 1 || rocks > kMaxRocks) {
    *error = "the run has " + std::to_string(rocks) + " rocks; expected 1 to " +
             std::to_string(kMaxRocks);
    return false;
  }
  const double steps = EstimatedSteps();
  if (!(steps <= kMaxEstimatedSteps)) {
    std::ostringstream s;
    s << "the run would take up to " << steps << " steps (" << rocks << " rocks, max_time "
      << options.max_time << " s, smallest contact step " << options.max_time * rocks / steps
      << " s); expected at most " << kMaxEstimatedSteps
      << ": lengthen the contact time or shorten max_time";
    *error = s.str();
    return false;
  }
  return true;
}

void Scene::SetTotalRocks(int total) {
  const int old_total = total_rocks();
  std::vector<double> share;
  int assigned = 0;
  for (auto& g : groups) {
    share.push_back(static_cast<double>(total) * g.count / old_total);
    g.count = static_cast<int>(std::floor(share.back()));
    assigned += g.count;
  }
  while (assigned < total) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < share.size(); ++k)
      if (share[k] - groups[k].count > share[best] - groups[best].count) best = k;
    ++groups[best].count;
    share[best] = groups[best].count;  // its remainder is taken
    ++assigned;
  }
}

RockBody GroupRockBody(const RockGroup& group, int index, double u, double gravity) {
  if (!group.inventory.empty()) {
    const Block& b = group.inventory[static_cast<std::size_t>(index) % group.inventory.size()];
    if (b.shape == Shape::kBox) return MakeBoxBody(b.sides, b.mass);
    if (b.shape == Shape::kScanned && b.scanned) return ScannedBody(*b.scanned, 1.0, b.mass);
    // A named shape of size L1 at the block's mass.
    return WithMass(MakeRockBody(b.shape, b.sides.x(), 1.0, 1.0), b.mass);
  }
  const double size = group.size_min + u * (group.size_max - group.size_min);
  if (group.shape == Shape::kScanned && group.scanned) {
    const double scale = size / group.scanned->clump.hull_sides.x();
    const double volume = group.scanned->mass.volume * scale * scale * scale;
    return ScannedBody(*group.scanned, scale, group.unit_weight * volume / gravity);
  }
  return MakeRockBody(group.shape, size, group.unit_weight, gravity, group.box);
}

GroupExtent GroupBodies(const RockGroup& group, double gravity) {
  GroupExtent extent;
  const int n = group.inventory.empty() ? 2 : static_cast<int>(group.inventory.size());
  for (int k = 0; k < n; ++k) {
    const RockBody b = GroupRockBody(group, k, k == 0 ? 0.0 : 1.0, gravity);
    if (k == 0 || b.mass < extent.lightest.mass) extent.lightest = b;
    if (k == 0 || b.mass > extent.heaviest.mass) extent.heaviest = b;
    extent.max_element_radius = std::max(extent.max_element_radius, b.element_radius);
  }
  return extent;
}

std::vector<ShapeUse> Scene::ScannedShapes() const {
  std::vector<ShapeUse> uses;
  auto add = [&](const ScannedShape& s) {
    auto it = std::lower_bound(uses.begin(), uses.end(), s.name,
                               [](const ShapeUse& u, const std::string& n) { return u.name < n; });
    if (it == uses.end() || it->name != s.name) {
      ShapeUse u;
      u.name = s.name;
      u.file = s.file;
      u.first = &s;
      u.spheres = static_cast<int>(s.clump.centres.size());
      u.min_volume = u.max_volume = s.mass.volume;
      it = uses.insert(it, u);
    }
    ++it->uses;
    it->volume_error = std::max(it->volume_error, std::abs(s.clump.volume_error));
    it->moment_error = std::max(it->moment_error, s.clump.moment_error);
    it->side_error = std::max(it->side_error, s.clump.side_error);
    it->min_volume = std::min(it->min_volume, s.mass.volume);
    it->max_volume = std::max(it->max_volume, s.mass.volume);
  };
  for (const RockGroup& g : groups) {
    if (g.scanned) add(*g.scanned);
    for (const Block& b : g.inventory)
      if (b.scanned) add(*b.scanned);
  }
  return uses;
}

int Scene::total_rocks() const {
  int n = 0;
  for (const auto& g : groups) n += g.count;
  return n;
}

}  // namespace rockcal::core
