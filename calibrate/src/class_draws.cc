#include "rockcal/calibrate/class_draws.h"

#include "rockcal/core/random.h"

namespace rockcal::calibrate {
namespace {

// The random stream of the class draws ("CLAS").
constexpr std::uint64_t kClassStream = 0x434c415300000000ull;

}  // namespace

CalibratedSite ClassParameters(const sites::Site& site) {
  CalibratedSite out;
  out.site = site.scene.name;
  for (const sites::ClassMaterial& c : site.class_materials) {
    if (out.file.find(c.table) == std::string::npos)
      out.file += (out.file.empty() ? "" : ", ") + c.table;
    for (const sites::ClassRow& row : c.from_table) {
      if (!row.low) continue;
      CalibratedParameter p;
      p.material = c.material;
      p.material_class = c.material_class;
      p.name = row.parameter;
      p.value = row.median;
      p.lower = *row.low;
      p.upper = *row.high;
      out.parameters.push_back(p);
    }
  }
  return out;
}

std::vector<std::vector<double>> ClassDrawSamples(const CalibratedSite& parameters, int draws,
                                                  std::uint64_t seed) {
  core::RandomStream rng(seed, kClassStream);
  std::vector<std::vector<double>> samples(static_cast<std::size_t>(draws));
  for (std::vector<double>& set : samples)
    for (const CalibratedParameter& p : parameters.parameters)
      set.push_back(p.lower + (p.upper - p.lower) * rng.Uniform());
  return samples;
}

}  // namespace rockcal::calibrate
