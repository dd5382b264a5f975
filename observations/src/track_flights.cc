#include "rockcal/observations/track_flights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rockcal/core/numbers.h"

namespace rockcal::observations {
namespace {

using core::kNaN;
// Points along a flight at which its height above the ground is taken, and
// between two flights at which the impact is sought.
constexpr int kProbePoints = 200;
// Samples at the end of a flight that the next may start from.
constexpr int kOverlap = 2;

// The least-squares parabola through samples [first, last]: x and y linear
// in time, z + g tau^2 / 2 linear in time (tau from the first sample), and
// what predicting a further sample needs (the times' mean and spread).
struct Fit {
  Flight flight;
  int n = 0;
  double mean_tau = 0.0, sxx = 0.0;
};

Fit FitParabola(const std::vector<TrackSample>& s, int first, int last, double g) {
  Fit f;
  f.n = last - first + 1;
  const double t0 = s[static_cast<std::size_t>(first)].t;
  double st = 0.0;
  for (int k = first; k <= last; ++k) st += s[static_cast<std::size_t>(k)].t - t0;
  f.mean_tau = st / f.n;
  Eigen::Vector3d mean_y = Eigen::Vector3d::Zero(), sxy = Eigen::Vector3d::Zero();
  auto target = [&](int k, double tau) {
    Eigen::Vector3d y = s[static_cast<std::size_t>(k)].x;
    y.z() += 0.5 * g * tau * tau;
    return y;
  };
  for (int k = first; k <= last; ++k) {
    const double tau = s[static_cast<std::size_t>(k)].t - t0;
    mean_y += target(k, tau);
    f.sxx += (tau - f.mean_tau) * (tau - f.mean_tau);
  }
  mean_y /= f.n;
  for (int k = first; k <= last; ++k) {
    const double tau = s[static_cast<std::size_t>(k)].t - t0;
    sxy += (tau - f.mean_tau) * (target(k, tau) - mean_y);
  }
  Flight& fl = f.flight;
  fl.first = first;
  fl.last = last;
  fl.t0 = t0;
  fl.gravity = g;
  fl.v0 = f.sxx > 0 ? Eigen::Vector3d(sxy / f.sxx) : Eigen::Vector3d::Zero();
  fl.x0 = mean_y - fl.v0 * f.mean_tau;
  fl.t_start = t0;
  fl.t_end = s[static_cast<std::size_t>(last)].t;
  double ss = 0.0;
  for (int k = first; k <= last; ++k) {
    const TrackSample& p = s[static_cast<std::size_t>(k)];
    ss += (p.x - fl.Position(p.t)).squaredNorm();
  }
  fl.rms = std::sqrt(ss / f.n);
  return f;
}

// How many predicted errors sample k lies from the fit's parabola: its
// distance over sigma sqrt(1 + 1/n + (tau - mean)^2 / sxx) per axis (the
// error of a new sample against a fitted line), as the root of the sum of
// the three axes' squares.
double Deviation(const Fit& f, const TrackSample& p, double noise) {
  const double tau = p.t - f.flight.t0;
  const double spread =
      1.0 + 1.0 / f.n + (f.sxx > 0 ? (tau - f.mean_tau) * (tau - f.mean_tau) / f.sxx : 0.0);
  return (p.x - f.flight.Position(p.t)).norm() / (noise * std::sqrt(spread));
}

// Whether every sample of [first, last] lies within the tolerance of the fit.
bool AllOn(const std::vector<TrackSample>& s, const Fit& f, const FlightOptions& o) {
  for (int k = f.flight.first; k <= f.flight.last; ++k)
    if (Deviation(f, s[static_cast<std::size_t>(k)], o.noise) > o.tolerance) return false;
  return true;
}

// Whether no two consecutive samples of the flight lie further apart in time
// than max_contact.
bool Unbroken(const std::vector<TrackSample>& s, const Flight& f, double max_contact) {
  for (int k = f.first; k < f.last; ++k)
    if (s[static_cast<std::size_t>(k + 1)].t - s[static_cast<std::size_t>(k)].t > max_contact)
      return false;
  return true;
}

// The last sample of the flight that starts at `first` with a seed that fits:
// the path is followed while each next sample stays on the parabola of the
// samples before it; it ends before two samples in a row that leave it (one
// alone is taken as a bad sample), or before a gap of max_contact.
int FollowFlight(const std::vector<TrackSample>& s, int first, const FlightOptions& o) {
  const int n = static_cast<int>(s.size());
  int last = first + o.min_samples - 1;
  auto near = [&](int a, int b) {
    return s[static_cast<std::size_t>(b)].t - s[static_cast<std::size_t>(a)].t <= o.max_contact;
  };
  while (last + 1 < n && near(last, last + 1)) {
    const Fit f = FitParabola(s, first, last, o.gravity);
    if (Deviation(f, s[static_cast<std::size_t>(last + 1)], o.noise) <= o.tolerance) {
      ++last;
      continue;
    }
    if (last + 2 < n && near(last + 1, last + 2) &&
        Deviation(f, s[static_cast<std::size_t>(last + 2)], o.noise) <= o.tolerance) {
      last += 2;
      continue;
    }
    break;
  }
  return last;
}

// When two parabolas of the same gravity come closest within [lo, hi]: their
// difference is linear in time, so the moment is in closed form.
double ClosestApproach(const Flight& a, const Flight& b, double lo, double hi) {
  const Eigen::Vector3d d0 = a.Position(lo) - b.Position(lo);
  const Eigen::Vector3d d1 = a.Velocity(lo) - b.Velocity(lo);  // constant
  const double speed2 = d1.squaredNorm();
  const double t = speed2 > 0 ? lo - d0.dot(d1) / speed2 : lo;
  return std::clamp(t, lo, hi);
}

// The impact between flights *a and *b (a before b), when their samples are
// close enough in time. A flight keeps the first few samples after its
// impact (the path is continuous there; only the velocity changes), so the
// impact is sought where the two parabolas come closest within max_contact
// either side of the gap between them; the samples are then dealt to the
// side of the impact they lie on and both parabolas fitted again, once.
bool ImpactBetween(const std::vector<TrackSample>& s, const FlightOptions& o, Flight* a, Flight* b,
                   TrackImpact* impact) {
  auto time = [&](int k) { return s[static_cast<std::size_t>(k)].t; };
  if (time(b->first) - time(a->last) > o.max_contact) return false;
  const double lo = std::max(time(a->first), time(a->last) - o.max_contact);
  const double hi = std::min(time(b->last), time(b->first) + o.max_contact);
  const double t0 = ClosestApproach(*a, *b, lo, hi);
  int a_last = a->last, b_first = b->first;
  while (a_last > a->first && time(a_last) >= t0) --a_last;
  while (b_first > a_last + 1 && time(b_first - 1) >= t0) --b_first;
  while (b_first <= a_last) ++b_first;  // an overlap: each sample to one side
  if (a_last - a->first + 1 >= o.min_samples && b->last - b_first + 1 >= o.min_samples) {
    const double a_start = a->t_start;  // an impact before it, if any
    *a = FitParabola(s, a->first, a_last, o.gravity).flight;
    a->t_start = a_start;
    *b = FitParabola(s, b_first, b->last, o.gravity).flight;
  }
  const double t = ClosestApproach(*a, *b, std::max(time(a->first), time(a->last) - o.max_contact),
                                   std::min(time(b->last), time(b->first) + o.max_contact));
  impact->t = t;
  impact->x = 0.5 * (a->Position(t) + b->Position(t));
  impact->v_in = a->Velocity(t);
  impact->v_out = b->Velocity(t);
  impact->gap = (a->Position(t) - b->Position(t)).norm();
  return true;
}

// Whether the samples of `f` show a flight rather than ground contact: their
// heights above the ground, fitted by a line in time (a rock rolling or
// sliding on locally even ground keeps its height, or changes it steadily),
// leave at least tolerance^2 sigma^2 of squared error beyond what the
// parabola leaves in elevation. (A lower bar, `tolerance` sigma^2, let noise
// on a rolling track pass for a flight in 19 of 30 tracks of 4 s at 50 Hz:
// every stretch of the track is tried.)
bool LeavesTheGround(const std::vector<TrackSample>& s, const Flight& f, const Ground& ground,
                     const FlightOptions& o) {
  std::vector<double> t, h, z_error;
  for (int k = f.first; k <= f.last; ++k) {
    const TrackSample& p = s[static_cast<std::size_t>(k)];
    const double g = ground(p.x.x(), p.x.y());
    if (!std::isfinite(g)) continue;
    t.push_back(p.t);
    h.push_back(p.x.z() - g);
    z_error.push_back(p.x.z() - f.Position(p.t).z());
  }
  const std::size_t n = t.size();
  if (n < 3) return true;  // the ground unknown here: the track alone decides
  double mt = 0, mh = 0;
  for (std::size_t k = 0; k < n; ++k) {
    mt += t[k] / n;
    mh += h[k] / n;
  }
  double stt = 0, sth = 0;
  for (std::size_t k = 0; k < n; ++k) {
    stt += (t[k] - mt) * (t[k] - mt);
    sth += (t[k] - mt) * (h[k] - mh);
  }
  const double slope = stt > 0 ? sth / stt : 0.0;
  double following = 0, flying = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = h[k] - mh - slope * (t[k] - mt);
    following += r * r;
    flying += z_error[k] * z_error[k];
  }
  return following - flying >= o.tolerance * o.tolerance * o.noise * o.noise;
}

}  // namespace

