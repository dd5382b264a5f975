// Flight and impact detection on synthetic tracks with known impacts: a point
// bouncing down a 30 degree plane with restitution, sampled at 10 to 100 Hz
// with Gaussian noise on every coordinate; a rock rolling down the plane.
#include "rockcal/observations/track_flights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "rockcal/core/random.h"

namespace rockcal::observations {
namespace {

constexpr double kG = 9.80665;
constexpr double kPi = 3.14159265358979323846;
const double kSlope = std::tan(30.0 * kPi / 180.0);

double Plane(double x, double /*y*/) { return -kSlope * x; }

// A true flight of the bouncing point: from its start to its landing.
struct TrueFlight {
  double t0, t1;
  Eigen::Vector3d x0, v0;
  Eigen::Vector3d At(double t) const {
    const double tau = t - t0;
    Eigen::Vector3d p = x0 + v0 * tau;
    p.z() -= 0.5 * kG * tau * tau;
    return p;
  }
  Eigen::Vector3d VelocityAt(double t) const {
    Eigen::Vector3d v = v0;
    v.z() -= kG * (t - t0);
    return v;
  }
  double Apex() const {  // highest point above the plane
    double best = 0.0;
    for (int k = 0; k <= 2000; ++k) {
      const Eigen::Vector3d p = At(t0 + (t1 - t0) * k / 2000.0);
      best = std::max(best, p.z() - Plane(p.x(), p.y()));
    }
    return best;
  }
};

// Bounces of a point released 2 m above the plane at 6 m/s down the slope
// and 1 m/s across: normal restitution 0.6, tangential 0.85, until a flight
// is shorter than `shortest` s.
std::vector<TrueFlight> Bounces(double shortest) {
  const Eigen::Vector3d n = Eigen::Vector3d(kSlope, 0, 1).normalized();
  std::vector<TrueFlight> flights;
  Eigen::Vector3d x(0, 0, 2), v(6, 1, 0);
  double t = 0;
  for (int k = 0; k < 12; ++k) {
    // n.(x + v tau - g tau^2 / 2 z) = 0, the later root.
    const double a = -0.5 * kG * n.z(), b = n.dot(v), c = n.dot(x);
    const double tau = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
    TrueFlight f{t, t + tau, x, v};
    if (tau < shortest) break;
    flights.push_back(f);
    x = f.At(f.t1);
    const Eigen::Vector3d vin = f.VelocityAt(f.t1);
    const Eigen::Vector3d vn = vin.dot(n) * n;
    v = -0.6 * vn + 0.85 * (vin - vn);
    t = f.t1;
  }
  return flights;
}

std::vector<TrackSample> Sample(const std::vector<TrueFlight>& flights, double hz, double noise,
                                std::uint64_t seed) {
  core::RandomStream rng(seed, 7);
  std::vector<TrackSample> out;
  for (double t = 0; t < flights.back().t1; t += 1.0 / hz) {
    std::size_t k = 0;
    while (k + 1 < flights.size() && t >= flights[k].t1) ++k;
    TrackSample s{t, flights[k].At(t)};
    for (int d = 0; d < 3; ++d) s.x(d) += noise * rng.Normal();
    out.push_back(s);
  }
  return out;
}

// Every true flight long enough to be seen, with samples to spare at both
// ends, is found; each impact between two found flights is placed within a
// twentieth of a sample interval plus the noise's share, its velocities
// within 10 % of the speed, and each flight's jump height within 3 sigma.
void CheckDetection(double hz, double noise, std::uint64_t seed) {
  const std::vector<TrueFlight> truth = Bounces(0.2);
  ASSERT_GE(truth.size(), 4u);
  const std::vector<TrackSample> track = Sample(truth, hz, noise, seed);
  FlightOptions o;
  o.noise = noise;
  const TrackFlights found = DetectFlights(track, o, Plane);
  std::ostringstream log;
  log << hz << " Hz, noise " << noise << " m, seed " << seed << ": " << found.flights.size()
      << " flights, " << found.impacts.size() << " impacts; min flight " << o.MinFlightTime()
      << " s\n";
  int seen = 0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const TrueFlight& f = truth[k];
    // What the detector promises: a flight at least MinFlightTime and three
    // sample intervals long (the samples next to an impact may go to the
    // flight on the other side) whose rise above its chord, P = g T^2 / 8,
    // stands out of the noise on the samples left, m: the heights above the
    // ground, less their line, hold 0.089 m P^2 (a parabola's variance about
    // its chord line), at least twice the tolerance^2 sigma^2 asked.
    const double t = f.t1 - f.t0, rise = kG * t * t / 8, inner = (t - 2.0 / hz) * hz;
    const bool visible =
        t >= o.MinFlightTime() + 3.0 / hz &&
        0.0889 * inner * rise * rise >= 2 * o.tolerance * o.tolerance * noise * noise;
    const Flight* match = nullptr;
    for (const Flight& d : found.flights) {
      const double mid = 0.5 * (d.t_start + d.t_end);
      if (mid > f.t0 && mid < f.t1) match = &d;
    }
    log << "  true flight " << k << " [" << f.t0 << ", " << f.t1 << "] apex " << f.Apex();
    if (match)
      log << ": found [" << match->t_start << ", " << match->t_end << "] apex "
          << match->JumpHeight(Plane) << "\n";
    else
      log << ": not found\n";
    if (!visible) continue;
    ++seen;
    ASSERT_NE(match, nullptr) << log.str();
    EXPECT_NEAR(match->JumpHeight(Plane), f.Apex(), 3 * noise) << log.str();
    EXPECT_NEAR(match->Length(), (f.At(match->t_end) - f.At(match->t_start)).head<2>().norm(),
                3 * noise)
        << log.str();
  }
  EXPECT_GE(seen, 2) << log.str();
  ASSERT_FALSE(found.impacts.empty()) << log.str();
  for (const TrackImpact& i : found.impacts) {
    std::size_t k = 0;  // the true impact nearest in time
    for (std::size_t j = 0; j + 1 < truth.size(); ++j)
      if (std::abs(truth[j].t1 - i.t) < std::abs(truth[k].t1 - i.t)) k = j;
    const double speed = truth[k].VelocityAt(truth[k].t1).norm();
    const double slack = 0.05 / hz + 10 * noise / speed;
    EXPECT_NEAR(i.t, truth[k].t1, slack) << log.str();
    EXPECT_LT((i.v_in - truth[k].VelocityAt(truth[k].t1)).norm(), 0.1 * speed) << log.str();
    EXPECT_LT((i.v_out - truth[k + 1].VelocityAt(truth[k].t1)).norm(), 0.1 * speed) << log.str();
  }
}

TEST(DetectFlights, FindsTheImpactsOfABouncingPointAt10Hz) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) CheckDetection(10, 0.02, seed);
}
TEST(DetectFlights, FindsTheImpactsOfABouncingPointAt25Hz) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) CheckDetection(25, 0.05, seed);
}
TEST(DetectFlights, FindsTheImpactsOfABouncingPointAt100Hz) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) CheckDetection(100, 0.05, seed);
}

