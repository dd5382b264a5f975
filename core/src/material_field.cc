#include "rockcal/core/material_field.h"

#include <limits>

#include "rockcal/core/limits.h"

namespace rockcal::core {

const std::vector<MaterialFieldInfo>& MaterialFields() {
  static const std::vector<MaterialFieldInfo> fields = {
      {MaterialField::kHardness, "hardness", "hardness", FieldUnit::kNone, 0.0, 1.0},
      {MaterialField::kRoughness, "roughness", "roughness", FieldUnit::kLength, 0.0,
       std::numeric_limits<double>::infinity()},
      {MaterialField::kContactTime, "contact_time", "contact time", FieldUnit::kTime,
       kMinContactTime, kMaxContactTime},
      {MaterialField::kRollingResistance, "rolling_resistance", "rolling resistance",
       FieldUnit::kNone, 0.0, 1.0},
      {MaterialField::kFriction, "friction", "friction", FieldUnit::kNone, 0.0, 10.0},
      {MaterialField::kVegetation, "vegetation", "vegetation resistance", FieldUnit::kStress, 0.0,
       kMaxVegetationStress},
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
  for (const MaterialFieldInfo& f : MaterialFields()) out += (out.empty() ? "" : ", ") + std::string(f.name);
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
  }
  return 0.0;
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
  }
}

}  // namespace rockcal::core
