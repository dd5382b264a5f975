// The stems of a forest as the engine finds them (docs/physics.md, "Trees"):
// a plan grid of stems built once per run (StemGrid), and each rock's view
// of it (StemSearch): the stems within reach of where it is, the contacts
// of its elements with their trunks, and how long a free flight may last
// before it could reach one. A scene without a forest builds none of this.
// Internal to core (simulate.cc; tests/core/forest_test.cc).
#ifndef ROCKCAL_CORE_SRC_STEMS_H_
#define ROCKCAL_CORE_SRC_STEMS_H_

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "rock_state.h"
#include "rockcal/core/forest.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// Contact keys of trunks: stem k's is kStemKey + k, below every terrain key
// (nodes >= 0, facets and catch planes above -2^41).
inline constexpr std::int64_t kStemKey = -(std::int64_t{1} << 60);

// The stems of a forest on a plan grid of cells of kStemCell metres: each
// cell lists the stems whose axis lies in it.
class StemGrid final {
 public:
  static constexpr double kStemCell = 4.0;  // m

  StemGrid() = default;
  // The stems of `forest` standing on `terrain` (their foot at the ground
  // height there); a stem off the slope is left out.
  StemGrid(const Forest& forest, const Terrain& terrain) : stems_(&forest.stems) {
    const std::size_t n = forest.stems.size();
    foot_.assign(n, std::numeric_limits<double>::quiet_NaN());
    std::vector<int> kept;
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (std::size_t k = 0; k < n; ++k) {
      const Stem& s = forest.stems[k];
      double z = 0.0;
      if (!terrain.GroundHeight(s.x, s.y, &z)) continue;
      foot_[k] = z;
      kept.push_back(static_cast<int>(k));
      x0 = std::min(x0, s.x);
      y0 = std::min(y0, s.y);
      x1 = std::max(x1, s.x);
      y1 = std::max(y1, s.y);
      max_radius_ = std::max(max_radius_, 0.5 * s.dbh);
    }
    if (kept.empty()) return;
    x0_ = x0;
    y0_ = y0;
    nx_ = static_cast<int>((x1 - x0) / kStemCell) + 1;
    ny_ = static_cast<int>((y1 - y0) / kStemCell) + 1;
    start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
    for (int k : kept) ++start_[static_cast<std::size_t>(Cell(k)) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    index_.resize(kept.size());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (int k : kept)
      index_[static_cast<std::size_t>(fill[static_cast<std::size_t>(Cell(k))]++)] = k;
  }

  bool empty() const { return index_.empty(); }
  const Stem& stem(int k) const { return (*stems_)[static_cast<std::size_t>(k)]; }
  // The ground height at stem k's axis.
  double foot(int k) const { return foot_[static_cast<std::size_t>(k)]; }
  double max_radius() const { return max_radius_; }

  // Calls f(k) for every stem whose axis may lie in the plan box [x0, x1] x
  // [y0, y1] (every stem of the cells the box meets).
  template <typename F>
  void ForEachIn(double x0, double y0, double x1, double y1, F&& f) const {
    if (index_.empty()) return;
    const int i0 = std::max(0, static_cast<int>(std::floor((x0 - x0_) / kStemCell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((y0 - y0_) / kStemCell)));
    const int i1 = std::min(nx_ - 1, static_cast<int>(std::floor((x1 - x0_) / kStemCell)));
    const int j1 = std::min(ny_ - 1, static_cast<int>(std::floor((y1 - y0_) / kStemCell)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
        for (int p = start_[c]; p < start_[c + 1]; ++p) f(index_[static_cast<std::size_t>(p)]);
      }
  }

 private:
  int Cell(int k) const {
    const Stem& s = stem(k);
    const int i = std::min(nx_ - 1, static_cast<int>((s.x - x0_) / kStemCell));
    const int j = std::min(ny_ - 1, static_cast<int>((s.y - y0_) / kStemCell));
    return j * nx_ + i;
  }

  const std::vector<Stem>* stems_ = nullptr;
  std::vector<double> foot_;
  double x0_ = 0.0, y0_ = 0.0, max_radius_ = 0.0;
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_, index_;  // stems by cell (CSR)
};

// One rock's view of the stems: those whose trunk its bounding sphere may
// reach while its centre stays within kStemSkin of where the list was made
// (a Verlet list in plan), less the stems it has broken.
class StemSearch final {
 public:
  static constexpr double kStemSkin = 2.0;  // m

  StemSearch(const StemGrid& grid, double bounding_radius) : grid_(grid), rb_(bounding_radius) {}

  // The list for a rock whose centre is at x, made anew when the centre has
  // moved kStemSkin in plan since the last.
  void Update(const Eigen::Vector3d& x) {
    if (made_ && (x.head<2>() - ref_).squaredNorm() < kStemSkin * kStemSkin) return;
    made_ = true;
    ref_ = x.head<2>();
    near_.clear();
    const double w = rb_ + grid_.max_radius() + kStemSkin;
    grid_.ForEachIn(x.x() - w, x.y() - w, x.x() + w, x.y() + w, [&](int k) {
      const Stem& s = grid_.stem(k);
      const double reach = rb_ + 0.5 * s.dbh + kStemSkin;
      if ((Eigen::Vector2d(s.x, s.y) - ref_).squaredNorm() < reach * reach && !Broken(k))
        near_.push_back(k);
    });
  }
  const std::vector<int>& near() const { return near_; }

  // The contact of an element sphere (c, a) with the trunk of stem k: the
  // normal horizontal from the axis, the overlap a + dbh/2 - distance, the
  // point in the middle of the overlap; only where the element's centre is
  // not above the stem's top. False without overlap.
  bool Contact(const Eigen::Vector3d& c, double a, int k, int material, TerrainContact* out) const {
    const Stem& s = grid_.stem(k);
    if (c.z() > grid_.foot(k) + s.height) return false;
    const Eigen::Vector2d d(c.x() - s.x, c.y() - s.y);
    const double r = 0.5 * s.dbh;
    const double reach = r + a;
    const double d2 = d.squaredNorm();
    if (d2 >= reach * reach || !(d2 > 0.0)) return false;
    const double dist = std::sqrt(d2);
    out->normal = Eigen::Vector3d(d.x() / dist, d.y() / dist, 0.0);
    out->overlap = reach - dist;
    out->point = c - out->normal * (a - 0.5 * out->overlap);
    out->material = material;
    out->key = kStemKey + k;
    return true;
  }

  // The longest free flight from s, at most tau, before the rock's bounding
  // sphere may reach a trunk: in flight the plan motion is straight and
  // uniform, so the time it enters a stem's reach (bounding radius plus
  // trunk radius) is exact; a stem it passes over (its lowest point above
  // the top while within reach; the height along the parabola is lowest at
  // an end of that span) does not end the flight. 0 when it is within reach
  // of a stem it does not clear.
  double FlightTime(const RockState& s, double tau, double g) const {
    const Eigen::Vector2d p = s.x.head<2>(), v = s.v.head<2>();
    const Eigen::Vector2d q = p + tau * v;
    const double w = rb_ + grid_.max_radius();
    double best = tau;
    grid_.ForEachIn(std::min(p.x(), q.x()) - w, std::min(p.y(), q.y()) - w,
                    std::max(p.x(), q.x()) + w, std::max(p.y(), q.y()) + w, [&](int k) {
                      if (Broken(k)) return;
                      const Stem& st = grid_.stem(k);
                      const double reach = rb_ + 0.5 * st.dbh;
                      const Eigen::Vector2d d = p - Eigen::Vector2d(st.x, st.y);
                      // |d + v t|^2 = reach^2: a t^2 + 2 b t + c = 0.
                      const double a = v.squaredNorm(), b = d.dot(v);
                      const double c = d.squaredNorm() - reach * reach;
                      double enter = 0.0, leave = best;
                      if (c > 0.0) {
                        const double disc = b * b - a * c;
                        if (!(a > 0.0) || b >= 0.0 || disc <= 0.0) return;  // never reaches it
                        const double root = std::sqrt(disc);
                        enter = c / (-b + root);  // the smaller root, without cancellation
                        if (!(enter < best)) return;
                        leave = std::min(best, (-b + root) / a);
                      } else if (a > 0.0) {
                        leave = std::min(best, (-b + std::sqrt(b * b - a * c)) / a);
                      }
                      const double top = grid_.foot(k) + st.height + rb_;
                      auto z = [&](double t) { return s.x.z() + s.v.z() * t - 0.5 * g * t * t; };
                      if (z(enter) > top && z(leave) > top) return;  // passes over it
                      best = std::min(best, enter);
                    });
    return best;
  }

  // Stem k is broken for this rock: it leaves the list for the rest of the run.
  void Break(int k) {
    broken_.push_back(k);
    near_.erase(std::remove(near_.begin(), near_.end(), k), near_.end());
  }
  bool Broken(int k) const { return std::find(broken_.begin(), broken_.end(), k) != broken_.end(); }

 private:
  const StemGrid& grid_;
  const double rb_;  // the rock's bounding radius
  bool made_ = false;
  Eigen::Vector2d ref_ = Eigen::Vector2d::Zero();
  std::vector<int> near_, broken_;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_STEMS_H_
