// Joint calibration of several sites: the campaign file and its errors, the
// joint parameters and their map to each site, the offsets' priors, the
// joint objective, and the search being Calibrate's own (one site alone
// gives the site's calibration; a resumed campaign replays its log).
#include "rockcal/calibrate/campaign.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "../sites/test_files.h"
#include "rockcal/core/error.h"
#include "twin_fixture.h"

namespace rockcal::calibrate {
namespace {

using sites::testing::ErrorOf;
using sites::testing::TempDir;
using ::testing::HasSubstr;
using testing::kTruth;
using testing::TwinObservations;
using testing::TwinSite;

// Two copies of the twin site, "a" and "b": their materials "slope" and
// "runout" are classes of their own (the ids), so both are shared.
Campaign TwoTwins(int rocks, bool observed = false) {
  Campaign c;
  c.name = "two twins";
  for (const char* name : {"a", "b"}) {
    CampaignSite s;
    s.name = name;
    s.site = TwinSite(rocks);
    s.site.scene.name = name;
    if (observed) s.observations = TwinObservations(TwinSite(20), kTruth, 5);
    c.sites.push_back(std::move(s));
  }
  return c;
}

std::vector<std::string> Labels(const ParameterSpace& space) {
  std::vector<std::string> out;
  for (const Parameter& p : space.parameters()) out.push_back(p.label());
  return out;
}

std::string Example(const std::string& file) {
  return std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/twin_campaign/" + file;
}

// ---- the joint space -----------------------------------------------------------

TEST(JointSpace, SharedClassesGiveOneValueToEverySite) {
  Campaign c = TwoTwins(4);
  // Site b calibrates three of the four, the slope hardness within [0.3, 0.9].
  c.sites[1].site.calibrate = {{"slope", "hardness", 0.3, 0.9, ""},
                               {"slope", "roughness", 0.1, 0.6, ""},
                               {"runout", "hardness", 0.1, 0.6, ""}};
  const JointSpace joint(c);
  EXPECT_EQ(Labels(joint.space()),
            (std::vector<std::string>{"slope.hardness", "slope.roughness", "runout.hardness",
                                      "runout.roughness"}));
  // The shared bounds are the intersection, and the narrowing is noted.
  EXPECT_DOUBLE_EQ(joint.space().parameters()[0].lower, 0.3);
  EXPECT_DOUBLE_EQ(joint.space().parameters()[0].upper, 0.8);
  ASSERT_EQ(joint.notes().size(), 1u);
  EXPECT_THAT(joint.notes()[0], HasSubstr("slope hardness: bounds [0.3, 0.8]"));
  EXPECT_THAT(joint.notes()[0], HasSubstr("site 'b' material 'slope' [0.3, 0.9]"));

  const std::vector<double> x = {0.5, 0.2, 0.3, 0.4};
  EXPECT_EQ(joint.SiteValues(0, x), x);
  EXPECT_EQ(joint.SiteValues(1, x), (std::vector<double>{0.5, 0.2, 0.3}));
  // Starting values: the mean of the sites' own, clamped into the bounds.
  const std::vector<double> start = joint.FromSiteValues({{0.4, 0.2, 0.3, 0.4}, {0.6, 0.3, 0.1}});
  EXPECT_EQ(start, (std::vector<double>{0.5, 0.25, 0.2, 0.4}));
  EXPECT_DOUBLE_EQ(joint.FromSiteValues({{0.2, 0.2, 0.3, 0.4}, {0.3, 0.3, 0.1}})[0], 0.3);
  EXPECT_EQ(joint.prior_count(), 0);
  EXPECT_TRUE(joint.PriorResiduals(x).empty());
}

TEST(JointSpace, BoundsWithoutACommonIntervalAreBadInput) {
  Campaign c = TwoTwins(4);
  c.path = "campaign.json";
  c.sites[1].site.calibrate[0] = {"slope", "hardness", 0.85, 0.9, ""};
  const std::string error = ErrorOf([&] { JointSpace{c}; });
  EXPECT_THAT(error, HasSubstr("campaign.json: class 'slope' hardness"));
  EXPECT_THAT(error, HasSubstr("no common interval"));
  EXPECT_THAT(error, HasSubstr("site 'a' material 'slope' [0.2, 0.8]"));
  EXPECT_THAT(error, HasSubstr("site 'b' material 'slope' [0.85, 0.9]"));
  // Not shared, the class is calibrated per site, each within its bounds.
  c.shared = {"runout"};
  const JointSpace joint(c);
  EXPECT_EQ(
      Labels(joint.space()),
      (std::vector<std::string>{"a:slope.hardness", "a:slope.roughness", "runout.hardness",
                                "runout.roughness", "b:slope.hardness", "b:slope.roughness"}));
  EXPECT_DOUBLE_EQ(joint.space().parameters()[4].lower, 0.85);
  const std::vector<double> x = {0.3, 0.2, 0.4, 0.5, 0.88, 0.3};
  EXPECT_EQ(joint.SiteValues(0, x), (std::vector<double>{0.3, 0.2, 0.4, 0.5}));
  EXPECT_EQ(joint.SiteValues(1, x), (std::vector<double>{0.88, 0.3, 0.4, 0.5}));
}

// Issue 13, finding 1: a roughness is the sag between virtual spheres a sphere
// spacing apart, so two sites share one only at one spacing.
TEST(JointSpace, SharedRoughnessAtTwoSphereSpacingsIsBadInput) {
  Campaign c = TwoTwins(4);
  c.path = "campaign.json";
  c.sites[1].site.scene.grid.spacing *= 2;
  const std::string error = ErrorOf([&] { JointSpace{c}; });
  EXPECT_THAT(error, HasSubstr("campaign.json: class 'slope' roughness is shared by sites whose "
                               "virtual spheres are spaced differently"));
  EXPECT_THAT(error, HasSubstr("('a' 2 m, 'b' 4 m)"));
  EXPECT_THAT(error, HasSubstr("one surface.sphere_spacing"));
}

TEST(JointSpace, SharedClassesAndOffsetsMustNameWhatTheSitesCalibrate) {
  Campaign c = TwoTwins(4);
  c.path = "campaign.json";
  c.shared = {"bedrock"};
  EXPECT_THAT(ErrorOf([&] { JointSpace{c}; }),
              HasSubstr("campaign.json: $.shared: class 'bedrock': no site calibrates"));
  c.shared = {"slope"};
  c.offsets = {{"runout", "hardness", 0.05}};
  EXPECT_THAT(ErrorOf([&] { JointSpace{c}; }),
              HasSubstr("campaign.json: $.offsets[0].class: class 'runout' is not shared"));
  c.shared.clear();
  c.offsets = {{"slope", "friction", 0.05}};
  EXPECT_THAT(ErrorOf([&] { JointSpace{c}; }),
              HasSubstr("$.offsets[0]: class 'slope' friction: no site calibrates it"));
  c.offsets = {{"slope", "hardness", 0.0}};
  EXPECT_THAT(ErrorOf([&] { JointSpace{c}; }), HasSubstr("$.offsets[0].sigma: 0: expected"));
}

TEST(JointSpace, OffsetsAddToTheSharedValueSumToZeroAndEnterTheMisfitAsPriorResiduals) {
  Campaign c = TwoTwins(4);
  c.offsets = {{"slope", "hardness", 0.05}};
  const JointSpace joint(c);
  // One offset parameter: site b's offset is minus site a's.
  ASSERT_EQ(joint.space().size(), 5);
  EXPECT_EQ(Labels(joint.space())[4], "a:slope.hardness_offset");
  const Parameter& offset = joint.space().parameters()[4];
  EXPECT_TRUE(offset.offset);
  EXPECT_EQ(offset.site, "a");
  EXPECT_DOUBLE_EQ(offset.lower, -0.15);  // 3 sigma
  EXPECT_DOUBLE_EQ(offset.upper, 0.15);
  EXPECT_EQ(joint.prior_count(), 2);

  const std::vector<double> x = {0.5, 0.2, 0.3, 0.4, 0.1};
  EXPECT_DOUBLE_EQ(joint.SiteValues(0, x)[0], 0.6);
  EXPECT_DOUBLE_EQ(joint.SiteValues(1, x)[0], 0.4);
  EXPECT_DOUBLE_EQ(joint.SiteValues(1, x)[1], 0.2);  // roughness has no offset
  // A site's value stays within its own bounds ([0.2, 0.8]).
  EXPECT_DOUBLE_EQ(joint.SiteValues(0, {0.75, 0.2, 0.3, 0.4, 0.15})[0], 0.8);
  EXPECT_DOUBLE_EQ(joint.SiteValues(1, {0.75, 0.2, 0.3, 0.4, 0.15})[0], 0.6);
  const std::vector<observations::Residual> prior = joint.PriorResiduals(x);
  ASSERT_EQ(prior.size(), 2u);
  EXPECT_DOUBLE_EQ(prior[0].value, 2.0);
  EXPECT_DOUBLE_EQ(prior[1].value, -2.0);
  EXPECT_EQ(prior[0].id.observation(), "prior");
  EXPECT_EQ(prior[0].id.quantity(), "a:slope.hardness_offset");
  EXPECT_EQ(prior[1].id.quantity(), "b:slope.hardness_offset");
  EXPECT_EQ(prior[1].id.kind, observations::ObservationKind::kPrior);
  EXPECT_EQ(prior[1].id.site, "b");
  EXPECT_DOUBLE_EQ(prior[0].sigma, 0.05);
  // The start: offsets 0.
  const std::vector<double> start =
      joint.FromSiteValues({{0.4, 0.2, 0.3, 0.4}, {0.6, 0.2, 0.3, 0.4}});
  EXPECT_DOUBLE_EQ(start[0], 0.5);
  EXPECT_EQ(start[4], 0.0);
  // One site alone has no offset to take.
  c.sites.pop_back();
  EXPECT_EQ(JointSpace(c).space().size(), 4);
  EXPECT_EQ(JointSpace(c).prior_count(), 0);
}

// ---- the joint objective ---------------------------------------------------------

TEST(CampaignObjective, JoinsTheSitesWeightedResidualsAndThePriors) {
  Campaign c = TwoTwins(6, true);
  c.sites[1].weight = 4.0;
  c.offsets = {{"runout", "roughness", 0.1}};
  std::vector<core::Scene> scenes;
  for (const CampaignSite& s : c.sites) scenes.push_back(s.site.scene);
  const CampaignObjective objective(c, scenes, {});
  const int a = objective.site(0).residual_count(), b = objective.site(1).residual_count();
  EXPECT_EQ(objective.residual_count(), a + b + 2);
  const std::vector<double> x = {0.5, 0.3, 0.3, 0.4, 0.05};
  const observations::Misfit joint = objective.Evaluate(x);
  const observations::Misfit ma = objective.site(0).Evaluate(objective.joint().SiteValues(0, x));
  const observations::Misfit mb = objective.site(1).Evaluate(objective.joint().SiteValues(1, x));
  ASSERT_EQ(static_cast<int>(joint.residuals.size()), a + b + 2);
  EXPECT_NEAR(joint.value, ma.value + 4.0 * mb.value + 0.5 * (0.25 + 0.25), 1e-9 * joint.value);
  double sum = 0.0;
  for (const auto& r : joint.residuals) sum += r.value * r.value;
  EXPECT_NEAR(joint.value, 0.5 * sum, 1e-9 * joint.value);
  EXPECT_EQ(joint.residuals[0].id.observation(), "a: " + ma.residuals[0].id.observation());
  EXPECT_EQ(joint.residuals[0].id.site, "a");
  EXPECT_EQ(joint.residuals[static_cast<std::size_t>(a)].id.site, "b");
  EXPECT_EQ(joint.residuals[static_cast<std::size_t>(a)].value, 2.0 * mb.residuals[0].value);
  EXPECT_EQ(joint.residuals.back().id.observation(), "prior");
  EXPECT_DOUBLE_EQ(joint.residuals.back().value, -0.5);
  // Several points at once: the same misfits as one by one, and `done` once per point.
  const std::vector<double> y = {0.4, 0.2, 0.2, 0.3, 0.0};
  int done = 0;
  const std::vector<observations::Misfit> all =
      objective.EvaluateAll({x, y}, [&](int, const observations::Misfit&) { ++done; });
  EXPECT_EQ(done, 2);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].value, joint.value);
  EXPECT_EQ(all[1].value, objective.Evaluate(y).value);
}

