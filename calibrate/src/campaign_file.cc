// The campaign file's reader (campaign.h).
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

namespace fs = std::filesystem;

// A file named at `node`, relative to the campaign file's folder; a missing
// one is an InputError at the node.
std::string ResolveFile(const sites::JsonNode& node, const fs::path& dir, const char* what) {
  const std::string name = node.String();
  const fs::path p = fs::path(name).is_absolute() ? fs::path(name) : dir / name;
  std::error_code ec;
  if (!fs::exists(p, ec))
    node.Fail(std::string("no such file: ") + p.string() + "; expected " + what +
              " (relative to the campaign file)");
  const std::string problem = sites::InputFileProblem(p.string(), what);
  if (!problem.empty()) node.Fail(problem);
  return p.string();
}

}  // namespace

// ---- the campaign file -------------------------------------------------------

Campaign LoadCampaign(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(path, "no such file; expected a campaign file (JSON listing the sites)");
  const nlohmann::json json = sites::ReadJsonFile(path);
  const sites::JsonNode root(&json, path, "$");
  if (!root.is_object()) root.Fail("expected a JSON object (a campaign file)");
  root.Keys({"name", "units", "sites", "shared", "offsets"});
  Campaign c;
  c.path = path;
  c.name = root.Has("name") ? root.Get("name").String() : fs::path(path).stem().string();
  c.units = sites::ReadUnits(root.Get("units"));
  c.inputs.push_back(path);
  const fs::path dir = fs::path(path).parent_path();
  const std::vector<sites::JsonNode> list = root.Get("sites").Array(1);
  for (const sites::JsonNode& node : list) {
    if (!node.is_object()) node.Fail("expected an object {\"site\": ..., \"observations\": ...}");
    node.Keys({"site", "observations", "name", "rocks", "weight"});
    CampaignSite s;
    s.site = sites::LoadSite(ResolveFile(node.Get("site"), dir, "a site file"));
    const std::string obs = ResolveFile(node.Get("observations"), dir, "an observations file");
    s.observations = observations::LoadObservations(obs, s.site.scene);
    s.name = node.Has("name") ? node.Get("name").String() : s.site.scene.name;
    if (s.name.empty()) node.Fail("the site has no name: give the campaign's site a \"name\"");
    for (const CampaignSite& other : c.sites)
      if (other.name == s.name)
        (node.Has("name") ? node.Get("name") : node)
            .Fail("two sites named '" + s.name +
                  "': give each site of the campaign a unique \"name\"");
    if (node.Has("rocks"))
      s.rocks = static_cast<int>(node.Get("rocks").Integer(1, core::kMaxRocks));
    if (node.Has("weight")) s.weight = node.Get("weight").Positive();
    for (const std::string& f :
         s.site.inputs.empty() ? std::vector<std::string>{s.site.path} : s.site.inputs)
      c.inputs.push_back(f);
    for (const std::string& f :
         s.observations.inputs.empty() ? std::vector<std::string>{obs} : s.observations.inputs)
      c.inputs.push_back(f);
    c.sites.push_back(std::move(s));
  }
  if (const auto shared = root.Find("shared"))
    for (const sites::JsonNode& name : shared->Array(1)) {
      const std::string cls = name.String();
      if (std::find(c.shared.begin(), c.shared.end(), cls) != c.shared.end())
        name.Fail("class '" + cls + "' listed twice");
      c.shared.push_back(cls);
    }
  if (const auto offsets = root.Find("offsets"))
    for (const sites::JsonNode& node : offsets->Array(1)) {
      if (!node.is_object())
        node.Fail("expected an object {\"class\": ..., \"parameter\": ..., \"sigma\": ...}");
      node.Keys({"class", "parameter", "sigma"});
      OffsetPrior o;
      o.class_name = node.Get("class").String();
      const sites::JsonNode parameter = node.Get("parameter");
      o.parameter = parameter.String();
      const core::MaterialFieldInfo* field = core::FindMaterialField(o.parameter);
      if (!field) parameter.Fail("unknown parameter (allowed: " + core::MaterialFieldNames() + ")");
      o.sigma = node.Get("sigma").Positive();
      o.sigma = sites::FieldToSI(o.sigma, field->unit, c.units);
      for (const OffsetPrior& other : c.offsets)
        if (other.class_name == o.class_name && other.parameter == o.parameter)
          node.Fail("a second offset of class '" + o.class_name + "' " + o.parameter);
      c.offsets.push_back(o);
    }
  JointSpace{c};  // its errors now, before anything runs
  return c;
}

}  // namespace rockcal::calibrate
