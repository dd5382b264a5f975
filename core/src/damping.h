// The contact law's damping role (docs/physics.md, Integration): how a rock's
// contacts share its dashpot, and the implicit (trapezoidal) dashpot solve,
// of one contact in closed form and of a step's contacts together.
// Internal to core (contact_forces.h; tests/core/damping_test.cc).
#ifndef ROCKCAL_CORE_SRC_DAMPING_H_
#define ROCKCAL_CORE_SRC_DAMPING_H_

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

namespace rockcal::core {

// Solves a x = b for a small symmetric positive definite a (n x n, its
// lower triangle), by Cholesky in place: b becomes x. For the few contacts
// of a step, where a general solver's loops cost more than the arithmetic.
template <int kMax>
void SolveSmallSpd(int n, double (&a)[kMax][kMax], double (&b)[kMax]) {
  for (int j = 0; j < n; ++j) {
    double d = a[j][j];
    for (int k = 0; k < j; ++k) d -= a[j][k] * a[j][k];
    d = std::sqrt(d);
    a[j][j] = d;
    for (int i = j + 1; i < n; ++i) {
      double x = a[i][j];
      for (int k = 0; k < j; ++k) x -= a[i][k] * a[j][k];
      a[i][j] = x / d;
    }
  }
  for (int i = 0; i < n; ++i) {  // L y = b
    for (int k = 0; k < i; ++k) b[i] -= a[i][k] * b[k];
    b[i] /= a[i][i];
  }
  for (int i = n - 1; i >= 0; --i) {  // L^T x = y
    for (int k = i + 1; k < n; ++k) b[i] -= a[k][i] * b[k];
    b[i] /= a[i][i];
  }
}

// A rock's restitution is the rock's, not each element's. With n of a
// cluster's elements touching at once, each takes the whole spring (the
// springs stay conservative: energy never rises), so the rock meets n k
// and its contact is sqrt(n) times shorter; for its damping ratio, and so
// its restitution, to stay the material's, the dashpots share sqrt(n) c
// between them. Contact i takes c d_i / |d| (d: the contacts' overlaps;
// |d| their Euclidean norm, `norm`): n equal contacts each c / sqrt(n), one
// contact all of c, and a contact's share grows from 0 with its overlap,
// so nothing jumps as contacts come and go. A shared dashpot only ever
// dissipates. A sphere (`single_element`), and a cluster with one contact,
// takes the whole law. (Sharing the springs as well would keep the contact
// time but is not conservative: a hardness-1 block gained 4 % of its
// energy.) Contacts that all touch without overlap (a landing's first
// instant) share equally. `contacts`: how many touch at once.
inline double DampingShare(double overlap, double norm, std::size_t contacts,
                           bool single_element) {
  if (single_element || contacts < 2) return 1.0;
  return norm > 0.0 ? overlap / norm : 1.0 / std::sqrt(static_cast<double>(contacts));
}

// The normal velocity at the end of a step of dt of a rock's only contact,
// its dashpot implicit (trapezoidal):
//   v_n = v_n,half + dt/2 (s k d - s c v_n + g_n),
// so v_n = (v_n,half + dt/2 (s k d + g_n)) / (1 + dt/2 s c). Per unit mass:
// k and c the law's stiffness and (shared) damping, d the overlap, g_n the
// gravity along the normal; s = m / m_eff, the rock's effective mass there
// (1 through the centre, 1 + m |r x n|^2_{J^-1} off it). JointDashpots' system
// for one contact, row by row.
inline double ImplicitNormalSpeed(double vn_half, double dt, double s, double stiffness_per_mass,
                                  double overlap, double gravity_n, double damping_per_mass) {
  return (vn_half + 0.5 * dt * (s * stiffness_per_mass * overlap + gravity_n)) /
         (1.0 + 0.5 * dt * s * damping_per_mass);
}

// The rock's velocity and spin at the end of a step of dt with its
// contacts: every contact's spring and its share of the damping act on the
// rock together, the dashpots implicit (trapezoidal), for its spin as for
// its centre. Per unit mass, with the generalised velocity u = (v, w),
// the mass matrix M = diag(I, J / m) (J the inertia in world axes) and
// each contact's row g_i = (n_i, r_i x n_i) (its normal velocity g_i u):
//   (M + dt/2 sum c_i g_i g_i^T) u = M u_half + dt/2 (g + sum k d_i g_i).
// So an off-centre contact meets its dashpot with the rock's effective
// mass there, and several contacts meet theirs together. Solved for the
// centre alone (spin explicit), n contacts of a cluster overshot as an
// explicit dashpot does, and the stable step had to fall with the damping
// (bench/README.md, "The step"). A sphere's contacts act through its
// centre: its spin is left out (kDof 3).
//
// A contact's force k d - c v_n is compressive only: one that would pull
// at the solved motion (separating faster than k d / c) takes no part,
// and the others are solved again without it.
//
// A cluster with fewer contacts than 6 solves it in the contacts' space
// (SolveInContacts); both forms by a Cholesky of their own (SolveSmallSpd).
// Together 8 % fewer instructions a step for the tutorial's blocks, 5 %
// for Authume's, than a 6 x 6 Eigen LLT every time.
//
// Use: Resize(n), fill each contact's row(i) (a sphere: its tail zero),
// reach(i) = M^-1 g_i (kDof 6 only) and terms(i), then Solve.
template <int kDof>
class JointDashpots {
 public:
  using Vector = Eigen::Matrix<double, kDof, 1>;
  using Matrix = Eigen::Matrix<double, kDof, kDof>;
  using Row = Eigen::Matrix<double, 6, 1>;
  // A contact's terms, per unit mass: dt/2 c_i and dt/2 k d_i.
  struct Terms {
    double damping, spring;
  };