// ---- the run --------------------------------------------------------------------

TEST(Campaign, OneSiteAloneIsThatSitesCalibration) {
  const sites::Site site = TwinSite(6);
  const observations::Observations obs = TwinObservations(TwinSite(20), kTruth, 5);
  Campaign c;
  c.name = "one";
  c.sites.push_back({"twin", site, obs, 0, 1.0});
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.methods = {Method::kBobyqa};
  options.method.max_evals = 6;
  options.seed = 3;
  const CampaignSummary joint = RunCampaign(c, options);
  const CalibrationSummary alone = Calibrate(site, obs, options);
  ASSERT_EQ(joint.calibration.methods.size(), 1u);
  const MethodResult& a = joint.calibration.best_method();
  const MethodResult& b = alone.best_method();
  ASSERT_EQ(a.trace.size(), b.trace.size());
  for (std::size_t k = 0; k < a.trace.size(); ++k) {
    EXPECT_EQ(a.trace[k].parameters, b.trace[k].parameters) << k;
    EXPECT_EQ(a.trace[k].misfit, b.trace[k].misfit) << k;
  }
  EXPECT_EQ(a.best, b.best);
  EXPECT_EQ(joint.calibration.misfit_before.value, alone.misfit_before.value);
  EXPECT_EQ(joint.calibration.misfit_after.value, alone.misfit_after.value);
  // The campaign also has the uncertainty, whatever the method, from central
  // differences at the joint values, and the site's fit.
  EXPECT_TRUE(a.uncertainty.computed);
  EXPECT_FALSE(a.uncertainty.from_search);
  ASSERT_EQ(joint.sites.size(), 1u);
  EXPECT_EQ(joint.sites[0].calibrated, a.best);
  EXPECT_EQ(joint.sites[0].misfit_joint.value, alone.misfit_after.value);
  EXPECT_EQ(joint.sites[0].misfit_start.value, alone.misfit_before.value);
}