double FlightOptions::MinFlightTime() const { return std::sqrt(8.0 * tolerance * noise / gravity); }

bool FlightOptions::IsValid(std::string* error) const {
  std::ostringstream s;
  if (!(gravity > 0 && std::isfinite(gravity)))
    s << "gravity = " << gravity << ": must be > 0";
  else if (!(noise > 0 && std::isfinite(noise)))
    s << "noise = " << noise << ": must be > 0";
  else if (!(tolerance > 0 && std::isfinite(tolerance)))
    s << "tolerance = " << tolerance << ": must be > 0";
  else if (min_samples < 3)
    s << "min_samples = " << min_samples << ": must be >= 3";
  else if (!(max_contact > 0 && std::isfinite(max_contact)))
    s << "max_contact = " << max_contact << ": must be > 0";
  else
    return true;
  *error = s.str();
  return false;
}

Eigen::Vector3d Flight::Position(double t) const {
  const double tau = t - t0;
  Eigen::Vector3d p = x0 + v0 * tau;
  p.z() -= 0.5 * gravity * tau * tau;
  return p;
}

Eigen::Vector3d Flight::Velocity(double t) const {
  Eigen::Vector3d v = v0;
  v.z() -= gravity * (t - t0);
  return v;
}

double Flight::Length() const { return (Position(t_end) - Position(t_start)).head<2>().norm(); }