  void Resize(std::size_t n) {
    rows_.resize(n);
    if constexpr (kDof == 6) reach_.resize(n);
    terms_.resize(n);
  }
  Row& row(std::size_t i) { return rows_[i]; }
  Row& reach(std::size_t i) { return reach_[i]; }
  Terms& terms(std::size_t i) { return terms_[i]; }
  // Whether contact i took no part in the last Solve (it would have pulled).
  bool pulling(std::size_t i) const { return pulling_[i] != 0; }

  // u for the contacts set: free = M^-1 (M u_half + dt/2 g); mass() gives M
  // per unit mass, asked for only where the full kDof x kDof system is solved.
  template <typename MassFn>
  Vector Solve(const Vector& free, MassFn mass_fn) {
    const std::size_t n = rows_.size();
    pulling_.assign(n, 0);
    Vector u;
    for (std::size_t pass = 0; pass <= n; ++pass) {
      if (!(kDof == 6 && SolveInContacts(free, n, &u))) {
        const Matrix mass = mass_fn();
        Vector b = mass * free;
        double a[kDof][kDof];
        for (int r = 0; r < kDof; ++r)
          for (int c = 0; c <= r; ++c) a[r][c] = mass(r, c);
        for (std::size_t i = 0; i < n; ++i) {
          if (pulling_[i]) continue;
          const Vector row = rows_[i].template head<kDof>();
          const double damping = terms_[i].damping;
          for (int r = 0; r < kDof; ++r)
            for (int c = 0; c <= r; ++c) a[r][c] += damping * row[r] * row[c];
          b += terms_[i].spring * row;
        }
        double x[kDof];
        for (int r = 0; r < kDof; ++r) x[r] = b[r];
        SolveSmallSpd<kDof>(kDof, a, x);  // M plus dashpots: SPD
        for (int r = 0; r < kDof; ++r) u[r] = x[r];
      }
      bool changed = false;
      for (std::size_t i = 0; i < n; ++i) {
        if (pulling_[i]) continue;
        const double vn = rows_[i].template head<kDof>().dot(u);
        if (terms_[i].spring - terms_[i].damping * vn < 0.0) {
          pulling_[i] = 1;
          changed = true;
        }
      }
      if (!changed) break;
    }
    return u;
  }

 private:
  // The system in the contacts' space, for a cluster with fewer than 6
  // contacts solved for (not pulling): with u_s = M^-1 (M u_half + dt/2 (g +
  // sum k d_i g_i)) and C the dashpot terms (Woodbury),
  //   u = u_s - M^-1 G C^1/2 (I + C^1/2 G^T M^-1 G C^1/2)^-1 C^1/2 G^T u_s,
  // a k x k system for the 6 x 6 one. False (u untouched) with 6 or more,
  // and for a sphere.
  bool SolveInContacts(const Vector& free, std::size_t n, Vector* u) const {
    if constexpr (kDof != 6) {
      return false;
    } else {
      std::size_t active[kDof];
      int k = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (pulling_[i]) continue;
        if (k == kDof) return false;
        active[k++] = i;
      }
      *u = free;
      for (int j = 0; j < k; ++j) *u += terms_[active[j]].spring * reach_[active[j]];
      double system[kDof][kDof], root[kDof], rhs[kDof];
      for (int j = 0; j < k; ++j) root[j] = std::sqrt(terms_[active[j]].damping);
      for (int j = 0; j < k; ++j) {
        const Vector& row = rows_[active[j]];
        rhs[j] = root[j] * row.dot(*u);
        for (int l = 0; l <= j; ++l) system[j][l] = root[j] * root[l] * row.dot(reach_[active[l]]);
        system[j][j] += 1.0;
      }
      SolveSmallSpd<kDof>(k, system, rhs);  // I plus a Gram matrix: SPD
      for (int j = 0; j < k; ++j) *u -= root[j] * rhs[j] * reach_[active[j]];
      return true;
    }
  }

  std::vector<Row> rows_, reach_;  // g_i and M^-1 g_i
  std::vector<Terms> terms_;
  std::vector<char> pulling_;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_DAMPING_H_
