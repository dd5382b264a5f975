// The joint parameter space of a campaign (campaign.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "rockcal/calibrate/campaign.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/format.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/material_field.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/json_reader.h"

namespace rockcal::calibrate {
namespace {

using core::FormatNumber;

std::string Interval(double lower, double upper) {
  return "[" + FormatNumber(lower) + ", " + FormatNumber(upper) + "]";
}

}  // namespace

// A joint value: (site, class, kind); the site is empty for a shared class.
struct JointSpace::Builder {
  using Key = std::tuple<std::string, std::string, ParameterKind>;
  std::string where;  // the campaign file, for the errors
  std::map<Key, int> index;
  std::vector<Parameter> parameters;
  // Who contributed each value's bounds: "site 'a' material 'talus' [0.1, 0.6]".
  std::vector<std::vector<std::string>> sources;
  std::vector<std::pair<double, double>> first_bounds;
  // The sphere spacing of the site that first gave each value.
  std::vector<std::pair<std::string, double>> first_spacing;
};

namespace {

bool SharedClass(const Campaign& campaign, const std::string& cls) {
  return campaign.shared.empty() ||
         std::find(campaign.shared.begin(), campaign.shared.end(), cls) != campaign.shared.end();
}

}  // namespace

JointSpace::JointSpace(const Campaign& campaign) {
  Builder b;
  b.where = campaign.path.empty() ? std::string("campaign") : campaign.path;
  AddSites(campaign, &b);
  CheckBounds(campaign, b);
  AddOffsets(campaign, &b);
  space_ = ParameterSpace(std::move(b.parameters));
}

// Each site's parameters onto the joint values: a shared class's values
// once for all sites (their bounds intersected), another's once per site.
void JointSpace::AddSites(const Campaign& campaign, Builder* b) {
  for (std::size_t s = 0; s < campaign.sites.size(); ++s) {
    const CampaignSite& site = campaign.sites[s];
    site_spaces_.push_back(ParameterSpace::FromSite(site.site));
    std::vector<Term> terms;
    for (const Parameter& p : site_spaces_.back().parameters()) {
      const std::string& cls = p.class_name();
      const Builder::Key key{SharedClass(campaign, cls) ? std::string() : site.name, cls, p.kind};
      auto it = b->index.find(key);
      if (it == b->index.end()) {
        Parameter q;
        q.material = std::get<0>(key).empty() ? cls : site.name + ":" + cls;
        q.material_class = cls;
        q.site = std::get<0>(key);
        q.kind = p.kind;
        q.lower = p.lower;
        q.upper = p.upper;
        q.material_index = -1;
        it = b->index.emplace(key, static_cast<int>(b->parameters.size())).first;
        b->parameters.push_back(q);
        b->sources.emplace_back();
        b->first_bounds.emplace_back(p.lower, p.upper);
        b->first_spacing.emplace_back(site.name, site.site.scene.grid.spacing);
      } else {
        Parameter& q = b->parameters[static_cast<std::size_t>(it->second)];
        const auto& [first_site, spacing] = b->first_spacing[static_cast<std::size_t>(it->second)];
        const double here = site.site.scene.grid.spacing;
        if (p.kind == ParameterKind::kRoughness && std::abs(here - spacing) > 1e-9 * spacing)
          throw InputError(b->where, "class '" + cls +
                                         "' roughness is shared by sites whose virtual "
                                         "spheres are spaced differently ('" +
                                         first_site + "' " + FormatNumber(spacing) + " m, '" +
                                         site.name + "' " + FormatNumber(here) +
                                         " m); a roughness means one ground only "
                                         "at one sphere spacing: expected one "
                                         "surface.sphere_spacing for these sites, or the class "
                                         "left out of \"shared\"");
        q.lower = std::max(q.lower, p.lower);
        q.upper = std::min(q.upper, p.upper);
      }
      b->sources[static_cast<std::size_t>(it->second)].push_back(
          "site '" + site.name + "' material '" + p.material + "' " + Interval(p.lower, p.upper));
      terms.push_back({it->second, kNoOffset});
    }
    sites_.push_back(std::move(terms));
  }
}

// Every joint value has a common interval (narrowed ones noted), and every
// shared class is calibrated by some site.
void JointSpace::CheckBounds(const Campaign& campaign, const Builder& b) {
  for (std::size_t k = 0; k < b.parameters.size(); ++k) {
    const Parameter& q = b.parameters[k];
    std::string from;
    for (const std::string& s : b.sources[k]) from += (from.empty() ? "" : ", ") + s;
    if (!(q.lower < q.upper))
      throw InputError(b.where, "class '" + q.material_class + "' " + q.name() +
                                    ": the bounds of the sites sharing it have no common "
                                    "interval (" +
                                    from +
                                    "); expected overlapping \"calibrate\" bounds, or leave "
                                    "the class out of \"shared\"");
    if (q.lower != b.first_bounds[k].first || q.upper != b.first_bounds[k].second)
      notes_.push_back("class " + q.material_class + " " + q.name() + ": bounds " +
                       Interval(q.lower, q.upper) + ", the intersection of " + from);
  }
  for (const std::string& cls : campaign.shared) {
    bool found = false;
    for (const Parameter& q : b.parameters) found = found || q.material_class == cls;
    if (!found)
      throw InputError(b.where + ": $.shared",
                       "class '" + cls +
                           "': no site calibrates a material of this class; "
                           "expected a class of the sites' materials with \"calibrate\" bounds");
  }
}

// Each offset prior: a parameter per site calibrating the shared value but
// the last, whose offset is minus their sum (the offsets sum to zero).
void JointSpace::AddOffsets(const Campaign& campaign, Builder* b) {
  for (std::size_t o = 0; o < campaign.offsets.size(); ++o) {
    const OffsetPrior& prior = campaign.offsets[o];
    const std::string path = b->where + ": $.offsets[" + std::to_string(o) + "]";
    const core::MaterialFieldInfo* field = core::FindMaterialField(prior.parameter);
    if (!field)
      throw InputError(path + ".parameter",
                       "'" + prior.parameter +
                           "': unknown parameter (allowed: " + core::MaterialFieldNames() + ")");
    if (!(prior.sigma > 0))
      throw InputError(path + ".sigma", FormatNumber(prior.sigma) + ": expected a sigma > 0");
    if (!SharedClass(campaign, prior.class_name))
      throw InputError(path + ".class", "class '" + prior.class_name +
                                            "' is not shared (not in \"shared\"): an offset is a "
                                            "site's departure from a shared value");
    const auto it = b->index.find(Builder::Key{std::string(), prior.class_name, field->field});
    if (it == b->index.end())
      throw InputError(path, "class '" + prior.class_name + "' " + prior.parameter +
                                 ": no site calibrates it; expected a class and parameter of the "
                                 "sites' \"calibrate\" bounds");
    // The sites calibrating it, in order.
    std::vector<std::size_t> with;
    for (std::size_t s = 0; s < campaign.sites.size(); ++s)
      for (const Term& t : sites_[s])
        if (t.value == it->second) {
          with.push_back(s);
          break;
        }
    std::vector<int> free;
    for (std::size_t w = 0; w + 1 < with.size(); ++w) {
      Parameter q = b->parameters[static_cast<std::size_t>(it->second)];
      q.site = campaign.sites[with[w]].name;
      q.material = q.site + ":" + prior.class_name;
      q.offset = true;
      q.lower = -3.0 * prior.sigma;
      q.upper = 3.0 * prior.sigma;
      free.push_back(static_cast<int>(b->parameters.size()));
      b->parameters.push_back(q);
    }
    for (std::size_t w = 0; w < with.size() && with.size() > 1; ++w) {
      Offset offset;
      offset.sigma = prior.sigma;
      offset.id.kind = observations::ObservationKind::kPrior;
      offset.id.index = static_cast<int>(offsets_.size());
      offset.id.name = prior.class_name + "." + prior.parameter;
      offset.id.statistic = observations::Statistic::kOffset;
      offset.id.site = campaign.sites[with[w]].name;
      if (w + 1 < with.size())
        offset.terms = {{free[w], 1.0}};
      else
        for (int f : free) offset.terms.emplace_back(f, -1.0);
      for (Term& t : sites_[with[w]])
        if (t.value == it->second) t.offset = offsets_.size();
      offsets_.push_back(std::move(offset));
    }
  }
}

double JointSpace::Offset::Value(const std::vector<double>& joint) const {
  double v = 0.0;
  for (const auto& [index, sign] : terms) v += sign * joint[static_cast<std::size_t>(index)];
  return v;
}

const ParameterSpace& JointSpace::site_space(int site) const {
  return site_spaces_[static_cast<std::size_t>(site)];
}

std::vector<double> JointSpace::SiteValues(int site, const std::vector<double>& joint) const {
  const std::vector<Term>& terms = sites_[static_cast<std::size_t>(site)];
  const std::vector<Parameter>& own = site_space(site).parameters();
  std::vector<double> x(terms.size());
  for (std::size_t k = 0; k < terms.size(); ++k) {
    double v = joint[static_cast<std::size_t>(terms[k].value)];
    if (terms[k].offset != kNoOffset) v += offsets_[terms[k].offset].Value(joint);
    x[k] = std::clamp(v, own[k].lower, own[k].upper);
  }
  return x;
}

std::vector<double> JointSpace::FromSiteValues(
    const std::vector<std::vector<double>>& site_values) const {
  const std::size_t n = static_cast<std::size_t>(space_.size());
  std::vector<double> sum(n, 0.0);
  std::vector<int> count(n, 0);
  for (std::size_t s = 0; s < sites_.size(); ++s)
    for (std::size_t k = 0; k < sites_[s].size(); ++k) {
      const std::size_t j = static_cast<std::size_t>(sites_[s][k].value);
      sum[j] += site_values[s][k];
      ++count[j];
    }
  std::vector<double> joint(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const Parameter& p = space_.parameters()[j];
    if (!p.offset && count[j] > 0) joint[j] = std::clamp(sum[j] / count[j], p.lower, p.upper);
  }
  return joint;
}

std::vector<observations::Residual> JointSpace::PriorResiduals(
    const std::vector<double>& joint) const {
  std::vector<observations::Residual> out;
  for (const Offset& o : offsets_) {
    observations::Residual r;
    r.id = o.id;
    r.simulated = o.Value(joint);
    r.observed = 0.0;
    r.sigma = o.sigma;
    r.value = r.simulated / o.sigma;
    out.push_back(r);
  }
  return out;
}

}  // namespace rockcal::calibrate
