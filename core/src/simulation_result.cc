// What a simulation returns, summed and summarised: outcome names, a rock's
// run figures and their sum, blocks of rocks joined, the statistics, the
// fence check and the runout (simulate.h).
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rockcal/core/numbers.h"
#include "rockcal/core/simulate.h"
#include "rockcal/core/statistics.h"

namespace rockcal::core {
namespace {

}  // namespace

const char* OutcomeName(Outcome outcome) {
  switch (outcome) {
    case Outcome::kStopped:
      return "stopped";
    case Outcome::kLeft:
      return "left";
    case Outcome::kTimeout:
      return "timeout";
  }
  return "?";
}

int SimulationResult::count(Outcome o) const {
  int n = 0;
  for (const auto& r : rocks) n += r.outcome == o;
  return n;
}

RunFigures RunFigures::OfRock(const RockRecord& r, bool shrunk) {
  RunFigures f;
  f.rocks = 1;
  f.steps = r.steps;
  f.flights = r.flights;
  f.gentle_steps = r.gentle_steps;
  f.retried_steps = r.retried_steps;
  f.dt_min = f.dt_max = r.dt;
  f.dt_shrunk = shrunk ? 1 : 0;
  f.tunneled = r.tunneled ? 1 : 0;
  if (!std::isfinite(r.max_relative_energy_gain) || !r.stop.allFinite())
    f.non_finite = 1;
  else
    f.max_relative_energy_gain = r.max_relative_energy_gain;
  f.max_penetration = r.max_penetration;
  return f;
}

RunFigures& RunFigures::operator+=(const RunFigures& o) {
  if (o.rocks == 0) return *this;
  dt_min = rocks == 0 ? o.dt_min : std::min(dt_min, o.dt_min);
  dt_max = rocks == 0 ? o.dt_max : std::max(dt_max, o.dt_max);
  rocks += o.rocks;
  steps += o.steps;
  flights += o.flights;
  gentle_steps += o.gentle_steps;
  retried_steps += o.retried_steps;
  dt_shrunk += o.dt_shrunk;
  max_relative_energy_gain = std::max(max_relative_energy_gain, o.max_relative_energy_gain);
  max_penetration = std::max(max_penetration, o.max_penetration);
  non_finite += o.non_finite;
  tunneled += o.tunneled;
  return *this;
}

SimulationResult JoinRockBlocks(std::vector<SimulationResult> blocks) {
  SimulationResult out;
  for (SimulationResult& b : blocks) {
    out.wall_seconds = std::max(out.wall_seconds, b.wall_seconds);
    out.busy_seconds += b.busy_seconds;
    out.cells_recorded = out.cells_recorded || b.cells_recorded;
    out.strikes_recorded = out.strikes_recorded || b.strikes_recorded;
    if (out.impacts.empty()) out.impacts = std::move(b.impacts);  // the first block's
    if (b.rocks.empty()) continue;
    out.figures += b.figures;
    if (out.rocks.empty()) {
      out.rocks = std::move(b.rocks);
    } else {
      out.rocks.insert(out.rocks.end(), std::make_move_iterator(b.rocks.begin()),
                       std::make_move_iterator(b.rocks.end()));
    }
  }
  return out;
}

ResultStats ComputeStats(const Scene& scene, const SimulationResult& result) {
  ResultStats stats;
  for (std::size_t p = 0; p < scene.partitions.size(); ++p) {
    PartitionStats ps;
    ps.id = scene.partitions[p].id;
    std::vector<double> h, v, e;
    for (const auto& r : result.rocks) {
      if (p < r.crossings.size() && r.crossings[p].crossed) {
        h.push_back(r.crossings[p].height);
        v.push_back(r.crossings[p].speed);
        e.push_back(r.crossings[p].energy);
      }
    }
    ps.passed = static_cast<int>(h.size());
    ps.height = Summarize(h);
    ps.velocity = Summarize(v);
    ps.energy = Summarize(e);
    stats.partitions.push_back(ps);
  }
  std::vector<double> xs;
  for (const auto& r : result.rocks)
    if (r.outcome == Outcome::kStopped) xs.push_back(r.stop.x());
  stats.runout_x = Summarize(xs);
  stats.runout = ComputeRunout(result.rocks);
  return stats;
}

FenceCheck CheckFence(const SimulationResult& result, std::size_t partition, double height,
                      double capacity) {
  FenceCheck f;
  for (const RockRecord& r : result.rocks) {
    if (partition >= r.crossings.size() || !r.crossings[partition].crossed) continue;
    const Crossing& c = r.crossings[partition];
    const bool over = c.height - r.bounding_radius > height, energy = c.energy > capacity;
    ++f.passed;
    f.over += over;
    f.over_by_centre += c.height > height;
    f.over_by_top += c.height + r.bounding_radius > height;
    f.over_capacity += energy;
    f.defeated += over || energy;
  }
  return f;
}

std::vector<BarrierStats> ComputeBarriers(const Scene& scene, const SimulationResult& result) {
  std::vector<BarrierStats> out;
  for (std::size_t p = 0; p < scene.partitions.size(); ++p) {
    const Partition& part = scene.partitions[p];
    if (part.kind != Partition::Kind::kLine) continue;
    BarrierStats b;
    b.partition = p;
    b.check = CheckFence(result, p, part.height, part.capacity);
    std::vector<double> lowest, centre, energy;
    for (const RockRecord& r : result.rocks) {
      b.stopped += r.stopped_by == static_cast<int>(p);
      if (p >= r.crossings.size() || !r.crossings[p].crossed) continue;
      lowest.push_back(r.crossings[p].height - r.bounding_radius);
      centre.push_back(r.crossings[p].height);
      energy.push_back(r.crossings[p].energy);
    }
    b.lowest_p95 = QuantileOf(&lowest, 0.95);
    b.lowest_p99 = QuantileOf(&lowest, 0.99);
    b.centre_p95 = QuantileOf(&centre, 0.95);
    b.centre_p99 = QuantileOf(&centre, 0.99);
    b.energy_p95 = QuantileOf(&energy, 0.95);
    b.energy_p99 = QuantileOf(&energy, 0.99);
    out.push_back(b);
  }
  return out;
}

double RunoutDistance(const RockRecord& rock) {
  return std::hypot(rock.stop.x() - rock.start.x(), rock.stop.y() - rock.start.y());
}

double TravelAngleDeg(const RockRecord& rock) {
  const double drop = rock.start.z() - rock.stop.z();
  const double d = RunoutDistance(rock);
  if (d == 0.0) return 90.0;
  return std::atan2(drop, d) * 180.0 / kPi;
}

RunoutStats ComputeRunout(const std::vector<RockRecord>& rocks) {
  RunoutStats out;
  std::vector<double> distance, angle;
  for (const RockRecord& r : rocks) {
    ++out.rocks;
    if (r.outcome == Outcome::kLeft) {
      ++out.beyond_edge;
      continue;
    }
    distance.push_back(RunoutDistance(r));
    angle.push_back(TravelAngleDeg(r));
  }
  out.distance_m = SummarizeWithBeyond(std::move(distance), out.beyond_edge, true);
  out.travel_angle_deg = SummarizeWithBeyond(std::move(angle), out.beyond_edge, false);
  return out;
}

}  // namespace rockcal::core
