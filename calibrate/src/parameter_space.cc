#include "rockcal/calibrate/parameter_space.h"

#include <algorithm>
#include <cassert>

#include "rockcal/core/error.h"

namespace rockcal::calibrate {

std::string Parameter::name() const {
  return std::string(core::Info(kind).name) + (offset ? "_offset" : "");
}

std::string Parameter::label() const { return material + "." + name(); }

const std::string& Parameter::class_name() const {
  return material_class.empty() ? material : material_class;
}

ParameterSpace::ParameterSpace(std::vector<Parameter> parameters)
    : parameters_(std::move(parameters)) {}

ParameterSpace ParameterSpace::FromSite(const sites::Site& site) {
  std::vector<Parameter> out;
  const auto& materials = site.scene.materials;
  for (const sites::ParameterBound& b : site.calibrate) {
    Parameter p;
    p.material = b.material;
    p.material_class = b.material_class;
    p.lower = b.lower;
    p.upper = b.upper;
    const core::MaterialFieldInfo* field = core::FindMaterialField(b.name);
    assert(field);  // the site reader checked the name
    p.kind = field->field;
    if (field->forest) {
      p.material_index = -1;  // the forest's (core::kForestEntry)
    } else {
      auto it = std::find_if(materials.begin(), materials.end(),
                             [&](const core::Material& m) { return m.id == b.material; });
      assert(it != materials.end());  // the site reader checked the material
      p.material_index = static_cast<int>(it - materials.begin());
    }
    if (p.kind == ParameterKind::kRoughness && p.lower <= 0.0)
      throw InputError(site.path, "material '" + b.material +
                                      "': calibrate.roughness lower bound must be > 0 (roughness "
                                      "0 switches from virtual spheres to smooth facets, which "
                                      "no optimiser can search across)");
    out.push_back(p);
  }
  if (out.empty())
    throw InputError(site.path,
                     "nothing to calibrate: give a material a \"calibrate\" object with bounds, "
                     "e.g. \"calibrate\": {\"hardness\": [0.1, 0.6]}");
  return ParameterSpace(std::move(out));
}

std::vector<double> ParameterSpace::ToPhysical(const std::vector<double>& unit) const {
  assert(unit.size() == parameters_.size());
  std::vector<double> x(unit.size());
  for (std::size_t k = 0; k < unit.size(); ++k) {
    const Parameter& p = parameters_[k];
    x[k] = p.lower + std::clamp(unit[k], 0.0, 1.0) * (p.upper - p.lower);
  }
  return x;
}

std::vector<double> ParameterSpace::ToUnit(const std::vector<double>& physical) const {
  assert(physical.size() == parameters_.size());
  std::vector<double> u(physical.size());
  for (std::size_t k = 0; k < physical.size(); ++k) {
    const Parameter& p = parameters_[k];
    u[k] = std::clamp((physical[k] - p.lower) / (p.upper - p.lower), 0.0, 1.0);
  }
  return u;
}

std::vector<double> ParameterSpace::Current(const core::Scene& scene) const {
  std::vector<double> x;
  for (const Parameter& p : parameters_) {
    if (core::Info(p.kind).forest) {
      x.push_back(std::clamp(core::ForestFieldValue(scene.forest, p.kind), p.lower, p.upper));
      continue;
    }
    const core::Material& m = scene.materials[static_cast<std::size_t>(p.material_index)];
    // Friction and rolling resistance: explicit, or the hardness model's.
    const double v = core::FieldValue(m, p.kind, scene.hardness_model);
    x.push_back(std::clamp(v, p.lower, p.upper));
  }
  return x;
}

void ParameterSpace::Apply(const std::vector<double>& physical, core::Scene* scene) const {
  assert(physical.size() == parameters_.size());
  for (std::size_t k = 0; k < physical.size(); ++k) {
    const Parameter& p = parameters_[k];
    if (core::Info(p.kind).forest)
      core::SetForestFieldValue(&scene->forest, p.kind, physical[k]);
    else
      core::SetFieldValue(&scene->materials[static_cast<std::size_t>(p.material_index)], p.kind,
                          physical[k]);
  }
}

bool ParameterSpace::SameTerrain(const std::vector<double>& a, const std::vector<double>& b) const {
  for (std::size_t k = 0; k < parameters_.size(); ++k)
    if (parameters_[k].kind == ParameterKind::kRoughness && a[k] != b[k]) return false;
  return true;
}

}  // namespace rockcal::calibrate
