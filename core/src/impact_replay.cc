#include "rockcal/core/impact_replay.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rebound.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/random.h"

namespace rockcal::core {
namespace {

// A replayed rock starts with its lowest element between one and two of
// this share of its radius clear of the ground.
constexpr double kClearance = 0.01;
// The steps that bring it there along the incoming velocity (PlaceDraw).
constexpr int kPlacingSteps = 64;
// The longest flight allowed before the first contact (an impact arriving
// nearly along the ground takes long to touch it).
constexpr double kMaxLeadSeconds = 2.0;

// The smallest gap between the rock's elements (body, orientation q,
// centre c) and the terrain; +inf when nothing is near.
double ElementGap(const Terrain& terrain, const RockBody& body, const Eigen::Quaterniond& q,
                  const Eigen::Vector3d& c) {
  double gap = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& e : body.elements)
    gap = std::min(gap, terrain.Gap(c + q * e, body.element_radius, 0.0));
  return gap;
}

// The state of draw `draw` of `impact`: at the incoming velocity, just clear
// of the ground below (or above) the observed centre, with its drawn
// orientation and spin.
ReboundJob PlaceDraw(const Scene& scene, const Terrain& terrain, const ImpactReplay& impact,
                     const Eigen::Vector3d& n, int draw, std::uint64_t stream) {
  RandomStream rng(scene.options.seed, stream);
  const RockGroup& group = scene.groups[static_cast<std::size_t>(impact.group)];
  const double u_size = rng.Uniform();
  const double u1 = rng.Uniform(), u2 = rng.Uniform(), u3 = rng.Uniform();
  const double u_spin = rng.Uniform();
  ReboundJob job;
  job.body = GroupRockBody(group, draw, u_size, scene.gravity);
  job.normal = n;
  const Eigen::Quaterniond q(
      std::sqrt(1 - u1) * std::sin(2 * kPi * u2), std::sqrt(1 - u1) * std::cos(2 * kPi * u2),
      std::sqrt(u1) * std::sin(2 * kPi * u3), std::sqrt(u1) * std::cos(2 * kPi * u3));
  const Eigen::Vector3d& v = impact.velocity_in;
  const Eigen::Vector3d vt = v - v.dot(n) * n;
  RockState& s = job.start;
  s.q = q.normalized();
  s.t = 0.0;
  s.w =
      impact.spin ? *impact.spin : Eigen::Vector3d(u_spin * n.cross(vt) / job.body.bounding_radius);
  // Along the line of the incoming velocity through the observed centre
  // (back while inside the ground, on while above it) until the lowest
  // element is just clear: the rock reaches this replay's ground where the
  // observed path meets it, at the observed velocity, wherever the centre
  // lies against it (a drawn orientation or size, or a roughness that
  // raises or lowers the ground between the spheres, puts it inside or
  // above). A step of the gap's excess or shortfall changes no obstacle's
  // gap by more than itself, so the gap comes to the band from one side; a
  // path that grazes the ground can fall short that way, and is then lifted
  // along the normal in doubling steps until clear.
  const double margin = kClearance * job.body.element_radius;
  const Eigen::Vector3d along =
      v.norm() > 0.0 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d(-n);
  s.x = impact.centre;
  s.v = v;
  double gap = ElementGap(terrain, job.body, s.q, s.x);
  for (int i = 0; i < kPlacingSteps && std::isfinite(gap) && (gap < margin || gap > 2 * margin);
       ++i) {
    s.x += (gap - 1.5 * margin) * along;
    gap = ElementGap(terrain, job.body, s.q, s.x);
  }
  double lift = margin;
  for (int i = 0; i < 40 && gap < margin; ++i, lift *= 2) {
    s.x += lift * n;
    gap = ElementGap(terrain, job.body, s.q, s.x);
  }
  job.max_time = kMaxLeadSeconds + kReplayContactSeconds;
  job.contact_seconds = kReplayContactSeconds;
  return job;
}

}  // namespace

bool GroundNormal(const Terrain& terrain, double x, double y, Eigen::Vector3d* normal) {
  double z = 0.0;
  if (!terrain.Elevation(x, y, &z)) return false;
  const double h = terrain.grid().spacing;
  // d/dx and d/dy by central differences, one-sided where a side is off the slope.
  auto slope = [&](double dx, double dy) {
    double zp = 0.0, zm = 0.0;
    const bool p = terrain.Elevation(x + dx, y + dy, &zp);
    const bool m = terrain.Elevation(x - dx, y - dy, &zm);
    if (p && m) return (zp - zm) / (2 * h);
    if (p) return (zp - z) / h;
    if (m) return (z - zm) / h;
    return 0.0;
  };
  *normal = Eigen::Vector3d(-slope(h, 0), -slope(0, h), 1.0).normalized();
  return true;
}

ReboundRatios RatiosOf(const Eigen::Vector3d& v_in, const Eigen::Vector3d& v_out,
                       const Eigen::Vector3d& n) {
  ReboundRatios r;
  r.normal = -v_out.dot(n) / v_in.dot(n);
  const Eigen::Vector3d t = v_in - v_in.dot(n) * n;
  const double vt = t.norm();
  r.tangential =
      vt >= kMinTangentialShare * v_in.norm() && vt > 0.0 ? v_out.dot(t) / (vt * vt) : kNaN;
  return r;
}

std::vector<ImpactRebound> ReplayImpacts(const Scene& scene, const Terrain& terrain,
                                         const std::vector<ImpactReplay>& impacts) {
  std::vector<ImpactRebound> out(impacts.size());
  std::vector<ReboundJob> jobs;
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const ImpactReplay& impact = impacts[i];
    Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    GroundNormal(terrain, impact.centre.x(), impact.centre.y(), &n);
    out[i].normal = n;
    for (int d = 0; d < impact.draws; ++d) {
      const std::uint64_t stream =
          (std::uint64_t{1} << 63) | (std::uint64_t{i} << 20) | static_cast<std::uint64_t>(d);
      jobs.push_back(PlaceDraw(scene, terrain, impact, n, d, stream));
    }
  }
  RunRebounds(scene, terrain, &jobs);
  std::size_t k = 0;
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    for (int d = 0; d < impacts[i].draws; ++d, ++k) {
      out[i].velocity.push_back(jobs[k].velocity);
      out[i].left.push_back(jobs[k].left ? 1 : 0);
    }
  }
  return out;
}

}  // namespace rockcal::core