TEST(DetectFlights, WithoutNoiseTheFlightsAreExact) {
  const std::vector<TrueFlight> truth = Bounces(0.3);
  std::vector<TrackSample> track = Sample(truth, 50, 0.0, 1);
  FlightOptions o;
  o.noise = 1e-6;
  const TrackFlights found = DetectFlights(track, o, Plane);
  ASSERT_EQ(found.flights.size(), truth.size());
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_LT(
        (found.flights[k].Velocity(truth[k].t0 + 0.1) - truth[k].VelocityAt(truth[k].t0 + 0.1))
            .norm(),
        1e-6)
        << "flight " << k;
    if (k + 1 < truth.size()) {
      ASSERT_LT(k, found.impacts.size());
      EXPECT_NEAR(found.impacts[k].t, truth[k].t1, 0.02 / 200 + 1e-6) << "impact " << k;
    }
  }
}

// A rock rolling down the plane follows it: no flight. Every stretch of a
// track is tried, so noise now and then passes for a short flight: 1 of 30
// such tracks showed one; of these ten, at most one may.
TEST(DetectFlights, ARollingRockHasNoFlight) {
  const double a = kG * std::sin(30.0 * kPi / 180.0) * 5.0 / 7.0;  // a rolling sphere
  FlightOptions o;
  o.noise = 0.03;
  int false_flights = 0;
  std::ostringstream log;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    core::RandomStream rng(seed, 1);
    std::vector<TrackSample> track;
    for (double t = 0; t < 4.0; t += 0.02) {
      const double s = 1.0 * t + 0.5 * a * t * t;  // along the slope
      TrackSample p{t, Eigen::Vector3d(s * std::cos(kPi / 6), 0.0, -s * std::sin(kPi / 6) + 0.5)};
      for (int d = 0; d < 3; ++d) p.x(d) += o.noise * rng.Normal();
      track.push_back(p);
    }
    const TrackFlights found = DetectFlights(track, o, Plane);
    false_flights += static_cast<int>(found.flights.size());
    for (const Flight& f : found.flights)
      log << "seed " << seed << ": a flight [" << f.t_start << ", " << f.t_end << "]\n";
  }
  EXPECT_LE(false_flights, 1) << log.str();
}

TEST(DetectFlights, RefusesTimesThatDoNotIncreaseAndBadOptions) {
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  std::vector<TrackSample> track = {{0.0, zero}, {0.1, zero}, {0.1, zero}};
  EXPECT_THROW(DetectFlights(track, FlightOptions{}), std::invalid_argument);
  FlightOptions o;
  o.noise = 0;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("noise = 0"), std::string::npos) << error;
  o = FlightOptions{};
  o.min_samples = 2;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("min_samples = 2"), std::string::npos) << error;
}

}  // namespace
}  // namespace rockcal::observations
