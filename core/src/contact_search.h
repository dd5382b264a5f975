// Contact detection of one rock (docs/physics.md, Integration): its neighbourhood
// of virtual spheres (a Verlet list), the element-sphere pairs within it
// that may touch (a second list one level down), and each element's
// contacts at a step. Internal to core (simulate.cc).
#ifndef ROCKCAL_CORE_SRC_CONTACT_SEARCH_H_
#define ROCKCAL_CORE_SRC_CONTACT_SEARCH_H_

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <vector>

#include "rockcal/core/rock_shape.h"
#include "rockcal/core/terrain.h"

namespace rockcal::core {

// Skin of the rock's neighbourhood list, in bounding radii: wider means
// fewer rebuilds, each scanning more cells, and a flight's look-ahead
// testing more spheres, each once per element: a sphere's is wider than a
// cluster's (the tutorial's spheres: 15 % fewer instructions at 1 than at
// 0.25, a third of the flights; Authume's blocks 6 % slower at 0.5).
inline constexpr double kSkin = 0.25;
inline constexpr double kSphereSkin = 1.0;
// Skin of the element-sphere pair lists, in element radii: wider means fewer
// rebuilds, each step testing more pairs (ContactSearch::UpdatePairs).
inline constexpr double kPairSkin = 0.2;

// kCluster: the rock's elements are off its centre (the rigid-cluster path);
// a sphere's one element is its centre. neighbours: false on the reference
// path, where every step tests the whole terrain.
template <bool kCluster>
class ContactSearch {
 public:
  ContactSearch(const Terrain& terrain, const RockBody& body, bool neighbours)
      : terrain_(terrain),
        body_(body),
        neighbours_(neighbours),
        single_element_(body.elements.size() == 1) {
    found_.reserve(16);
  }

  // The neighbourhood of the rock at centre x (a Verlet list): the virtual
  // spheres within a skin of its bounding sphere, and the clearance of the
  // floor surface, measured at near_ref_. Every element stays inside the
  // bounding sphere, so while the centre has moved less than the skin no
  // other sphere can be touched, and less than floor_clear_, not the floor.
  // Rebuilt when needed (then *rebuilt is set). keep: the fraction of the
  // skin the centre may have moved for the neighbourhood to be kept (less
  // before a flight). Returns the centre's distance from where it was made.
  double UpdateNeighbours(const Eigen::Vector3d& x, double keep, bool* rebuilt) {
    if (!neighbours_) return std::numeric_limits<double>::infinity();  // reference path: the floor tested every step
    const double moved = (x - near_ref_).norm();
    if (moved < keep * skin_) return moved;
    const double rb = body_.bounding_radius;
    skin_ = (single_element_ ? kSphereSkin : kSkin) * rb;
    terrain_.NearSpheres(x, rb, skin_, &near_);
    floor_clear_ = terrain_.FloorGap(x, rb, skin_, skin_);
    near_ref_ = x;
    pairs_valid_ = false;  // made for the old neighbourhood
    *rebuilt = true;
    return 0.0;
  }
  // The neighbourhood's spheres, skin and floor clearance.
  const std::vector<int>& near() const { return near_; }
  double skin() const { return skin_; }
  double floor_clear() const { return floor_clear_; }
  // The bounding sphere at x clears the floor surface (as of the last neighbourhood).
  bool FloorClear(const Eigen::Vector3d& x) const {
    return neighbours_ && (x - near_ref_).norm() < floor_clear_;
  }

  // The pair lists are to be made anew (after a flight, a step taken back).
  void InvalidatePairs() { pairs_valid_ = false; }