TEST(Campaign, ResumeReplaysTheLogAndGivesTheSameResult) {
  const TempDir dir;
  Campaign c = TwoTwins(5, true);
  c.offsets = {{"slope", "hardness", 0.05}};
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.methods = {Method::kBobyqa};
  options.method.max_evals = 4;
  options.seed = 3;
  options.log_path = dir.path() + "/evaluations.jsonl";
  // An in-memory site has no file to fingerprint: give it one.
  for (CampaignSite& s : c.sites) s.site.path = dir.Write(s.name + ".json", s.name);
  const CampaignSummary first = RunCampaign(c, options);
  options.resume = true;
  const CampaignSummary again = RunCampaign(c, options);
  const MethodResult& a = first.calibration.best_method();
  const MethodResult& b = again.calibration.best_method();
  EXPECT_EQ(b.simulated, 0);
  EXPECT_EQ(b.evaluations, a.evaluations);
  EXPECT_EQ(b.best, a.best);
  EXPECT_EQ(b.best_misfit, a.best_misfit);
  EXPECT_EQ(again.calibration.misfit_after.value, first.calibration.misfit_after.value);
  // A change in what determines the evaluations: no resume, the part named.
  c.sites[1].weight = 2.0;
  EXPECT_THAT(ErrorOf([&] { RunCampaign(c, options); }), HasSubstr("b: weight"));
}

