// The time steps of a rock on a contact law: the stable step, the contact
// step, the gentle step and the smallest step of a group and of a scene
// (simulate.h), and a rock's steps on each material (contact_forces.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "contact_forces.h"
#include "rockcal/core/numbers.h"
#include "rockcal/core/simulate.h"

namespace rockcal::core {
namespace {

// Stiff contacts that may act on one body at once (rough terrain: a rock
// between nodes touches two virtual spheres); part of the stable-step bound.
constexpr double kParallelContacts = 2.0;

// The stable step of `body` on `law`: `safety` times the critical step
// 2 / omega of its stiffest contact. The damping ratio does not shorten it:
// every dashpot is implicit, for the rock's spin as for its centre, and
// together with the step's other contacts (contact_forces.h, JointEndMotion), and the
// central-difference step with implicit dashpots is stable up to
// omega dt = 2 whatever the damping (bench/README.md, "The step").
double StableTimeStep(const RockBody& body, const ContactLaw& law, double safety) {
  // An off-centre contact on a cluster acts on a smaller effective mass:
  // 1/m_eff = 1/m + l^2 / I_min for a lever arm l.
  double mass_ratio = 1.0;
  if (body.elements.size() > 1) {
    double arm = 0.0;
    for (const auto& e : body.elements) arm = std::max(arm, e.norm());
    arm += body.element_radius;
    mass_ratio += body.mass * arm * arm / body.inertia.minCoeff();
  }
  const double omega = std::sqrt(law.stiffness_per_mass * mass_ratio * kParallelContacts);
  return safety * 2.0 / omega;
}

}  // namespace

double ContactTimeStep(const RockBody& body, const ContactLaw& law, const SimulationOptions& opt,
                       bool* shrunk) {
  const double by_contact = law.contact_time / opt.steps_per_contact;
  const double stable = StableTimeStep(body, law, opt.safety);
  if (shrunk) *shrunk = stable < by_contact;
  return std::min(by_contact, stable);
}

double GroupContactStep(const Scene& scene, const RockGroup& group, bool* shrunk) {
  const GroupExtent extent = GroupBodies(group, scene.gravity);
  double dt = kInf;
  bool any = false;
  std::vector<ContactLaw> laws;
  for (const Material& m : scene.materials)
    laws.push_back(DeriveContactLaw(m, scene.hardness_model));
  if (!scene.forest.empty()) laws.push_back(scene.forest.Law());  // the trunks'
  for (const RockBody* body : {&extent.lightest, &extent.heaviest}) {
    for (const ContactLaw& law : laws) {
      bool sh = false;
      dt = std::min(dt, ContactTimeStep(*body, law, scene.options, &sh));
      any = any || sh;
    }
  }
  if (shrunk) *shrunk = any;
  return dt;
}

double SmallestContactStep(const Scene& scene) {
  double dt = kInf;
  for (const RockGroup& g : scene.groups) dt = std::min(dt, GroupContactStep(scene, g));
  return dt;
}

double GentleTimeStep(const RockBody& body, const ContactLaw& law, const SimulationOptions& opt) {
  if (opt.gentle_steps_per_contact <= 0 || opt.reference_path) return 0.0;
  return std::min(law.contact_time / opt.gentle_steps_per_contact,
                  StableTimeStep(body, law, opt.gentle_safety));
}

StepSizes RockSteps(const RockBody& body, const std::vector<ContactLaw>& laws, const Scene& scene,
                    bool* any_shrunk) {
  StepSizes steps;
  steps.finest = kInf;
  for (const auto& law : laws) {
    bool sh = false;
    const double dt = ContactTimeStep(body, law, scene.options, &sh);
    steps.material.push_back({dt, std::max(dt, GentleTimeStep(body, law, scene.options)),
                              scene.gravity * law.contact_time});
    steps.finest = std::min(steps.finest, dt);
    *any_shrunk = *any_shrunk || sh;
  }
  return steps;
}

}  // namespace rockcal::core
