// The oblique impacts of tests/core/oblique_impact_test.cc (a solid sphere
// on a flat plane, incidence 5-85 degrees, without spin, rolling and with
// backspin, e 0.3 / 0.5 / 0.8, friction 0.1 / 0.5) run by LIGGGHTS with the
// same contact law, against the exact answer of that law (the test's
// tests/core/oblique_impact.h): how far a peer engine's rebound is from the
// exact one at its step, beside rockcal's (issue 36).
//
// LIGGGHTS: `fix wall/gran model hooke/stiffness tangential history` on a
// primitive plane, k_n = m (pi^2 + ln^2 e) / t_c^2, gamma_n = rockcal's C / m
// (LIGGGHTS multiplies it by the effective mass), k_t = 2/7 k_n, gamma_t = 0
// (tangential_damping off), limitForce on (the plane never pulls): exactly
// rockcal's law. Each impact is its own rock, touching the plane at t = 0;
// the run lasts 1.5 t_c, and the final velocities and spins are compared
// with the exact ones at that time.
//
//   oblique_impact_liggghts [liggghts_dt_divisor=1 ...]   (LIGGGHTS' step t_c / (50 K))
#include <stdlib.h>  // mkdtemp

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "oblique_impact.h"
#include "rockcal/core/material.h"

