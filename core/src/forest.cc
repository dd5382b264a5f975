#include "rockcal/core/forest.h"

#include <cmath>
#include <sstream>

namespace rockcal::core {

const char* SpeciesClassName(SpeciesClass species) {
  switch (species) {
    case SpeciesClass::kConifer:
      return "conifer";
    case SpeciesClass::kBroadleaf:
      return "broadleaf";
  }
  return "?";
}

double StemCapacity(double dbh, SpeciesClass species, double factor) {
  // Dorren & Berger (2006): E = 38.7 DBH^2.31 [J], DBH in cm (Norway spruce).
  const double spruce = 38.7 * std::pow(100.0 * dbh, 2.31);
  const double relative = species == SpeciesClass::kBroadleaf ? kBroadleafFractureFactor : 1.0;
  return spruce * relative * factor;
}

void Forest::Add(double x, double y, double dbh, double height, SpeciesClass species) {
  Stem s;
  s.x = x;
  s.y = y;
  s.dbh = dbh;
  s.height = height;
  s.species = species;
  s.capacity = StemCapacity(dbh, species, capacity_factor);
  stems.push_back(s);
}

ContactLaw Forest::Law() const {
  Material m;
  m.id = "trunk";
  m.contact_time_s = contact.contact_time;
  m.restitution = contact.restitution;
  m.friction = contact.friction;
  m.rolling_resistance = 0.0;
  return DeriveContactLaw(m);
}

bool Forest::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, double value, const char* rule) {
    std::ostringstream s;
    s << "forest." << field << " = " << value << ": " << rule;
    *error = s.str();
    return false;
  };
  if (!(contact.restitution > 0 && contact.restitution < 1))
    return fail("contact.restitution", contact.restitution, "must be in (0, 1)");
  if (!(contact.contact_time > 0 && std::isfinite(contact.contact_time)))
    return fail("contact.contact_time", contact.contact_time, "must be > 0");
  if (!(contact.friction >= 0 && std::isfinite(contact.friction)))
    return fail("contact.friction", contact.friction, "must be >= 0");
  if (!(capacity_factor > 0 && std::isfinite(capacity_factor)))
    return fail("capacity_factor", capacity_factor, "must be > 0");
  for (std::size_t k = 0; k < stems.size(); ++k) {
    const Stem& s = stems[k];
    const std::string at = "stems[" + std::to_string(k) + "].";
    if (!(std::isfinite(s.x) && std::isfinite(s.y))) return fail(at + "x", s.x, "must be finite");
    if (!(s.dbh > 0 && s.dbh <= 5.0)) return fail(at + "dbh", s.dbh, "must be in (0, 5] m");
    if (!(s.height > 0 && std::isfinite(s.height)))
      return fail(at + "height", s.height, "must be > 0");
    if (!(s.capacity > 0 && std::isfinite(s.capacity)))
      return fail(at + "capacity", s.capacity, "must be > 0");
  }
  return true;
}

}  // namespace rockcal::core
