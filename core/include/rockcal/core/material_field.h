// The material values a site gives, calibrates and changes with --set, in one
// list: the site reader, the calibration, the parameter tables and the
// reports all read their names, units and ranges from here. The forest's
// values are in the list too, as the fields of one more entry, "forest"
// (kForestEntry), that stands for the site's forest where a parameter or a
// --set names a material (docs/reference/site-file.md, `$.forest.calibrate`).
#ifndef ROCKCAL_CORE_MATERIAL_FIELD_H_
#define ROCKCAL_CORE_MATERIAL_FIELD_H_

#include <string>
#include <string_view>
#include <vector>

#include "rockcal/core/forest.h"
#include "rockcal/core/material.h"

namespace rockcal::core {

enum class MaterialField {
  kHardness,
  kRoughness,
  kContactTime,
  kRollingResistance,
  kFriction,
  kVegetation,
  kCapacityFactor,      // the forest's (Forest::capacity_factor)
  kTrunkRestitution,    // the forest's (TrunkContact::restitution)
  kTrunkFriction        // the forest's (TrunkContact::friction)
};

// The entry that holds the forest's fields, in the place of a material id.
inline constexpr const char* kForestEntry = "forest";

// kStress: kPa in SI site files, lbf/ft^2 in US ones; Pa inside.
enum class FieldUnit { kNone, kLength, kTime, kStress };

struct MaterialFieldInfo {
  MaterialField field;
  const char* name;   // the key in site files, --set and parameter tables
  const char* label;  // in prose
  FieldUnit unit;
  // Allowed range, SI. Roughness is further limited by half the grid
  // spacing, which only a site knows.
  double min, max;
  // A value of the site's forest (the entry kForestEntry), not of a ground
  // material.
  bool forest;
};

// The SI unit of a field's values in machine-read outputs: "", "m", "s", "Pa".
const char* SiUnitName(FieldUnit unit);

// Every field, in the order the tables list them.
const std::vector<MaterialFieldInfo>& MaterialFields();

const MaterialFieldInfo& Info(MaterialField field);

// The field called `name`, or nullptr.
const MaterialFieldInfo* FindMaterialField(std::string_view name);

// "hardness, roughness, ...": the names of a ground material's fields (not
// the forest's), for messages.
std::string MaterialFieldNames();

// The value a run uses: the material's own, or for friction and rolling
// resistance without one, the hardness model's. A forest field is not a
// material's (std::logic_error).
double FieldValue(const Material& material, MaterialField field, const HardnessModel& model);

// Sets the field (SI); friction and rolling resistance become explicit. A
// forest field is not a material's (std::logic_error).
void SetFieldValue(Material* material, MaterialField field, double value);

// A forest field's value, and setting it (SI): the capacity factor rescales
// every stem's capacity (StemCapacity at the new factor); the trunk
// contact's restitution and friction are Forest::contact's. A material's field is
// not the forest's (std::logic_error).
double ForestFieldValue(const Forest& forest, MaterialField field);
void SetForestFieldValue(Forest* forest, MaterialField field, double value);

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_MATERIAL_FIELD_H_
