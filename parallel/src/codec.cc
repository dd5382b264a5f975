// Plain values and simulation records as bytes: what the ranks exchange.
// Doubles travel as their bytes, so a decoded record is the encoded one bit
// for bit (all ranks of a job share one architecture).
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "rockcal/parallel/parallel.h"

namespace rockcal::parallel {
namespace {

void Vector3(Writer* w, const Eigen::Vector3d& v) {
  for (int k = 0; k < 3; ++k) w->Double(v[k]);
}
Eigen::Vector3d Vector3(Reader* r) {
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) v[k] = r->Double();
  return v;
}

void Crossings(Writer* w, const std::vector<core::Crossing>& list) {
  w->Int(static_cast<long long>(list.size()));
  for (const core::Crossing& c : list) {
    w->Int(c.crossed ? 1 : 0);
    w->Double(c.height);
    w->Double(c.speed);
    w->Double(c.energy);
    Vector3(w, c.point);
  }
}
std::vector<core::Crossing> Crossings(Reader* r) {
  std::vector<core::Crossing> list(static_cast<std::size_t>(r->Int()));
  for (core::Crossing& c : list) {
    c.crossed = r->Int() != 0;
    c.height = r->Double();
    c.speed = r->Double();
    c.energy = r->Double();
    c.point = Vector3(r);
  }
  return list;
}

void Record(Writer* w, const core::RockRecord& rec) {
  w->Int(rec.rock);
  w->Int(rec.group);
  w->Int(static_cast<long long>(rec.shape));
  w->Double(rec.size);
  w->Double(rec.mass);
  w->Double(rec.bounding_radius);
  w->Int(static_cast<long long>(rec.outcome));
  Vector3(w, rec.start);
  Vector3(w, rec.stop);
  w->Double(rec.time);
  w->Int(rec.steps);
  w->Int(rec.gentle_steps);
  w->Int(rec.retried_steps);
  w->Int(rec.flights);
  w->Double(rec.dt);
  w->Double(rec.max_relative_energy_gain);
  w->Double(rec.max_penetration);
  w->Int(rec.tunneled ? 1 : 0);
  w->Int(rec.stopped_by);
  Crossings(w, rec.crossings);
  Crossings(w, rec.trees);
  w->Int(static_cast<long long>(rec.cells.size()));
  for (const core::CellVisit& c : rec.cells) {
    w->Int(c.cell);
    w->Double(c.height);
    w->Double(c.energy);
    w->Double(c.speed);
  }
  w->Int(static_cast<long long>(rec.trajectory.size()));
  for (const core::TrajectorySample& s : rec.trajectory) {
    w->Double(s.t);
    Vector3(w, s.x);
    Vector3(w, s.v);
    Vector3(w, s.w);
    for (int k = 0; k < 4; ++k) w->Double(s.q[k]);
  }
  w->Int(static_cast<long long>(rec.strikes.size()));
  for (const core::TreeStrike& s : rec.strikes) {
    w->Int(s.tree);
    Vector3(w, s.point);
    w->Double(s.height);
    w->Double(s.speed);
    w->Double(s.energy);
    w->Double(s.absorbed);
    w->Int(s.broken ? 1 : 0);
  }
}

core::RockRecord Record(Reader* r) {
  core::RockRecord rec;
  rec.rock = static_cast<int>(r->Int());
  rec.group = static_cast<int>(r->Int());
  rec.shape = static_cast<core::Shape>(r->Int());
  rec.size = r->Double();
  rec.mass = r->Double();
  rec.bounding_radius = r->Double();
  rec.outcome = static_cast<core::Outcome>(r->Int());
  rec.start = Vector3(r);
  rec.stop = Vector3(r);
  rec.time = r->Double();
  rec.steps = static_cast<long>(r->Int());
  rec.gentle_steps = static_cast<long>(r->Int());
  rec.retried_steps = static_cast<long>(r->Int());
  rec.flights = static_cast<long>(r->Int());
  rec.dt = r->Double();
  rec.max_relative_energy_gain = r->Double();
  rec.max_penetration = r->Double();
  rec.tunneled = r->Int() != 0;
  rec.stopped_by = static_cast<int>(r->Int());
  rec.crossings = Crossings(r);
  rec.trees = Crossings(r);
  rec.cells.resize(static_cast<std::size_t>(r->Int()));
  for (core::CellVisit& c : rec.cells) {
    c.cell = static_cast<int>(r->Int());
    c.height = r->Double();
    c.energy = r->Double();
    c.speed = r->Double();
  }
  rec.trajectory.resize(static_cast<std::size_t>(r->Int()));
  for (core::TrajectorySample& s : rec.trajectory) {
    s.t = r->Double();
    s.x = Vector3(r);
    s.v = Vector3(r);
    s.w = Vector3(r);
    for (int k = 0; k < 4; ++k) s.q[k] = r->Double();
  }
  rec.strikes.resize(static_cast<std::size_t>(r->Int()));
  for (core::TreeStrike& s : rec.strikes) {
    s.tree = static_cast<int>(r->Int());
    s.point = Vector3(r);
    s.height = r->Double();
    s.speed = r->Double();
    s.energy = r->Double();
    s.absorbed = r->Double();
    s.broken = r->Int() != 0;
  }
  return rec;
}

void Figures(Writer* w, const core::RunFigures& f) {
  w->Int(f.rocks);
  w->Int(f.steps);
  w->Int(f.flights);
  w->Int(f.gentle_steps);
  w->Int(f.retried_steps);
  w->Double(f.dt_min);
  w->Double(f.dt_max);
  w->Int(f.dt_shrunk);
  w->Double(f.max_relative_energy_gain);
  w->Double(f.max_penetration);
  w->Int(f.non_finite);
  w->Int(f.tunneled);
}

core::RunFigures Figures(Reader* r) {
  core::RunFigures f;
  f.rocks = static_cast<int>(r->Int());
  f.steps = static_cast<long>(r->Int());
  f.flights = static_cast<long>(r->Int());
  f.gentle_steps = static_cast<long>(r->Int());
  f.retried_steps = static_cast<long>(r->Int());
  f.dt_min = r->Double();
  f.dt_max = r->Double();
  f.dt_shrunk = static_cast<int>(r->Int());
  f.max_relative_energy_gain = r->Double();
  f.max_penetration = r->Double();
  f.non_finite = static_cast<int>(r->Int());
  f.tunneled = static_cast<int>(r->Int());
  return f;
}

}  // namespace