namespace {

using namespace rockcal;

constexpr double kRadius = 1.0, kDensity = 2650.0, kContactTime = 5e-4, kSpeed = 10.0;
constexpr double kGravity = 9.81;
constexpr double kDeg = M_PI / 180.0;

struct Case {
  double incidence, spin;  // rad; a w / v_t
};

struct Errors {
  double vn = 0.0, vt = 0.0, spin = 0.0;  // largest |LIGGGHTS - exact| / V
  double rebound = 0.0;  // (LIGGGHTS - exact) / exact normal rebound, at 5 degrees without spin
};

// Runs one deck (all the cases at one e and f) and returns the largest errors.
Errors RunDeck(double e, double f, int divisor, const std::vector<Case>& cases) {
  core::Material m;
  m.restitution = e;
  m.friction = f;
  m.contact_time_s = kContactTime;
  const core::ContactLaw law = core::DeriveContactLaw(m, core::HardnessModel{});
  const double mass = kDensity * 4.0 / 3.0 * M_PI * std::pow(kRadius, 3);
  const double dt = kContactTime / (50.0 * divisor);
  const long steps = std::lround(1.5 * kContactTime / dt);
  const double t_end = steps * dt;

  std::string dir = (std::filesystem::temp_directory_path() / "rockcal_impacts_XXXXXX").string();
  if (::mkdtemp(dir.data()) == nullptr) return {};
  const int n = static_cast<int>(cases.size());
  {
    std::ofstream d(dir + "/data.impacts");
    d.precision(17);
    d << "oblique impacts\n\n"
      << n << " atoms\n2 atom types\n\n"
      << "-5 " << 10.0 * n + 5 << " xlo xhi\n-5 5 ylo yhi\n-1 5 zlo zhi\n\nAtoms\n\n";
    for (int k = 0; k < n; ++k)
      d << k + 1 << " 2 " << 2 * kRadius << " " << kDensity << " " << 10.0 * k << " 0 " << kRadius
        << "\n";
    d << "\nVelocities\n\n";
    for (int k = 0; k < n; ++k) {
      const double vn = kSpeed * std::cos(cases[k].incidence);
      const double vt = kSpeed * std::sin(cases[k].incidence);
      d << k + 1 << " " << vt << " 0 " << -vn << " 0 " << cases[k].spin * vt / kRadius << " 0\n";
    }
  }
  {
    const double kn = law.stiffness_per_mass * mass;
    std::ofstream in(dir + "/in.impacts");
    in.precision(17);
    in << "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\n"
       << "communicate single vel yes\nunits si\nread_data data.impacts\n"
       << "neighbor 0.2 bin\nneigh_modify delay 0 exclude type 2 2\n"
       << "fix kn all property/global kn peratomtypepair 2 " << kn << " " << kn << " " << kn << " "
       << kn << "\n"
       << "fix kt all property/global kt peratomtypepair 2 " << law.tangential_ratio * kn << " "
       << law.tangential_ratio * kn << " " << law.tangential_ratio * kn << " "
       << law.tangential_ratio * kn << "\n"
       << "fix gn all property/global gamman peratomtypepair 2 " << law.damping_per_mass << " "
       << law.damping_per_mass << " " << law.damping_per_mass << " " << law.damping_per_mass << "\n"
       << "fix gt all property/global gammat peratomtypepair 2 0 0 0 0\n"
       << "fix cof all property/global coefficientFriction peratomtypepair 2 " << f << " " << f
       << " " << f << " " << f << "\n"
       << "pair_style gran model hooke/stiffness tangential history limitForce on "
          "tangential_damping off absolute_damping off\npair_coeff * *\n"
       << "fix plane all wall/gran model hooke/stiffness tangential history primitive type 1 "
          "zplane 0.0 limitForce on tangential_damping off absolute_damping off\n"
       << "timestep " << dt << "\n"
       << "fix gravity all gravity " << kGravity << " vector 0 0 -1\n"
       << "fix integrate all nve/sphere\n"
       << "run " << steps << "\n"
       << "write_dump all custom final.dump id vx vy vz omegax omegay omegaz\n";
  }
  const std::string command = "cd '" + dir +
                              "' && OMP_NUM_THREADS=1 liggghts -in in.impacts -log log.liggghts "
                              "-nocite > screen.liggghts 2>&1";
  Errors worst;
  if (std::system(command.c_str()) != 0) {
    std::printf("liggghts failed: see %s\n", dir.c_str());
    worst.vn = worst.vt = worst.spin = NAN;
    return worst;
  }
  std::ifstream dump(dir + "/final.dump");
  std::string line;
  bool atoms = false;
  while (std::getline(dump, line)) {
    if (line.rfind("ITEM:", 0) == 0) {
      atoms = line.rfind("ITEM: ATOMS", 0) == 0;
      continue;
    }
    long id;
    double vx, vy, vz, wx, wy, wz;
    if (!atoms || std::sscanf(line.c_str(), "%ld %lf %lf %lf %lf %lf %lf", &id, &vx, &vy, &vz, &wx,
                              &wy, &wz) != 7)
      continue;
    const Case& c = cases[static_cast<std::size_t>(id - 1)];
    const double vn = kSpeed * std::cos(c.incidence), vt = kSpeed * std::sin(c.incidence);
    const double w0 = c.spin * vt / kRadius;
    core::testing::ImpactLaw il;
    il.omega = std::sqrt(law.stiffness_per_mass);
    il.zeta = law.damping_ratio;
    il.tangential_ratio = law.tangential_ratio;
    il.friction = f;
    core::testing::ImpactStart st;
    st.gn = kGravity;
    st.vn = vn;
    st.slip = vt - kRadius * w0;
    const core::testing::ImpactEnd end = core::testing::SolveImpact(il, st);
    const double vz_exact = end.vn - kGravity * (t_end - end.duration);
    const double vx_exact = vt + end.impulse;
    const double wy_exact = w0 - 2.5 * end.impulse / kRadius;
    worst.vn = std::max(worst.vn, std::abs(vz - vz_exact) / kSpeed);
    if (id == 1) worst.rebound = (vz - vz_exact) / vz_exact;
    worst.vt = std::max(worst.vt, std::abs(vx - vx_exact) / kSpeed);
    worst.spin = std::max(worst.spin, std::abs(kRadius * (wy - wy_exact)) / kSpeed);
  }
  std::filesystem::remove_all(dir);
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> divisors;
  for (int i = 1; i < argc; ++i) divisors.push_back(std::atoi(argv[i]));
  if (divisors.empty()) divisors = {1};
  std::vector<Case> cases;
  for (double spin : {0.0, 1.0, -1.0})
    for (int deg = 5; deg <= 85; deg += 10) cases.push_back({deg * kDeg, spin});
  std::printf(
      "LIGGGHTS against the exact answer: %zu impacts per setting (incidence 5-85 deg, spin "
      "0 / rolling / backspin), a sphere of radius %.1f m at %.0f m/s, t_c %.2g s; largest "
      "|LIGGGHTS - exact| / impact speed\n",
      cases.size(), kRadius, kSpeed, kContactTime);
  std::printf("%-8s %5s %5s %10s %10s %10s %14s\n", "step", "e", "f", "normal", "tangential",
              "spin a", "rebound 5 deg");
  for (int divisor : divisors)
    for (double e : {0.3, 0.5, 0.8})
      for (double f : {0.1, 0.5}) {
        const Errors err = RunDeck(e, f, divisor, cases);
        char step[32];
        std::snprintf(step, sizeof step, "t_c/%d", 50 * divisor);
        std::printf("%-8s %5.1f %5.1f %10.2e %10.2e %10.2e %+13.2f%%\n", step, e, f, err.vn, err.vt,
                    err.spin, 100.0 * err.rebound);
        std::fflush(stdout);
      }
  return 0;
}
