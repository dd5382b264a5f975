#include "rockcal/core/material_field.h"

#include <limits>
#include <stdexcept>

#include "rockcal/core/limits.h"

namespace rockcal::core {
namespace {

// A forest's capacity factor (docs/reference/site-file.md, `$.forest`).
constexpr double kMinCapacityFactor = 0.01;
constexpr double kMaxCapacityFactor = 100.0;
// The trunk contact's restitution, (0, 1) in the site file, calibrated
// within [0.01, 0.99]; its friction as the ground's.
constexpr double kMinTrunkRestitution = 0.01;
constexpr double kMaxTrunkRestitution = 0.99;

}  // namespace

const std::vector<MaterialFieldInfo>& MaterialFields() {
  static const std::vector<MaterialFieldInfo> fields = {
      {MaterialField::kHardness, "hardness", "hardness", FieldUnit::kNone, 0.0, 1.0, false},
      {MaterialField::kRoughness, "roughness", "roughness", FieldUnit::kLength, 0.0,
       std::numeric_limits<double>::infinity(), false},
      {MaterialField::kContactTime, "contact_time", "contact time", FieldUnit::kTime,
       kMinContactTime, kMaxContactTime, false},
      {MaterialField::kRollingResistance, "rolling_resistance", "rolling resistance",
       FieldUnit::kNone, 0.0, 1.0, false},
      {MaterialField::kFriction, "friction", "friction", FieldUnit::kNone, 0.0, 10.0, false},
      {MaterialField::kVegetation, "vegetation", "vegetation resistance", FieldUnit::kStress, 0.0,
       kMaxVegetationStress, false},
      // docs/physics.md, Trees: scales Dorren & Berger's capacity curves.
      {MaterialField::kCapacityFactor, "capacity_factor", "capacity factor", FieldUnit::kNone,
       kMinCapacityFactor, kMaxCapacityFactor, true},
      // docs/physics.md, Trees: the trunk's side of the contact law.
      {MaterialField::kTrunkRestitution, "contact_restitution", "trunk restitution",
       FieldUnit::kNone, kMinTrunkRestitution, kMaxTrunkRestitution, true},
      {MaterialField::kTrunkFriction, "contact_friction", "trunk friction", FieldUnit::kNone, 0.0,
       10.0, true},
  };
  return fields;
}

const char* SiUnitName(FieldUnit unit) {
  switch (unit) {
    case FieldUnit::kLength:
      return "m";
    case FieldUnit::kTime:
      return "s";
    case FieldUnit::kStress:
      return "Pa";
    case FieldUnit::kNone:
      break;
  }
  return "";
}

const MaterialFieldInfo& Info(MaterialField field) {
  return MaterialFields()[static_cast<std::size_t>(field)];
}

const MaterialFieldInfo* FindMaterialField(std::string_view name) {
  for (const MaterialFieldInfo& f : MaterialFields())
    if (name == f.name) return &f;
  return nullptr;
}

std::string MaterialFieldNames() {
  std::string out;
  for (const MaterialFieldInfo& f : MaterialFields())
    if (!f.forest) out += (out.empty() ? "" : ", ") + std::string(f.name);
  return out;
}

double FieldValue(const Material& material, MaterialField field, const HardnessModel& model) {
  switch (field) {
    case MaterialField::kHardness:
      return material.hardness;
    case MaterialField::kRoughness:
      return material.roughness_m;
    case MaterialField::kContactTime:
      return material.contact_time_s;
    case MaterialField::kRollingResistance:
      return DeriveContactLaw(material, model).rolling_resistance;
    case MaterialField::kFriction:
      return DeriveContactLaw(material, model).friction;
    case MaterialField::kVegetation:
      return material.vegetation_pa;
    case MaterialField::kCapacityFactor:
    case MaterialField::kTrunkRestitution:
    case MaterialField::kTrunkFriction:
      break;
  }
  throw std::logic_error(std::string("FieldValue: ") + Info(field).name +
                         " is the forest's, not a material's");
}

void SetFieldValue(Material* material, MaterialField field, double value) {
  switch (field) {
    case MaterialField::kHardness:
      material->hardness = value;
      break;
    case MaterialField::kRoughness:
      material->roughness_m = value;
      break;
    case MaterialField::kContactTime:
      material->contact_time_s = value;
      break;
    case MaterialField::kRollingResistance:
      material->rolling_resistance = value;
      break;
    case MaterialField::kFriction:
      material->friction = value;
      break;
    case MaterialField::kVegetation:
      material->vegetation_pa = value;
      break;
    case MaterialField::kCapacityFactor:
    case MaterialField::kTrunkRestitution:
    case MaterialField::kTrunkFriction:
      throw std::logic_error(std::string("SetFieldValue: ") + Info(field).name +
                             " is the forest's, not a material's");
  }
}

double ForestFieldValue(const Forest& forest, MaterialField field) {
  switch (field) {
    case MaterialField::kCapacityFactor:
      return forest.capacity_factor;
    case MaterialField::kTrunkRestitution:
      return forest.contact.restitution;
    case MaterialField::kTrunkFriction:
      return forest.contact.friction;
    default:
      throw std::logic_error(std::string("ForestFieldValue: ") + Info(field).name +
                             " is a material's, not the forest's");
  }
}

void SetForestFieldValue(Forest* forest, MaterialField field, double value) {
  switch (field) {
    case MaterialField::kCapacityFactor:
      forest->capacity_factor = value;
      for (Stem& s : forest->stems) s.capacity = StemCapacity(s.dbh, s.species, value);
      return;
    case MaterialField::kTrunkRestitution:
      forest->contact.restitution = value;
      return;
    case MaterialField::kTrunkFriction:
      forest->contact.friction = value;
      return;
    default:
      throw std::logic_error(std::string("SetForestFieldValue: ") + Info(field).name +
                             " is a material's, not the forest's");
  }
}

}  // namespace rockcal::core
