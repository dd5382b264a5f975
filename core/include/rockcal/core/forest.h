// Forests (docs/physics.md, "Trees"): stems standing on the terrain, each a
// vertical cylinder a rock strikes through the contact law, with an energy
// capacity beyond which it breaks for that rock.
#ifndef ROCKCAL_CORE_FOREST_H_
#define ROCKCAL_CORE_FOREST_H_

#include <string>
#include <vector>

#include "rockcal/core/material.h"

namespace rockcal::core {

// A stem's species class: its capacity is the conifer curve times the
// class's relative fracture energy (StemCapacity).
enum class SpeciesClass { kConifer, kBroadleaf };
// "conifer", "broadleaf".
const char* SpeciesClassName(SpeciesClass species);

// Relative fracture energy of a broadleaf stem against Norway spruce
// (docs/physics.md, "Trees": Dorren & Berger 2006, Fagus sylvatica).
inline constexpr double kBroadleafFractureFactor = 1.59;

// The energy [J] a stem of diameter at breast height dbh [m] absorbs before
// it breaks: Dorren & Berger (2006) for Norway spruce, E = 38.7 DBH^2.31 J
// with DBH in cm, times the class's relative fracture energy, times
// `factor` (Forest::capacity_factor).
double StemCapacity(double dbh, SpeciesClass species, double factor = 1.0);

// One stem, SI units, in the scene's frame.
struct Stem {
  double x = 0.0, y = 0.0;  // m, its axis
  double dbh = 0.3;         // m, diameter at breast height (the cylinder's)
  double height = 20.0;     // m, above the ground at its axis
  SpeciesClass species = SpeciesClass::kConifer;
  double capacity = 0.0;  // J, StemCapacity of the above (Forest::Add sets it)
};

// The trunk's side of the contact law: what a user measures (restitution,
// contact time, friction), the stiffness and damping derived from them per
// unit rock mass as for a slope material (DeriveContactLaw), the trunk taken
// as fixed.
struct TrunkContact {
  double restitution = 0.3;    // rebound / impact speed of a head-on strike, (0, 1)
  double contact_time = 0.02;  // s, duration of a head-on strike, > 0
  double friction = 0.5;       // Coulomb coefficient on the bark, >= 0
};

struct Forest {
  std::vector<Stem> stems;
  TrunkContact contact;
  double capacity_factor = 1.0;  // scales every stem's capacity, > 0

  bool empty() const { return stems.empty(); }
  // Appends a stem with its capacity from dbh, species and capacity_factor.
  void Add(double x, double y, double dbh, double height, SpeciesClass species);
  // The trunk's contact law (a material of restitution, contact time and
  // friction, no rolling resistance, no undergrowth).
  ContactLaw Law() const;
  // Stems with 0 < dbh <= 5 m, height > 0, capacity > 0; the contact's
  // values in range. On failure sets *error (field, value, rule).
  bool IsValid(std::string* error) const;
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_FOREST_H_
