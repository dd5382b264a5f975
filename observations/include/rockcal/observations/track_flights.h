// Flights and impacts of a tracked rock: the path of its centre, sampled in
// time, split into free-flight parabolas, with an impact where one parabola
// gives way to the next. The rule and its thresholds are in
// docs/field-campaigns.md (Tracks: flights and impacts).
#ifndef ROCKCAL_OBSERVATIONS_TRACK_FLIGHTS_H_
#define ROCKCAL_OBSERVATIONS_TRACK_FLIGHTS_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace rockcal::observations {

// One sample of a tracked rock's centre.
struct TrackSample {
  double t = 0.0;                               // s
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // m
};

struct FlightOptions {
  double gravity = 9.80665;  // m/s^2, > 0
  // One-sigma error of a sample's position along each axis [m], > 0: the
  // track's measurement error.
  double noise = 0.05;
  // A sample is off a parabola when it lies further from it than `tolerance`
  // times its predicted error [4], > 0.
  double tolerance = 4.0;
  // A flight holds at least this many samples [4], >= 3.
  int min_samples = 4;
  // Two parabolas meet at an impact only when the gap between the last
  // sample of the one and the first of the next is at most this [s]; a longer
  // gap is ground contact (rolling, sliding) or missing samples [0.3], > 0.
  double max_contact = 0.3;

  // The shortest flight a track can show: one whose rise above its chord,
  // g T^2 / 8, reaches `tolerance` sigma of the noise. Shorter hops cannot be
  // told from ground contact by the track alone.
  double MinFlightTime() const;
  bool IsValid(std::string* error) const;
};

// A free flight: the parabola fitted to its samples (x, y linear in t; z with
// the acceleration -g).
struct Flight {
  int first = 0, last = 0;            // indices of its first and last samples
  double t0 = 0.0;                    // s, the fit's origin of time
  Eigen::Vector3d x0, v0;             // m, m/s: position and velocity at t0
  double gravity = 9.80665;           // m/s^2
  double t_start = 0.0, t_end = 0.0;  // s, its start and end: the impacts around it where
                                      // detected, else its first and last samples
  double rms = 0.0;                   // m, the samples' rms distance to the parabola

  Eigen::Vector3d Position(double t) const;
  Eigen::Vector3d Velocity(double t) const;
  // m, the plan distance from its start to its end.
  double Length() const;
  // m, the highest point of the centre above the ground along the flight
  // (the ground's elevation below each point of the parabola); NaN where the
  // ground is unknown all along.
  double JumpHeight(const std::function<double(double, double)>& ground) const;
  // m, the centre's lowest height above the ground along the flight (NaN
  // where the ground is unknown all along).
  double LowestHeight(const std::function<double(double, double)>& ground) const;
};

// Where one flight gives way to the next.
struct TrackImpact {
  int before = 0;               // index of the flight that ends here (its successor follows)
  double t = 0.0;               // s, where the two parabolas come closest between them
  Eigen::Vector3d x;            // m, the mean of the two parabolas' points then
  Eigen::Vector3d v_in, v_out;  // m/s, the two parabolas' velocities then
  double gap = 0.0;             // m, the distance between the two points then
};

struct TrackFlights {
  std::vector<Flight> flights;
  std::vector<TrackImpact> impacts;
};

// The ground's elevation [m] below a plan point (x, y); NaN where unknown.
using Ground = std::function<double(double, double)>;

// Splits a track (samples in increasing time) into flights and the impacts
// between them. With a ground, a stretch that fits a parabola is a flight
// only if its centre rises above the ground, along it, by at least
// `tolerance` sigma more than its lowest height there: a rock rolling or
// sliding keeps its height above the ground. Throws std::invalid_argument for
// invalid options or samples whose times do not increase (the readers check
// the files first).
TrackFlights DetectFlights(const std::vector<TrackSample>& samples, const FlightOptions& options,
                           const Ground& ground = {});

}  // namespace rockcal::observations

#endif  // ROCKCAL_OBSERVATIONS_TRACK_FLIGHTS_H_
