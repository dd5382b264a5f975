#include "recording.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "flight.h"

namespace rockcal::core {

Recorder::Recorder(const Scene& scene, const Terrain& terrain, const RockBody& body, bool cluster,
                   RockRecord* rec)
    : scene_(scene),
      opt_(scene.options.record),
      terrain_(terrain),
      body_(body),
      cluster_(cluster),
      gravity_(0, 0, -scene.gravity),
      inv_inertia_(body.inertia.cwiseInverse()),
      rec_(rec) {
  for (std::size_t p = 0; p < scene.partitions.size(); ++p)
    if (scene.partitions[p].kind == Partition::Kind::kLine && scene.partitions[p].stops)
      stopping_.push_back(static_cast<int>(p));
}

void Recorder::Start(const RockState& s) {
  const int np = static_cast<int>(scene_.partitions.size());
  if (opt_.partitions) rec_->crossings.assign(np, Crossing{});
  rec_->trees.assign(opt_.trees.size(), Crossing{});
  trajectory_ =
      opt_.trajectories > rec_->rock ||
      std::binary_search(opt_.trajectory_rocks.begin(), opt_.trajectory_rocks.end(), rec_->rock) ||
      std::binary_search(opt_.trajectory_groups.begin(), opt_.trajectory_groups.end(), rec_->group);
  met_.assign(stopping_.size(), 0);
  crossed_at_.assign(stopping_.size(), -1.0);
  next_sample_ = 0.0;
  Sample(s);
  if (opt_.passages) VisitAt(s, s, true);
}

bool Recorder::Advance(const RockState& s0, const RockState& s, bool flew, RockState* stopped) {
  double f = 0.0;
  int at = -1;
  Crossing crossing;
  if (!stopping_.empty() && Caught(s0, s, flew, &f, &at, &crossing)) {
    *stopped = Between(s0, s, f, flew, /*turn=*/true);
    rec_->stopped_by = at;
    if (opt_.partitions) rec_->crossings[static_cast<std::size_t>(at)] = crossing;
    Track(s0, *stopped, flew);
    return true;
  }
  Track(s0, s, flew);
  return false;
}

bool Recorder::Caught(const RockState& s0, const RockState& s, bool flew, double* f, int* at,
                      Crossing* crossing) {
  bool caught = false;
  for (std::size_t k = 0; k < stopping_.size(); ++k) {
    double& fk = crossed_at_[k];
    fk = -1.0;              // not crossed within this advance
    if (met_[k]) continue;  // a barrier is met once: one the rock passed does not catch it later
    const Partition& part = scene_.partitions[static_cast<std::size_t>(stopping_[k])];
    if (!CrossesLine(part.line, s0.x.head<2>(), s.x.head<2>(), &fk)) {
      fk = -1.0;
      continue;
    }
    if (caught && fk >= *f) continue;
    const Crossing c = Record(s0, Between(s0, s, fk, flew));
    if (c.height - body_.bounding_radius > part.height || c.energy > part.capacity) continue;
    *f = fk;
    *at = stopping_[k];
    *crossing = c;
    caught = true;
  }
  // The barriers the rock crossed before it stopped (all it crossed, if it
  // did not) are met.
  for (std::size_t k = 0; k < stopping_.size(); ++k)
    if (crossed_at_[k] >= 0.0 && (!caught || crossed_at_[k] <= *f)) met_[k] = 1;
  return caught;
}

void Recorder::Track(const RockState& s0, const RockState& s, bool flew) {
  const auto& parts = scene_.partitions;
  if (opt_.partitions) {
    for (std::size_t p = 0; p < parts.size(); ++p) {
      Crossing& cr = rec_->crossings[p];
      if (cr.crossed) continue;
      const Partition& part = parts[p];
      double f0, f1;
      if (part.kind == Partition::Kind::kLine) {
        double f = 0.0;
        if (CrossesLine(part.line, s0.x.head<2>(), s.x.head<2>(), &f))
          cr = Record(s0, Between(s0, s, f, flew));
        continue;
      }
      if (part.kind == Partition::Kind::kX) {
        f0 = s0.x.x() - part.value;
        f1 = s.x.x() - part.value;
      } else {
        double z0, z1;
        if (!ElevationAt(s0.x, &z0) || !ElevationAt(s.x, &z1)) continue;
        f0 = z0 - part.value;
        f1 = z1 - part.value;
      }
      if ((f0 < 0) != (f1 < 0)) cr = Record(s0, Between(s0, s, f0 / (f0 - f1), flew));
    }
  }
  const auto& trees = opt_.trees;
  for (std::size_t k = 0; k < trees.size(); ++k) {
    Crossing& cr = rec_->trees[k];
    if (cr.crossed) continue;
    // First time the plan path (straight over one advance) comes within
    // reach of the trunk.
    const double reach = trees[k].radius + body_.bounding_radius;
    const Eigen::Vector2d p0(s0.x.x() - trees[k].x, s0.x.y() - trees[k].y);
    const Eigen::Vector2d d(s.x.x() - s0.x.x(), s.x.y() - s0.x.y());
    const double aa = d.squaredNorm(), bb = 2.0 * p0.dot(d), cc = p0.squaredNorm() - reach * reach;
    if (cc <= 0.0) continue;  // started inside: not a passage
    const double disc = bb * bb - 4.0 * aa * cc;
    if (aa <= 0.0 || disc < 0.0) continue;
    const double f = (-bb - std::sqrt(disc)) / (2.0 * aa);
    if (f >= 0.0 && f <= 1.0) cr = Record(s0, Between(s0, s, f, flew));
  }
  if (opt_.passages) Visit(s0, s, flew);
  if (trajectory_) {
    while (next_sample_ <= s.t) {
      const double f = s.t > s0.t ? (next_sample_ - s0.t) / (s.t - s0.t) : 1.0;
      Sample(Between(s0, s, std::clamp(f, 0.0, 1.0), flew, /*turn=*/true));
    }
  }
}

bool Recorder::ElevationAt(const Eigen::Vector3d& x, double* z) {
  if (x.x() == elevation_at_.x() && x.y() == elevation_at_.y()) {
    *z = elevation_;
    return true;
  }
  if (!terrain_.Elevation(x.x(), x.y(), z)) return false;
  elevation_at_ = x.head<2>();
  elevation_ = *z;
  return true;
}

void Recorder::Visit(const RockState& s0, const RockState& s, bool flew) {
  // Quarter cells along the advance's plan path (a small step: none).
  const double quarter = 0.25 * scene_.grid.spacing;
  const double run2 = flew ? (s.x.head<2>() - s0.x.head<2>()).squaredNorm() : 0.0;
  if (run2 <= quarter * quarter) {  // kept when over another cell or an eighth of one away
    VisitAt(s0, s, /*every=*/false);
    return;
  }
  const int n = static_cast<int>(std::ceil(std::sqrt(run2) / quarter));
  for (int k = 1; k < n; ++k) VisitAt(s0, Between(s0, s, static_cast<double>(k) / n, true), true);
  VisitAt(s0, s, true);
}

void Recorder::VisitAt(const RockState& s0, const RockState& s, bool every) {
  const HeightGrid& g = scene_.grid;
  const double eighth2 = 0.015625 * g.spacing * g.spacing;
  // Over the last kept sample's cell (well inside it) and within an eighth
  // of a cell of that sample: skipped, as below, without finding the cell.
  if (!every && s.x.x() > last_cell_low_.x() && s.x.x() < last_cell_high_.x() &&
      s.x.y() > last_cell_low_.y() && s.x.y() < last_cell_high_.y() &&
      (s.x.head<2>() - last_visit_).squaredNorm() < eighth2)
    return;
  const double fi = std::round((s.x.x() - g.x0) / g.spacing);
  const double fj = std::round((s.x.y() - g.y0) / g.spacing);
  if (!(fi >= 0.0 && fj >= 0.0 && fi < g.nx && fj < g.ny)) return;  // off the grid
  const int cell = static_cast<int>(fj) * g.nx + static_cast<int>(fi);
  if (std::isnan(g.z[static_cast<std::size_t>(cell)])) return;  // over a hole: no map there
  std::vector<CellVisit>& cells = rec_->cells;
  // The cell's visit if it is one of the last few (a rock at rest on a cell
  // border goes back and forth); -1: a new one.
  int at = -1;
  for (int k = static_cast<int>(cells.size()) - 1;
       k >= 0 && k + 4 >= static_cast<int>(cells.size()); --k) {
    if (cells[static_cast<std::size_t>(k)].cell == cell) {
      at = k;
      break;
    }
  }
  if (at >= 0 && !every && (s.x.head<2>() - last_visit_).squaredNorm() < eighth2)
    return;  // within an eighth of a cell of the last sample kept
  last_visit_ = s.x.head<2>();
  // The cell's extent, a millionth of a cell inside its borders, where
  // rounding cannot place a point in another cell.
  const Eigen::Vector2d centre(g.x(static_cast<int>(fi)), g.y(static_cast<int>(fj)));
  const double half = 0.5 * (1.0 - 1e-6) * g.spacing;
  last_cell_low_ = centre.array() - half;
  last_cell_high_ = centre.array() + half;
  const Crossing c = Record(s0, s);
  if (at < 0) {
    cells.push_back({cell, c.height, c.energy, c.speed});
  } else {
    CellVisit& v = cells[static_cast<std::size_t>(at)];
    v.height = std::max(v.height, c.height);
    v.energy = std::max(v.energy, c.energy);
    v.speed = std::max(v.speed, c.speed);
  }
}

void Recorder::Finish(const RockState& s) {
  if (opt_.passages) {  // one visit per cell, by cell: the largest values of its passes
    std::vector<CellVisit>& cells = rec_->cells;
    std::stable_sort(cells.begin(), cells.end(),
                     [](const CellVisit& a, const CellVisit& b) { return a.cell < b.cell; });
    std::size_t out = 0;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (out > 0 && cells[out - 1].cell == cells[k].cell) {
        cells[out - 1].height = std::max(cells[out - 1].height, cells[k].height);
        cells[out - 1].energy = std::max(cells[out - 1].energy, cells[k].energy);
        cells[out - 1].speed = std::max(cells[out - 1].speed, cells[k].speed);
      } else {
        cells[out++] = cells[k];
      }
    }
    cells.resize(out);
  }
  if (trajectory_) Sample(s, /*force=*/true);
}

