// The calibrated parameters of a site, and the map between their physical
// values and the unit box the optimisers search.
#ifndef ROCKCAL_CALIBRATE_PARAMETER_SPACE_H_
#define ROCKCAL_CALIBRATE_PARAMETER_SPACE_H_

#include <string>
#include <vector>

#include "rockcal/core/material_field.h"
#include "rockcal/core/scene.h"
#include "rockcal/sites/site.h"

namespace rockcal::calibrate {

// What a parameter is: one of the material values of core::MaterialFields().
using ParameterKind = core::MaterialField;

struct Parameter {
  // Material id, or core::kForestEntry ("forest") for a forest field
  // (core::MaterialFieldInfo::forest): the scene's forest holds its value.
  std::string material;
  // The material's class for default tables (sites::Site::material_classes);
  // empty means the material id.
  std::string material_class;
  int material_index = 0;  // in Scene::materials; -1 for a forest field
  ParameterKind kind = ParameterKind::kHardness;
  double lower = 0.0, upper = 1.0;  // SI (roughness m, contact time s)
  // A joint parameter of a campaign (JointSpace), whose `material` is the
  // class ("talus"), or "<site>:<class>" for one of a single site: the site
  // it belongs to, empty when the sites share it (and in a single site's
  // calibration); and whether it is that site's offset from the shared
  // value rather than a value.
  std::string site;
  bool offset = false;

  // core::Info(kind).name: "hardness", "roughness", ...; an offset's with
  // "_offset" after it ("hardness_offset").
  std::string name() const;
  std::string label() const;  // "talus.hardness"
  // material_class, or the material id when it is empty.
  const std::string& class_name() const;
};

class ParameterSpace final {
 public:
  ParameterSpace() = default;
  explicit ParameterSpace(std::vector<Parameter> parameters);
  // The parameters of the site's "calibrate" bounds. Throws InputError when
  // there are none, or a bound cannot be searched (a roughness range touching
  // 0 switches between virtual spheres and smooth facets: not continuous).
  static ParameterSpace FromSite(const sites::Site& site);

  int size() const { return static_cast<int>(parameters_.size()); }
  const std::vector<Parameter>& parameters() const { return parameters_; }
  // Unit box [0, 1]^n <-> physical values (linear within the bounds).
  std::vector<double> ToPhysical(const std::vector<double>& unit) const;
  std::vector<double> ToUnit(const std::vector<double>& physical) const;
  // The scene's current values of the parameters, clamped into the bounds.
  std::vector<double> Current(const core::Scene& scene) const;
  // Sets the parameters of `scene` to `physical`.
  void Apply(const std::vector<double>& physical, core::Scene* scene) const;
  // True when only hardness or contact time change between a and b (the
  // terrain's virtual spheres can be reused).
  bool SameTerrain(const std::vector<double>& a, const std::vector<double>& b) const;

 private:
  std::vector<Parameter> parameters_;
};

}  // namespace rockcal::calibrate

#endif  // ROCKCAL_CALIBRATE_PARAMETER_SPACE_H_