  // The element-sphere pairs of the neighbourhood that may touch (a Verlet
  // list one level down): pairs_[pair_start_[e] .. pair_start_[e + 1]) are
  // the spheres of near_ (in its order) within kPairSkin element radii of
  // element e, and floor_near_[e] says whether the floor is. No point of the
  // rock moves further in a step than its centre plus its turn at the
  // bounding radius (`travel`), so while the travel summed since the lists
  // were made stays below that skin, no other pair can touch and each step
  // tests only these: the same contacts in the same order as testing them
  // all. Made anew after a flight, a step taken back, or a new
  // neighbourhood (each sets pairs_valid_ false). False (no lists) on the
  // reference path. x, rot: the rock's centre and rotation, for the element
  // centres of new lists. moved: the centre's distance from the
  // neighbourhood's centre (UpdateNeighbours).
  bool UpdatePairs(const Eigen::Vector3d& x, double travel, double moved,
                   const Eigen::Matrix3d& rot) {
    if (!neighbours_) return false;
    const double skin = kPairSkin * body_.element_radius;
    pair_travel_ += travel;
    if (pairs_valid_ && pair_travel_ < skin) return true;
    if constexpr (kCluster) ElementCentres(x, rot);
    pairs_valid_ = true;
    pair_travel_ = 0.0;
    const std::size_t ne = body_.elements.size();
    const double a = body_.element_radius;
    pairs_.clear();
    pair_start_.resize(ne + 1);
    floor_near_.assign(ne, 0);
    // The floor is out of reach until the centre has moved floor_clear_.
    const bool floor = moved + skin >= floor_clear_;
    for (std::size_t e = 0; e < ne; ++e) {
      const Eigen::Vector3d& p = kCluster ? centres_[e] : x;
      pair_start_[e] = static_cast<int>(pairs_.size());
      for (int n : near_) {
        const double reach = terrain_.sphere_radius(n) + a + skin;
        if ((p - terrain_.sphere_centre(n)).squaredNorm() < reach * reach) pairs_.push_back(n);
      }
      if (floor) floor_near_[e] = terrain_.FloorGap(p, a, skin, skin) < skin;
    }
    pair_start_[ne] = static_cast<int>(pairs_.size());
    return true;
  }

  // The world centres of the elements of a rock at x turned by rot (centre).
  void ElementCentres(const Eigen::Vector3d& x, const Eigen::Matrix3d& rot) {
    centres_.resize(body_.elements.size());
    for (std::size_t e = 0; e < body_.elements.size(); ++e) centres_[e] = x + rot * body_.elements[e];
  }
  const Eigen::Vector3d& centre(std::size_t e) const { return centres_[e]; }

  // The contacts of element e of the rock at x turned by rot, at a step:
  // from its pairs when `paired` (UpdatePairs returned true), else from the
  // whole neighbourhood (the element centres already made). floor: the
  // floor may be reached (UpdateNeighbours' moved >= floor_clear()). Null
  // when the element has no pair and no floor near: it cannot touch.
  const std::vector<TerrainContact>* StepContacts(std::size_t e, const Eigen::Vector3d& x,
                                                  const Eigen::Matrix3d& rot, bool paired,
                                                  bool floor) {
    const double a = body_.element_radius;
    if (paired) {
      // An element with no pair and no floor near cannot touch: its
      // centre is not even needed.
      const int* begin = pairs_.data() + pair_start_[e];
      const int* end = pairs_.data() + pair_start_[e + 1];
      const bool floor_near = floor && floor_near_[e];
      if (begin == end && !floor_near) return nullptr;
      if constexpr (kCluster) centres_[e] = x + rot * body_.elements[e];
      const Eigen::Vector3d& centre = kCluster ? centres_[e] : x;
      found_.clear();
      terrain_.SphereContacts(centre, a, begin, end, &found_);
      if (floor_near) terrain_.FloorContacts(centre, a, &found_);
      return &found_;
    }
    return &FindElementContacts(kCluster ? centres_[e] : x, floor, a);
  }

  // The contacts of an element centred at `centre`; the floor (facets and
  // catch surface) only where the rock may reach it. `a`: the element's
  // radius, or more for a landing's tolerance.
  const std::vector<TerrainContact>& FindElementContacts(const Eigen::Vector3d& centre, bool floor,
                                                         double a) {
    found_.clear();
    if (neighbours_) {
      terrain_.SphereContacts(centre, a, near_.data(), near_.data() + near_.size(), &found_);
      if (floor) terrain_.FloorContacts(centre, a, &found_);
    } else {
      terrain_.FindContacts(centre, a, &found_);
    }
    return found_;
  }

 private:
  const Terrain& terrain_;
  const RockBody& body_;
  const bool neighbours_;      // off on the reference path
  const bool single_element_;  // a sphere (on either path)
  // The neighbourhood (UpdateNeighbours): virtual spheres within skin_ of the
  // bounding sphere at near_ref_, and the floor's clearance there.
  Eigen::Vector3d near_ref_ = Eigen::Vector3d::Zero();
  double skin_ = 0.0, floor_clear_ = 0.0;
  std::vector<int> near_;
  std::vector<Eigen::Vector3d> centres_;  // element centres (ElementCentres)
  // The pairs that may touch (UpdatePairs): valid while the travel since
  // they were made stays below their skin, within one neighbourhood.
  std::vector<int> pairs_, pair_start_;
  std::vector<char> floor_near_;
  bool pairs_valid_ = false;
  double pair_travel_ = 0.0;
  std::vector<TerrainContact> found_;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_SRC_CONTACT_SEARCH_H_