void Writer::Int(long long v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof v); }
void Writer::Double(double v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof v); }
void Writer::Doubles(const std::vector<double>& v) {
  Int(static_cast<long long>(v.size()));
  for (double x : v) Double(x);
}
void Writer::String(const std::string& v) {
  Int(static_cast<long long>(v.size()));
  bytes_ += v;
}

void Reader::Take(void* to, std::size_t n) {
  if (n > bytes_.size() - at_) throw std::runtime_error("parallel: a message ended early");
  std::memcpy(to, bytes_.data() + at_, n);
  at_ += n;
}
long long Reader::Int() {
  long long v = 0;
  Take(&v, sizeof v);
  return v;
}
double Reader::Double() {
  double v = 0.0;
  Take(&v, sizeof v);
  return v;
}
std::vector<double> Reader::Doubles() {
  const long long n = Int();
  if (n < 0 || static_cast<unsigned long long>(n) > (bytes_.size() - at_) / sizeof(double))
    throw std::runtime_error("parallel: a message ended early");
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) x = Double();
  return v;
}
std::string Reader::String() {
  const long long n = Int();
  if (n < 0 || static_cast<unsigned long long>(n) > bytes_.size() - at_)
    throw std::runtime_error("parallel: a message ended early");
  std::string s = bytes_.substr(at_, static_cast<std::size_t>(n));
  at_ += static_cast<std::size_t>(n);
  return s;
}

std::string EncodeResult(const core::SimulationResult& result) {
  Writer w;
  w.Int(static_cast<long long>(result.rocks.size()));
  for (const core::RockRecord& rec : result.rocks) Record(&w, rec);
  Figures(&w, result.figures);
  w.Double(result.wall_seconds);
  w.Double(result.busy_seconds);
  w.Int(result.cells_recorded ? 1 : 0);
  w.Int(result.strikes_recorded ? 1 : 0);
  w.Int(static_cast<long long>(result.impacts.size()));
  for (const core::ImpactRebound& impact : result.impacts) {
    std::vector<double> v(impact.normal.data(), impact.normal.data() + 3);
    for (std::size_t d = 0; d < impact.velocity.size(); ++d) {
      v.insert(v.end(), impact.velocity[d].data(), impact.velocity[d].data() + 3);
      v.push_back(impact.left[d]);
    }
    w.Doubles(v);
  }
  return w.bytes();
}

core::SimulationResult DecodeResult(const std::string& bytes) {
  Reader r(bytes);
  core::SimulationResult result;
  const long long n = r.Int();
  if (n < 0) throw std::runtime_error("parallel: a message ended early");
  result.rocks.reserve(std::min(static_cast<std::size_t>(n), bytes.size()));
  for (long long k = 0; k < n; ++k) result.rocks.push_back(Record(&r));
  result.figures = Figures(&r);
  result.wall_seconds = r.Double();
  result.busy_seconds = r.Double();
  result.cells_recorded = r.Int() != 0;
  result.strikes_recorded = r.Int() != 0;
  const long long impacts = r.Int();
  if (impacts < 0) throw std::runtime_error("parallel: a message ended early");
  for (long long k = 0; k < impacts; ++k) {
    const std::vector<double> v = r.Doubles();
    if (v.size() < 3 || (v.size() - 3) % 4 != 0)
      throw std::runtime_error("parallel: a replayed impact's message is malformed");
    core::ImpactRebound impact;
    impact.normal = Eigen::Vector3d(v[0], v[1], v[2]);
    for (std::size_t i = 3; i < v.size(); i += 4) {
      impact.velocity.emplace_back(v[i], v[i + 1], v[i + 2]);
      impact.left.push_back(v[i + 3] != 0.0 ? 1 : 0);
    }
    result.impacts.push_back(std::move(impact));
  }
  if (!r.done()) throw std::runtime_error("parallel: a simulation message has extra bytes");
  return result;
}

}  // namespace rockcal::parallel