RockState Recorder::Between(const RockState& s0, const RockState& s1, double f, bool flew,
                            bool turn) const {
  RockState s = s0;
  const double tau = f * (s1.t - s0.t);
  s.t = s0.t + tau;
  if (flew) {  // the exact flight: a parabola, a torque-free turn
    s.x = s0.x + s0.v * tau + 0.5 * gravity_ * tau * tau;
    s.v = s0.v + gravity_ * tau;
    if (cluster_ && turn) RotateFree(body_, inv_inertia_, tau, kFlightRotationAngle, &s);
    return s;
  }
  s.x = s0.x + f * (s1.x - s0.x);
  s.v = s0.v + f * (s1.v - s0.v);
  s.w = s0.w + f * (s1.w - s0.w);
  s.q = s1.q;
  return s;
}

double Recorder::GroundBelow(const RockState& s0, double x, double y) const {
  double ground = std::numeric_limits<double>::quiet_NaN();  // if s0 were off the slope
  if (terrain_.GroundHeight(x, y, &ground)) return ground;
  // Over a hole: bisect the plan path for where it left the slope (an
  // advance spans at most a cell, so 30 halvings place it within a micron).
  double on = 0.0, off = 1.0;
  for (int k = 0; k < 30; ++k) {
    const double mid = 0.5 * (on + off);
    const double xm = s0.x.x() + mid * (x - s0.x.x()), ym = s0.x.y() + mid * (y - s0.x.y());
    (terrain_.OnSlope(xm, ym) ? on : off) = mid;
  }
  const bool found = terrain_.GroundHeight(s0.x.x() + on * (x - s0.x.x()),
                                           s0.x.y() + on * (y - s0.x.y()), &ground);
  assert(found && "every advance starts on the slope");
  (void)found;
  return ground;
}

Crossing Recorder::Record(const RockState& s0, const RockState& s) const {
  Crossing c;
  c.crossed = true;
  c.height = s.x.z() - GroundBelow(s0, s.x.x(), s.x.y());
  c.speed = s.v.norm();
  c.energy = cluster_ ? KineticEnergy<true>(body_, s) : KineticEnergy<false>(body_, s);
  c.point = s.x;
  return c;
}

void Recorder::Sample(const RockState& s, bool force) {
  if (!trajectory_) return;
  if (!force && s.t + 1e-12 < next_sample_) return;
  rec_->trajectory.push_back(
      {s.t, s.x, s.v, s.w, Eigen::Vector4d(s.q.w(), s.q.x(), s.q.y(), s.q.z())});
  next_sample_ += opt_.sample_seconds;
}

}  // namespace rockcal::core