namespace {

// The extreme (the highest with `highest`, else the lowest) height of the
// flight's centre above the ground, over kProbePoints of its path.
double ExtremeHeight(const Flight& f, const std::function<double(double, double)>& ground,
                     bool highest) {
  double extreme = kNaN;
  for (int k = 0; k <= kProbePoints; ++k) {
    const Eigen::Vector3d p = f.Position(f.t_start + (f.t_end - f.t_start) * k / kProbePoints);
    const double h = p.z() - ground(p.x(), p.y());
    if (!std::isfinite(h)) continue;
    if (std::isnan(extreme) || (highest ? h > extreme : h < extreme)) extreme = h;
  }
  return extreme;
}

}  // namespace

double Flight::JumpHeight(const std::function<double(double, double)>& ground) const {
  return ExtremeHeight(*this, ground, true);
}

double Flight::LowestHeight(const std::function<double(double, double)>& ground) const {
  return ExtremeHeight(*this, ground, false);
}

TrackFlights DetectFlights(const std::vector<TrackSample>& samples, const FlightOptions& options,
                           const Ground& ground) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("flight options: " + error);
  for (std::size_t k = 1; k < samples.size(); ++k)
    if (!(samples[k].t > samples[k - 1].t))
      throw std::invalid_argument("track samples: time does not increase at sample " +
                                  std::to_string(k));
  TrackFlights out;
  const int n = static_cast<int>(samples.size());
  const double min_time = options.MinFlightTime();
  int first = 0;
  while (first + options.min_samples <= n) {
    const Fit seed = FitParabola(samples, first, first + options.min_samples - 1, options.gravity);
    if (!AllOn(samples, seed, options) || !Unbroken(samples, seed.flight, options.max_contact)) {
      ++first;
      continue;
    }
    const int last = FollowFlight(samples, first, options);
    const Fit whole = FitParabola(samples, first, last, options.gravity);
    if (whole.flight.t_end - whole.flight.t_start < min_time) {
      ++first;  // too short to tell from ground contact
      continue;
    }
    if (ground && !LeavesTheGround(samples, whole.flight, ground, options)) {
      ++first;  // keeps its height above the ground: rolling or sliding
      continue;
    }
    out.flights.push_back(whole.flight);
    // The last samples may lie past an impact yet still near the parabola
    // (the path is continuous there): the next flight may start among them;
    // ImpactBetween deals the shared samples to their sides.
    const bool left = last + 1 < n && samples[static_cast<std::size_t>(last + 1)].t -
                                              samples[static_cast<std::size_t>(last)].t <=
                                          options.max_contact;
    first = left ? std::max(first + 1, last - kOverlap) : last + 1;
  }
  for (std::size_t k = 0; k + 1 < out.flights.size(); ++k) {
    TrackImpact impact;
    if (!ImpactBetween(samples, options, &out.flights[k], &out.flights[k + 1], &impact)) continue;
    impact.before = static_cast<int>(k);
    out.flights[k].t_end = impact.t;
    out.flights[k + 1].t_start = impact.t;
    out.impacts.push_back(impact);
  }
  return out;
}

}  // namespace rockcal::observations
