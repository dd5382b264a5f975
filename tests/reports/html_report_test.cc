// report.html: well-formed XHTML with inline SVG, each section exactly when
// the run has what it shows, and the numbers of summary.json,
// diagnostics.json and calibration.json.
#include "rockcal/reports/html_report.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "report_check.h"
#include "rockcal/core/rasters.h"
#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/html_page.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/reports/svg.h"
#include "rockcal/sites/site.h"
#include "xml_check.h"

namespace rockcal::reports {
namespace {

using testing::CheckNumbers;
using testing::ExpectSelfContained;
using testing::FindSection;
using testing::HasSection;
using testing::Leaves;
using testing::Parsed;
using testing::ParseReport;
using testing::Unescape;
using testing::XmlNode;

struct SimulatedSite {
  sites::Site site;
  core::SimulationResult result;
};

// An example site with few rocks, recorded as the CLI records it for the report.
SimulatedSite Simulated(const std::string& name, int rocks = 8) {
  SimulatedSite run;
  run.site =
      sites::LoadSite(std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/" + name + "/site.json");
  core::Scene& scene = run.site.scene;
  scene.SetTotalRocks(rocks);
  scene.options.threads = 2;
  scene.options.record.passages = true;
  scene.options.record.trajectories = 4;
  run.result = core::Simulate(scene);
  return run;
}

ReportInput Input(const SimulatedSite& run) {
  ReportInput in;
  in.scene = &run.site.scene;
  in.result = &run.result;
  in.site_file = run.site.path;
  in.units = run.site.units;
  in.notes = run.site.notes;
  return in;
}

Parsed Render(const ReportInput& in) { return ParseReport(HtmlReport(in)); }

void CheckSimulationReport(const SimulatedSite& run, const Parsed& p) {
  ExpectSelfContained(p);
  const core::Scene& scene = run.site.scene;
  const nlohmann::json summary = SummaryJson(scene, run.result);
  const nlohmann::json diagnostics = DiagnosticsJson(scene, run.result);
  auto seen = CheckNumbers(p, {{"summary.json", summary}, {"diagnostics.json", diagnostics}});
  // Every number of summary.json is in the report but runout.x_m, the
  // stopped rocks' stop x kept for older readers: a coordinate, not a runout.
  for (const std::string& leaf : Leaves(summary)) {
    if (leaf.rfind("/runout/x_m", 0) == 0) continue;
    EXPECT_TRUE(seen["summary.json"].count(leaf))
        << "summary.json" << leaf << " is not in the report";
  }
  for (const std::string& leaf : Leaves(diagnostics))
    EXPECT_TRUE(seen["diagnostics.json"].count(leaf))
        << "diagnostics.json" << leaf << " is not in the report";
  // Sections: what ReportSections promises, in order.
  ReportInput in = Input(run);
  EXPECT_EQ(p.sections, ReportSections(in));
  for (const char* always : {"site", "profile", "diagnostics"})
    EXPECT_TRUE(HasSection(p, always)) << always;
  for (const char* never : {"calibration", "trace", "fit"})
    EXPECT_FALSE(HasSection(p, never)) << never;
  for (const core::Partition& part : scene.partitions) {
    const XmlNode* s = FindSection(p, PartitionSectionId(part.id));
    ASSERT_NE(s, nullptr) << part.id;
    const std::string kind = part.kind == core::Partition::Kind::kX ? "X partition" : "Z partition";
    EXPECT_NE(s->AllText().find(kind), std::string::npos) << part.id << " does not say " << kind;
  }
  EXPECT_EQ(HasSection(p, "barrier"), !scene.partitions.empty());
}

int CountZ(const core::Scene& scene) {
  int n = 0;
  for (const auto& part : scene.partitions) n += part.kind == core::Partition::Kind::kZ ? 1 : 0;
  return n;
}

TEST(HtmlReportTest, TutorialHasEverySimulationSection) {
  const SimulatedSite run = Simulated("tutorial");
  const Parsed p = Render(Input(run));
  CheckSimulationReport(run, p);
  EXPECT_TRUE(HasSection(p, "plan"));
  EXPECT_TRUE(HasSection(p, "partition-BP-1"));
  EXPECT_TRUE(HasSection(p, "partition-BP-2"));  // the Z partition
  EXPECT_EQ(CountZ(run.site.scene), 1);
  EXPECT_TRUE(HasSection(p, "shapes")) << "spheres and cubes";
  EXPECT_NE(p.html.find("ft-tons"), std::string::npos);
  EXPECT_NE(p.html.find("2.7116 kJ"), std::string::npos) << "the ft-ton conversion is stated";
  EXPECT_NE(p.html.find("for 0.1 s is taken to stay so"), std::string::npos)
      << "the stopping rule says a still rock ends without waiting out its second";
}

TEST(HtmlReportTest, ProfileHasNoPlanNoShapesNoZPartition) {
  const SimulatedSite run = Simulated("profile2d");
  const Parsed p = Render(Input(run));
  CheckSimulationReport(run, p);
  EXPECT_FALSE(HasSection(p, "plan")) << "a one-cell-wide profile has no plan view";
  EXPECT_FALSE(HasSection(p, "shapes")) << "spheres only";
  EXPECT_EQ(CountZ(run.site.scene), 0);
  EXPECT_EQ(p.html.find("Z partition"), std::string::npos);
  EXPECT_TRUE(HasSection(p, "partition-P-talus"));
}

TEST(HtmlReportTest, AuthumeIsSmallAndHasNoShapes) {
  const SimulatedSite run = Simulated("authume");
  const Parsed p = Render(Input(run));
  CheckSimulationReport(run, p);
  EXPECT_TRUE(HasSection(p, "plan"));
  EXPECT_FALSE(HasSection(p, "shapes")) << "boxes only";
  EXPECT_EQ(p.html.find("Z partition"), std::string::npos);
  // 115 x 210 nodes: runs of cells keep the plan small.
  EXPECT_LT(p.html.size(), 1000000u) << "report of " << p.html.size() << " bytes";
}

// A site with a forest whose strikes were recorded has a Forest section
// holding every figure of summary.json's "forest"; without the strikes, or
// without stems, it has none.
TEST(HtmlReportTest, AForestHasItsSectionWhenItsStrikesWereRecorded) {
  SimulatedSite run = Simulated("tutorial", 6);
  core::Scene& scene = run.site.scene;
  for (int k = 0; k < 40; ++k)  // a row of stems across the slope, 1.5 m apart
    scene.forest.Add(60.0, 1.0 + 1.5 * k, 0.3, 20.0,
                     k % 2 ? core::SpeciesClass::kBroadleaf : core::SpeciesClass::kConifer);
  scene.options.record.tree_strikes = true;
  run.result = core::Simulate(scene);
  long strikes = 0;
  for (const core::RockRecord& r : run.result.rocks) strikes += static_cast<long>(r.strikes.size());
  ASSERT_GT(strikes, 0) << "no rock reached the row of stems";
  Parsed p = Render(Input(run));
  CheckSimulationReport(run, p);
  const XmlNode* forest = FindSection(p, "forest");
  ASSERT_NE(forest, nullptr);
  EXPECT_NE(forest->AllText().find("40 stems stand on the slope"), std::string::npos)
      << forest->AllText();
  EXPECT_NE(forest->AllText().find("Stems struck most"), std::string::npos);

  scene.options.record.tree_strikes = false;
  run.result = core::Simulate(scene);
  EXPECT_FALSE(HasSection(Render(Input(run)), "forest"));
}

TEST(HtmlReportTest, SectionsFollowTheRun) {
  SimulatedSite run = Simulated("tutorial", 4);
  core::Scene& scene = run.site.scene;
  scene.options.max_time = 15.0;  // enough for what the sections depend on
  // No partitions: no partition sections and no barrier check.
  const std::vector<core::Partition> partitions = scene.partitions;
  scene.partitions.clear();
  run.result = core::Simulate(scene);
  Parsed p = Render(Input(run));
  ASSERT_NE(p.root, nullptr);
  EXPECT_FALSE(HasSection(p, "barrier"));
  for (const auto& s : p.sections) EXPECT_NE(s.rfind("partition-", 0), 0u) << s;
  // One shape: no shapes section.
  scene.partitions = partitions;
  for (auto& g : scene.groups) g.shape = core::Shape::kCube;
  run.result = core::Simulate(scene);
  p = Render(Input(run));
  EXPECT_FALSE(HasSection(p, "shapes"));
  EXPECT_TRUE(HasSection(p, "barrier"));
}

// Runout counts every rock: the tutorial's slope ends where many rocks are
// still rolling (issue 55: 74 of 200 left over its far edge);
// summary.json, the runout section, its curve and the opening line say how
// many, and a percentile among them is "beyond".
TEST(HtmlReportTest, RunoutCountsTheRocksThatLeftTheTerrain) {
  const SimulatedSite run = Simulated("tutorial", 40);
  const core::Scene& scene = run.site.scene;
  const core::HeightGrid& g = scene.grid;
  const int left = run.result.count(core::Outcome::kLeft);
  ASSERT_GT(left, 4) << "enough rocks leave for the 90th percentile to be among them";
  ASSERT_LT(left, 40) << "and some stay";
  const nlohmann::json summary = SummaryJson(scene, run.result);
  const nlohmann::json& ro = summary["runout"];
  EXPECT_EQ(ro["beyond_edge"], left);
  EXPECT_EQ(ro["rocks"], 40);
  EXPECT_EQ(ro["distance_m"]["p90"], "beyond") << ro.dump();
  EXPECT_EQ(ro["distance_m"]["max"], "beyond") << ro.dump();
  EXPECT_EQ(ro["travel_angle_deg"]["p10"], "beyond") << ro.dump();
  EXPECT_TRUE(ro["travel_angle_deg"]["max"].is_number()) << ro.dump();
  // A distance, not a coordinate: within the grid's diagonal.
  ASSERT_TRUE(ro["distance_m"]["p10"].is_number()) << ro.dump();
  EXPECT_LT(ro["distance_m"]["p10"].get<double>(),
            std::hypot(g.x(g.nx - 1) - g.x0, g.y(g.ny - 1) - g.y0));
  const Parsed p = Render(Input(run));
  CheckSimulationReport(run, p);
  const XmlNode* section = FindSection(p, "runout");
  ASSERT_NE(section, nullptr);
  const std::string text = Unescape(section->AllText());
  EXPECT_NE(text.find(std::to_string(left) + " ("), std::string::npos) << text;
  EXPECT_NE(text.find("left the terrain"), std::string::npos) << text;
  EXPECT_NE(text.find(std::to_string(left) + " left: beyond the edge"), std::string::npos)
      << "the exceedance curve holds up at the share that left";
  EXPECT_NE(text.find("hold the curve up at their share"), std::string::npos) << text;
  EXPECT_EQ(text.find("are not counted"), std::string::npos) << text;
  EXPECT_NE(p.html.find(std::to_string(left) + " rocks, "), std::string::npos)
      << "the opening line says how many left";
}

// An SI site in map coordinates (Lambert-93) reads in SI: no feet anywhere,
// coordinates as the site gives them, one rounding for each.
TEST(HtmlReportTest, AnSiSiteInMapCoordinatesReadsInItsOwnUnits) {
  const SimulatedSite run = Simulated("authume_gis", 6);
  ASSERT_EQ(run.site.units, sites::Units::kSI);
  const Parsed p = Render(Input(run));
  CheckSimulationReport(run, p);
  const std::string text = Unescape(p.root->AllText());
  for (const char* us : {" ft", "ft)", "[ft]", "ft-ton", "ft/s", "lbf", " lb)"})
    EXPECT_EQ(text.find(us), std::string::npos) << "'" << us << "' in an SI site's report";
  const core::HeightGrid& g = run.site.scene.grid;
  ASSERT_GT(g.y(g.ny - 1), 1e6) << "a northing";
  // The grid's extent and the partition: each coordinate one way.
  for (double v : {g.x0, g.x(g.nx - 1), g.y0, g.y(g.ny - 1)}) {
    const std::string shown = html::CoordinateNumber(v);
    EXPECT_NE(text.find(shown), std::string::npos) << shown;
    const std::string other = svg::Label(v);
    if (other != shown) {
      EXPECT_EQ(text.find(other + " "), std::string::npos) << other;
    }
  }
  EXPECT_NE(text.find("x = 888630.0 m"), std::string::npos);
  // The runout is a distance from each rock's release, metres down the slope.
  const nlohmann::json ro = SummaryJson(run.site.scene, run.result)["runout"];
  for (const char* key : {"p10", "p50"}) {
    ASSERT_TRUE(ro["distance_m"][key].is_number()) << ro.dump();
    EXPECT_LT(ro["distance_m"][key].get<double>(), 500.0) << ro.dump();
  }
}

// A US site keeps US units beside SI.
TEST(HtmlReportTest, AUsSiteShowsUsUnitsBesideSi) {
  const SimulatedSite run = Simulated("tutorial", 6);
  ASSERT_EQ(run.site.units, sites::Units::kUS);
  const std::string text = Unescape(Render(Input(run)).root->AllText());
  for (const char* us : {" ft)", "[ft]", "ft-tons", "lbf/ft"})
    EXPECT_NE(text.find(us), std::string::npos) << "no '" << us << "' in a US site's report";
}

// The barrier check counts the passing rocks above the thresholds.
TEST(HtmlReportTest, BarrierCountsFollowTheThresholds) {
  const SimulatedSite run = Simulated("profile2d", 10);
  const core::ResultStats stats = core::ComputeStats(run.site.scene, run.result);
  const int passed = stats.partitions[0].passed;
  ASSERT_GT(passed, 0);
  auto energy_cell = [&](double energy_j) {
    ReportInput in = Input(run);
    in.options.barrier_energy_j = energy_j;
    const Parsed p = Render(in);
    const XmlNode* s = FindSection(p, "barrier");
    std::string cell;
    s->Visit([&](const XmlNode& n) {
      if (n.name == "tr" && cell.empty() && n.children.size() > 3 && n.children[0]->name == "td")
        cell = Unescape(n.children[5]->AllText());  // energy above capacity
    });
    return cell;
  };
  EXPECT_EQ(energy_cell(1e-6).rfind(std::to_string(passed) + " (100.0 %)", 0), 0u)
      << energy_cell(1e-6);
  EXPECT_EQ(energy_cell(1e15).rfind("0 (0.0 %)", 0), 0u) << energy_cell(1e15);
}

TEST(HtmlReportTest, RejectsMissingInputAndBadOptions) {
  ReportInput in;
  EXPECT_THROW(HtmlReport(in), std::invalid_argument);
  const SimulatedSite run = Simulated("profile2d", 2);
  in = Input(run);
  in.options.barrier_height_m = 0.0;
  EXPECT_THROW(HtmlReport(in), std::invalid_argument);
  std::string error;
  EXPECT_FALSE(in.options.IsValid(&error));
  EXPECT_NE(error.find("barrier_height_m"), std::string::npos) << error;
  EXPECT_TRUE(ReportOptions{}.IsValid(&error));
}

TEST(HtmlReportTest, PartitionIdsBecomeSafeSectionIds) {
  EXPECT_EQ(PartitionSectionId("BP-1"), "partition-BP-1");
  EXPECT_EQ(PartitionSectionId("fence at 30 m & \"x\""), "partition-fence_at_30_m____x_");
}

// ---- calibration -------------------------------------------------------------

observations::Residual MakeResidual(const observations::ResidualId& id, double sim, double seen) {
  observations::Residual r;
  r.id = id;
  r.simulated = sim;
  r.observed = seen;
  r.sigma = 0.5;
  r.value = (sim - seen) / r.sigma;
  return r;
}

using observations::ObservationKind;
using observations::ResidualId;
using observations::Statistic;

observations::Misfit MakeMisfit(double offset) {
  observations::Misfit m;
  const ResidualId distance = ResidualId::Of(ObservationKind::kRunoutDistance);
  const ResidualId scars = ResidualId::Of(ObservationKind::kTreeScars, 0, "tree_scars[0] BP-1");
  const double levels[] = {0.1, 0.5, 0.9};
  for (int k = 0; k < 4; ++k) {
    const auto statistic = k < 3 ? Statistic::kQuantile : Statistic::kMax;
    const double level = k < 3 ? levels[k] : 0.0;
    m.residuals.push_back(
        MakeResidual(distance.With(statistic, level), 40.0 + 5 * k + offset, 40.0 + 5 * k));
    m.residuals.push_back(
        MakeResidual(scars.With(statistic, level), 1.0 + k * 0.5 + offset / 10, 1.0 + k * 0.5));
  }
  m.residuals.push_back(MakeResidual(
      ResidualId::Of(ObservationKind::kPassing, 0, "passing[0] BP-2").With(Statistic::kFraction),
      0.3 + offset / 100, 0.35));
  for (const auto& r : m.residuals) m.value += 0.5 * r.value * r.value;
  return m;
}

calibrate::MethodResult MakeMethod(calibrate::Method method, const calibrate::ParameterSpace& space,
                                   double misfit) {
  calibrate::MethodResult m;
  m.stage = calibrate::Stage{method};
  m.termination = {calibrate::TerminationType::kBudgetUsed, "evaluation budget used"};
  for (const auto& p : space.parameters()) m.best.push_back(0.5 * (p.lower + p.upper));
  m.best_misfit = misfit;
  for (int k = 1; k <= 5; ++k) {
    calibrate::Evaluation e;
    e.stage = m.stage;
    e.index = k;
    e.parameters = m.best;
    e.misfit = misfit * (6 - k);
    e.seconds = 0.1;
    e.elapsed = 0.1 * k;
    m.trace.push_back(e);
  }
  m.evaluations = m.simulated = 5;
  m.wall_seconds = 0.5;
  return m;
}

CalibrationSummary MakeRecord(const sites::Site& site, int methods) {
  CalibrationSummary record;
  record.site = site.scene.name;
  record.units = site.units;
  record.space = calibrate::ParameterSpace::FromSite(site);
  record.start = record.space.Current(site.scene);
  record.misfit_before = MakeMisfit(8.0);
  record.misfit_after = MakeMisfit(1.0);
  record.methods.push_back(MakeMethod(calibrate::Method::kBobyqa, record.space, 3.0));
  if (methods > 1) {
    calibrate::MethodResult ceres = MakeMethod(calibrate::Method::kCeres, record.space, 2.0);
    const std::size_t n = record.space.parameters().size();
    ceres.uncertainty.computed = true;
    ceres.uncertainty.std_error.assign(n, 0.01);
    ceres.uncertainty.correlation.assign(n, std::vector<double>(n, 0.1));
    for (std::size_t k = 0; k < n; ++k) ceres.uncertainty.correlation[k][k] = 1.0;
    record.methods.push_back(ceres);
    record.best = 1;
  }
  record.rocks = site.scene.total_rocks();
  record.seed = site.scene.options.seed;
  record.wall_seconds = 1.5;
  return record;
}

// Issue 12: a value the observations do not determine is said to be so, in
// parameters.md and in the report, not printed as if it were known.
TEST(HtmlReportTest, TheReportSaysWhichValuesTheObservationsDoNotDetermine) {
  auto has = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  const SimulatedSite run = Simulated("tutorial", 6);
  CalibrationSummary record = MakeRecord(run.site, 2);
  const auto& ps = record.space.parameters();
  ASSERT_GE(ps.size(), 2u);
  EXPECT_EQ(DeterminationSentence(record), "");  // standard errors 0.01: all determined
  calibrate::Uncertainty& u = record.methods[1].uncertainty;
  u.message = "linearised";
  u.std_error[0] = 0.4 * (ps[0].upper - ps[0].lower);
  u.correlation[0][1] = u.correlation[1][0] = -0.95;
  const std::string d = DeterminationSentence(record);
  EXPECT_TRUE(has(d,
                  "Not determined by the observations (standard error above a quarter "
                  "of the range): " +
                      ps[0].label()))
      << d;
  EXPECT_TRUE(has(d, "Determined only together (correlation of 0.9 or more in size): " +
                         ps[0].label() + " and " + ps[1].label() + " (-0.95)"))
      << d;
  EXPECT_TRUE(has(ParametersMarkdown(record), d));
  ReportInput in = Input(run);
  in.calibration = &record;
  EXPECT_TRUE(has(FindSection(Render(in), "calibration")->AllText(), "Determined only together"));
  u = calibrate::Uncertainty{};
  EXPECT_TRUE(has(DeterminationSentence(record),
                  "how well the observations determine each value is unknown"));
}

// A value at its bound is flagged in parameters.md (the console's table)
// as in the report; two stages of one method are named as stages, each
// with its rocks, and the misfits before and after at the same rocks.
TEST(HtmlReportTest, BoundsAndStagesAreSaidAlikeInParametersMdAndTheReport) {
  const SimulatedSite run = Simulated("tutorial", 6);
  CalibrationSummary record = MakeRecord(run.site, 1);
  calibrate::MethodResult refining = record.methods[0];
  refining.stage.rocks = 24;
  const auto& ps = record.space.parameters();
  refining.best[0] = ps[0].lower;
  record.methods.push_back(refining);
  record.best = 1;
  record.final_rocks = 24;
  ASSERT_NE(record.rocks, 24);
  const std::string md = ParametersMarkdown(record);
  EXPECT_NE(md.find("**at the lower bound**"), std::string::npos) << md;
  EXPECT_EQ(md.find("upper bound**"), std::string::npos) << md;
  EXPECT_NE(md.find("after, both at 24 rocks"), std::string::npos) << md;
  EXPECT_NE(md.find(std::to_string(record.rocks) +
                    " rocks per evaluation in the first stage, 24 in the refining stage"),
            std::string::npos)
      << md;
  ReportInput in = Input(run);
  in.calibration = &record;
  const std::string text = Unescape(FindSection(Render(in), "calibration")->AllText());
  EXPECT_NE(text.find("at a bound"), std::string::npos) << text;
  EXPECT_EQ(text.find("the best of 2 methods"), std::string::npos) << text;
  EXPECT_NE(text.find("the last of 2 stages"), std::string::npos) << text;
  EXPECT_NE(text.find(" in the refining stage"), std::string::npos) << text;
}

// Issue 54: a value the posterior does not determine, and a search value
// outside its own posterior interval, are flagged in the headline table
// (parameters.md, the console's) and the report says which to use.
TEST(HtmlReportTest, ASearchValueOutsideItsPosteriorSaysWhichToUse) {
  const SimulatedSite run = Simulated("tutorial", 6);
  CalibrationSummary record = MakeRecord(run.site, 1);
  const auto& ps = record.space.parameters();
  ASSERT_GE(ps.size(), 2u);
  calibrate::PosteriorResult post;
  post.space = record.space;
  // Parameter 0 in the lowest tenth of its range, parameter 1 over all of it.
  for (int i = 0; i < 200; ++i) {
    std::vector<double> x(ps.size());
    for (std::size_t k = 0; k < ps.size(); ++k) {
      const double u = (i + 0.5) / 200.0;
      x[k] = ps[k].lower + (k == 0 ? 0.1 * u : u) * (ps[k].upper - ps[k].lower);
    }
    post.samples.push_back(x);
  }
  calibrate::SummariseSamples(0.75, nullptr, &post);
  ASSERT_TRUE(post.parameters[1].undetermined);
  record.posterior = post;
  record.methods[0].best[0] = ps[0].lower + 0.5 * (ps[0].upper - ps[0].lower);
  record.methods[0].best[1] = ps[1].lower + 0.5 * (ps[1].upper - ps[1].lower);
  const std::string md = ParametersMarkdown(record);
  const std::string advice = PosteriorAdvice(record);
  EXPECT_NE(advice.find("outside its posterior 5-95 % interval for " + ps[0].label()),
            std::string::npos)
      << advice;
  EXPECT_EQ(advice.find(ps[1].label()), std::string::npos) << "inside its interval: " << advice;
  EXPECT_NE(advice.find("Use the posterior for a design"), std::string::npos) << advice;
  EXPECT_NE(md.find(advice), std::string::npos) << md;
  EXPECT_NE(md.find("**outside its posterior**"), std::string::npos) << md;
  EXPECT_NE(md.find("**not determined**"), std::string::npos) << md;
  ReportInput in = Input(run);
  in.calibration = &record;
  const std::string text = Unescape(FindSection(Render(in), "posterior")->AllText());
  EXPECT_NE(text.find("Use the posterior for a design"), std::string::npos) << text;
  // The scene family's measured coverage, with where the docs give it.
  EXPECT_NE(text.find("held the truth 89.0 % of the time"), std::string::npos) << text;
  EXPECT_NE(text.find("docs/posterior.md, \"How honest the intervals are\""), std::string::npos)
      << text;
  // Inside its interval: no advice.
  record.methods[0].best[0] = post.parameters[0].median;
  EXPECT_EQ(PosteriorAdvice(record), "");
}

TEST(HtmlReportTest, CalibrationSectionsShowTheRecord) {
  const SimulatedSite run = Simulated("tutorial", 6);
  for (int methods : {1, 2}) {
    const CalibrationSummary record = MakeRecord(run.site, methods);
    ReportInput in = Input(run);
    in.calibration = &record;
    const Parsed p = Render(in);
    ExpectSelfContained(p);
    for (const char* id : {"calibration", "trace", "fit"}) EXPECT_TRUE(HasSection(p, id)) << id;
    EXPECT_EQ(p.sections, ReportSections(in));
    const nlohmann::json cal = CalibrationJson(record);
    auto seen = CheckNumbers(
        p, {{"summary.json", SummaryJson(run.site.scene, run.result)}, {"calibration.json", cal}});
    for (const char* ptr :
         {"/misfit_before", "/misfit_after", "/termination", "/evaluations", "/wall_seconds"})
      EXPECT_TRUE(seen["calibration.json"].count(ptr)) << ptr;
    for (std::size_t k = 0; k < record.space.parameters().size(); ++k)
      EXPECT_TRUE(seen["calibration.json"].count("/calibrated/" + std::to_string(k))) << k;
    for (std::size_t k = 0; k < record.misfit_after.residuals.size(); ++k)
      EXPECT_TRUE(seen["calibration.json"].count("/fit/" + std::to_string(k) + "/simulated")) << k;
    const std::string text = FindSection(p, "calibration")->AllText();
    EXPECT_EQ(text.find("Methods compared") != std::string::npos, methods > 1) << methods;
    EXPECT_EQ(text.find("Correlation") != std::string::npos, methods > 1) << methods;
    // One quantile plot per observation set.
    int plots = 0;
    FindSection(p, "fit")->Visit(
        [&](const XmlNode& n) { plots += n.name == "svg" && n.Has("role") ? 1 : 0; });
    EXPECT_EQ(plots, 3);
  }
}

// The stopped share is a fraction like a passing fraction: no metres, and
// one value, not quantiles.
TEST(HtmlReportTest, TheStoppedShareIsShownAsAFraction) {
  const SimulatedSite run = Simulated("tutorial", 4);
  CalibrationSummary record = MakeRecord(run.site, 1);
  const ResidualId share = ResidualId::Of(ObservationKind::kRunoutStopped).With(Statistic::kShare);
  record.misfit_before.residuals.push_back(MakeResidual(share, 0.85, 1.0));
  record.misfit_after.residuals.push_back(MakeResidual(share, 0.95, 1.0));
  ReportInput in = Input(run);
  in.calibration = &record;
  const std::string text = FindSection(Render(in), "fit")->AllText();
  EXPECT_NE(text.find("0.950"), std::string::npos) << text;
  for (const char* wrong : {"0.95 m", "0.85 m", "runout stopped (quantiles"})
    EXPECT_EQ(text.find(wrong), std::string::npos) << wrong;
}

// The noise check's warning reaches the report's summary when the noise
// dominated, and only then.
TEST(HtmlReportTest, TheSummarySaysWhenNoiseDominated) {
  const SimulatedSite run = Simulated("tutorial", 4);
  CalibrationSummary record = MakeRecord(run.site, 1);
  record.noise_check.done = true;
  record.noise_check.message = "noise small: the misfit at the start varies by 1.5";
  ReportInput in = Input(run);
  in.calibration = &record;
  EXPECT_EQ(HtmlReport(in).find("the noise check before the search"), std::string::npos);
  record.noise_check.noise_dominates = true;
  record.noise_check.message = "noise dominates: the misfit at the start varies by 12.8";
  const std::string html = HtmlReport(in);
  EXPECT_NE(html.find("the noise check before the search: noise dominates: the misfit at the "
                      "start varies by 12.8"),
            std::string::npos);
}

// The calibrated values' misfit at the other seeds is listed in the
// summary as a list reads: "2", "2 and 3", "2, 3 and 4".
TEST(HtmlReportTest, TheSummaryListsTheMisfitAtOtherSeeds) {
  const SimulatedSite run = Simulated("tutorial", 4);
  CalibrationSummary record = MakeRecord(run.site, 1);
  ReportInput in = Input(run);
  in.calibration = &record;
  record.noise_seeds = {2};
  record.noise_misfits = {12.5};
  EXPECT_NE(HtmlReport(in).find("at seed 2 the same values score 12.5 ("), std::string::npos);
  record.noise_seeds = {2, 3};
  record.noise_misfits = {12.5, 9.25};
  EXPECT_NE(HtmlReport(in).find("at seeds 2 and 3 the same values score 12.5 and 9.25 ("),
            std::string::npos);
  record.noise_seeds = {2, 3, 4};
  record.noise_misfits = {12.5, 9.25, 10};
  EXPECT_NE(HtmlReport(in).find("at seeds 2, 3 and 4 the same values score 12.5, 9.25 and 10 ("),
            std::string::npos);
  // The warning of a dip follows CalibrationSummary::noise_dip.
  EXPECT_EQ(HtmlReport(in).find("the search found a dip of its own seed"), std::string::npos);
  record.noise_dip = true;
  EXPECT_NE(HtmlReport(in).find("the search found a dip of its own seed"), std::string::npos);
}

TEST(HtmlReportTest, NoFitSectionWithoutResiduals) {
  const SimulatedSite run = Simulated("tutorial", 4);
  CalibrationSummary record = MakeRecord(run.site, 1);
  record.misfit_after = observations::Misfit{};
  ReportInput in = Input(run);
  in.calibration = &record;
  const Parsed p = Render(in);
  EXPECT_TRUE(HasSection(p, "calibration"));
  EXPECT_FALSE(HasSection(p, "fit"));
}

// Tracked runs get a section of their own: each run's observed runout
// against its group's simulated median, the mean per-run error in sample
// and held out, every number from calibration.json and holdout.json.
TEST(HtmlReportTest, TrackedRunsShowTheirErrorsInSampleAndHeldOut) {
  const SimulatedSite run = Simulated("tutorial", 4);
  CalibrationSummary record = MakeRecord(run.site, 1);
  ReportInput in = Input(run);
  in.calibration = &record;
  EXPECT_FALSE(HasSection(Render(in), "runs")) << "no runs";
  for (const auto& [id, observed, simulated] :
       {std::tuple{"v1", 40.0, 52.5}, std::tuple{"v2", 80.0, 71.0}, std::tuple{"v3", 60.0, 60.5}}) {
    observations::RunFit r;
    r.id = id, r.observed = observed, r.simulated = simulated;
    r.rocks = 8, r.stopped = 7, r.stuck = id == std::string("v2") ? 1 : 0, r.spread = 11.0;
    r.sigma = 5.0;  // v1 (12.5 m off) lies beyond 2 sigma, v2 (9 m) and v3 within
    record.misfit_after.runs.push_back(r);
  }
  calibrate::HoldoutSummary holdout;
  holdout.folds = 2;
  holdout.results.resize(2);
  holdout.results[0].runout_error_m = 9.5;
  holdout.results[1].runout_error_m = 14.25;
  holdout.mean_runout_error_m = 11.875;
  in.holdout = &holdout;
  const Parsed p = Render(in);
  ExpectSelfContained(p);
  EXPECT_EQ(p.sections, ReportSections(in));
  ASSERT_TRUE(HasSection(p, "runs"));
  auto seen = CheckNumbers(p, {{"calibration.json", CalibrationJson(record)},
                               {"holdout.json", HoldoutJson(holdout, record)}});
  for (const char* ptr : {"/runs/mean_abs_error_m", "/runs/stuck_at_release",
                          "/runs/per_run/1/simulated_median_m", "/runs/per_run/2/observed_m"})
    EXPECT_TRUE(seen["calibration.json"].count(ptr)) << ptr;
  for (const char* ptr : {"/mean_runout_median_abs_error_m",
                          "/per_fold/1/runout_median_abs_error_m"})
    EXPECT_TRUE(seen["holdout.json"].count(ptr)) << ptr;
  const std::string text = FindSection(p, "runs")->AllText();
  EXPECT_NE(text.find("3 tracked runs"), std::string::npos) << text;
  EXPECT_NE(text.find("12.5 m"), std::string::npos) << "v1's |error|: " << text;
  EXPECT_NE(text.find("1 of 3 runs lie beyond 2 sigma"), std::string::npos) << text;
  EXPECT_EQ(text.find("repeated runs"), std::string::npos) << "no observations, no repeats";
  int plots = 0;  // observed against simulated, one point a run
  FindSection(p, "runs")->Visit(
      [&](const XmlNode& n) { plots += n.name == "svg" && n.Has("role") ? 1 : 0; });
  EXPECT_EQ(plots, 1);
}

// With the Tschamut example's observations the section gives the campaign's
// repeat scatter and the held-out error against it.
TEST(HtmlReportTest, TrackedRunsAreReadAgainstTheCampaignsRepeats) {
  const SimulatedSite run = Simulated("tschamut", 62);
  const observations::Observations obs = observations::LoadObservations(
      std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tschamut/observations.json",
      run.site.scene);
  CalibrationSummary record = MakeRecord(run.site, 1);
  observations::RunFit r;
  r.id = "v004", r.observed = 102.0, r.simulated = 95.0, r.rocks = 1, r.stopped = 1;
  record.misfit_after.runs.push_back(r);
  calibrate::HoldoutSummary holdout;
  holdout.folds = 1;
  holdout.results.resize(1);
  holdout.results[0].runout_error_m = 28.8;
  holdout.mean_runout_error_m = 28.8;
  ReportInput in = Input(run);
  in.calibration = &record;
  in.observations = &obs;
  in.holdout = &holdout;
  const std::string text = FindSection(Render(in), "runs")->AllText();
  EXPECT_NE(text.find("Repeated runs: 48 runs in 12 sets"), std::string::npos) << text;
  EXPECT_NE(text.find("The held-out error is 2 times the repeats' error"), std::string::npos)
      << "28.8 m against 14.4 m: " << text;
}

// The plan's passage density is drawn from the run's maps (the RasterSet that
// rasters.tif holds), one full cell centred on each grid node.
TEST(HtmlReportTest, PlanDrawsTheRastersCellsCentredOnNodes) {
  const SimulatedSite run = Simulated("tutorial", 4);
  core::RasterSet maps = core::ComputeRasters(run.site.scene, run.result);
  ASSERT_NE(maps.Find("reach_probability"), nullptr);
  core::RasterBand& reach =
      maps.bands[static_cast<std::size_t>(maps.Find("reach_probability") - maps.bands.data())];
  for (double& v : reach.values)
    if (!std::isnan(v)) v = 0.0;
  // Two neighbouring cells of the class 20-50 %, inside the grid.
  const core::HeightGrid& g = run.site.scene.grid;
  const int i = g.nx / 2, j = g.ny / 2;
  reach.values[static_cast<std::size_t>(g.index(i, j))] = 0.3;
  reach.values[static_cast<std::size_t>(g.index(i + 1, j))] = 0.4;
  ReportInput in = Input(run);
  in.rasters = &maps;
  const Parsed p = Render(in);
  const XmlNode* plan = FindSection(p, "plan");
  ASSERT_NE(plan, nullptr);
  // The density layer: one class, one run of two cells.
  std::vector<const XmlNode*> rects;
  std::set<std::string> fills;
  plan->Visit([&](const XmlNode& n) {
    if (n.name != "g" || n.Attribute("fill-opacity") != "0.85") return;
    for (const auto& cls : n.children) {
      fills.insert(cls->Attribute("fill"));
      for (const auto& r : cls->children) rects.push_back(r.get());
    }
  });
  EXPECT_EQ(fills, (std::set<std::string>{"#e31a1c"}));
  ASSERT_EQ(rects.size(), 1u);
  const double w = std::atof(rects[0]->Attribute("width").c_str());
  const double h = std::atof(rects[0]->Attribute("height").c_str());
  EXPECT_NEAR(w, 2.0 * h, 0.02 * h) << "two whole cells side by side";

  // Without maps and without recorded cells the plan says so.
  SimulatedSite bare = run;
  bare.result.cells_recorded = false;
  const Parsed q = Render(Input(bare));
  EXPECT_NE(FindSection(q, "plan")->AllText().find("was not recorded"), std::string::npos);
  // Maps of another grid are a programmer error.
  maps.nx += 1;
  EXPECT_THROW(HtmlReport(in), std::invalid_argument);
}

}  // namespace
}  // namespace rockcal::reports