TEST(Campaign, OptionsItDoesNotTakeAreBadInput) {
  const Campaign c = TwoTwins(4);
  CalibrationOptions options = CalibrationOptions::SingleStage();
  options.refine_factor = 2;
  EXPECT_THAT(ErrorOf([&] { CheckCampaign(c, options); }),
              HasSubstr("a campaign takes no a refining stage"));
  options.refine_factor = 1;
  options.reach_points = 8;
  EXPECT_THAT(ErrorOf([&] { CheckCampaign(c, options); }), HasSubstr("reach check"));
  options.reach_points = 0;
  options.methods = {static_cast<Method>(99)};
  EXPECT_THAT(ErrorOf([&] { CheckCampaign(c, options); }), HasSubstr("unknown method 99"));
}

// ---- the campaign file ------------------------------------------------------------

TEST(CampaignFile, ReadsSitesAndObservationsRelativeToTheFile) {
  const Campaign c = LoadCampaign(Example("campaign.json"));
  EXPECT_EQ(c.name, "twin campaign");
  ASSERT_EQ(c.sites.size(), 2u);
  EXPECT_EQ(c.sites[0].name, "fan");
  EXPECT_EQ(c.sites[1].name, "gully");
  EXPECT_EQ(c.sites[0].weight, 1.0);
  EXPECT_EQ(c.sites[0].rocks, 0);
  EXPECT_FALSE(c.sites[0].observations.empty());
  // The campaign file, then each site's file and observations file.
  ASSERT_EQ(c.inputs.size(), 5u);
  EXPECT_EQ(c.inputs[0], Example("campaign.json"));
  const JointSpace joint(c);
  EXPECT_EQ(Labels(joint.space()),
            (std::vector<std::string>{"ground.hardness", "ground.roughness"}));
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Writes a campaign file beside copies of the example's site files.
std::string WriteCampaign(const TempDir& dir, const nlohmann::json& campaign) {
  for (const char* site : {"fan", "gully"})
    for (const char* file : {"site.json", "observations.json"})
      std::filesystem::copy_file(Example(std::string(site) + "/" + file),
                                 dir.path() + "/" + site + "_" + file,
                                 std::filesystem::copy_options::overwrite_existing);
  return dir.Write("campaign.json", campaign.dump());
}

nlohmann::json GoodCampaign() {
  return {{"units", "si"},
          {"sites",
           {{{"site", "fan_site.json"}, {"observations", "fan_observations.json"}},
            {{"site", "gully_site.json"}, {"observations", "gully_observations.json"}}}}};
}

TEST(CampaignFile, ErrorsNameTheFileThePathTheValueAndWhatWasExpected) {
  const TempDir dir;
  struct Case {
    std::function<void(nlohmann::json*)> change;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {[](nlohmann::json* j) { (*j)["site"] = 1; }, "$.site: unknown key 'site'"},
      {[](nlohmann::json* j) { j->erase("units"); }, "$"},
      {[](nlohmann::json* j) { (*j)["units"] = "metric"; }, "$.units: unknown units"},
      {[](nlohmann::json* j) { (*j)["sites"][1]["site"] = "nowhere.json"; },
       "$.sites[1].site: no such file: "},
      {[](nlohmann::json* j) { (*j)["sites"][0]["observations"] = "none.json"; },
       "$.sites[0].observations: no such file"},
      {[](nlohmann::json* j) { (*j)["sites"][0]["weight"] = -1; }, "$.sites[0].weight"},
      {[](nlohmann::json* j) { (*j)["sites"][0]["rocks"] = 0.5; }, "$.sites[0].rocks"},
      {[](nlohmann::json* j) {
         (*j)["sites"][0]["name"] = "x";
         (*j)["sites"][1]["name"] = "x";
       },
       "$.sites[1].name: two sites named 'x'"},
      {[](nlohmann::json* j) { (*j)["sites"] = nlohmann::json::array(); }, "$.sites"},
      {[](nlohmann::json* j) {
         (*j)["offsets"] = {{{"class", "ground"}, {"parameter", "hardnes"}, {"sigma", 0.1}}};
       },
       "$.offsets[0].parameter: unknown parameter"},
      {[](nlohmann::json* j) {
         (*j)["offsets"] = {{{"class", "ground"}, {"parameter", "hardness"}, {"sigma", -0.1}}};
       },
       "$.offsets[0].sigma"},
      {[](nlohmann::json* j) { (*j)["shared"] = {"rock"}; }, "$.shared: class 'rock'"},
  };
  for (const Case& c : cases) {
    nlohmann::json json = GoodCampaign();
    c.change(&json);
    const std::string path = WriteCampaign(dir, json);
    const std::string error = ErrorOf([&] { LoadCampaign(path); });
    EXPECT_THAT(error, HasSubstr(path)) << json.dump();
    EXPECT_THAT(error, HasSubstr(c.expected)) << json.dump();
  }
  // Bounds of the shared class that do not overlap.
  const std::string path = WriteCampaign(dir, GoodCampaign());
  nlohmann::json site = nlohmann::json::parse(ReadText(dir.path() + "/gully_site.json"));
  site["materials"][0]["hardness"] = 0.87;
  site["materials"][0]["calibrate"]["hardness"] = {0.85, 0.9};
  dir.Write("gully_site.json", site.dump());
  const std::string error = ErrorOf([&] { LoadCampaign(path); });
  EXPECT_THAT(error, HasSubstr(path + ": class 'ground' hardness"));
  EXPECT_THAT(error, HasSubstr("site 'gully' material 'scree' [0.85, 0.9]"));
}

}  // namespace
}  // namespace rockcal::calibrate
