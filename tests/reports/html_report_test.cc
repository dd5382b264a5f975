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
#include <vector>

#include "rockcal/reports/calibration_outputs.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/sites/site.h"
#include "xml_check.h"

namespace rockcal::reports {
namespace {

using testing::ParseXml;
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

struct Parsed {
  std::string html;
  std::unique_ptr<XmlNode> root;
  std::vector<std::string> sections;  // <section id> in order
};

Parsed Render(const ReportInput& in) {
  Parsed p;
  p.html = HtmlReport(in);
  std::string error;
  p.root = ParseXml(p.html, &error);
  EXPECT_NE(p.root, nullptr) << "not well-formed: " << error;
  if (p.root)
    p.root->Visit([&](const XmlNode& n) {
      if (n.name == "section") p.sections.push_back(n.Attribute("id"));
    });
  return p;
}

bool HasSection(const Parsed& p, const std::string& id) {
  for (const auto& s : p.sections)
    if (s == id) return true;
  return false;
}

const XmlNode* FindSection(const Parsed& p, const std::string& id) {
  const XmlNode* found = nullptr;
  p.root->Visit([&](const XmlNode& n) {
    if (n.name == "section" && n.Attribute("id") == id) found = &n;
  });
  return found;
}

// Self-contained and script-free: no <script>, no external resources, links
// only within the file, unique ids, and every link target present.
void ExpectSelfContained(const Parsed& p) {
  ASSERT_NE(p.root, nullptr);
  EXPECT_EQ(p.root->name, "html");
  std::set<std::string> ids, targets;
  p.root->Visit([&](const XmlNode& n) {
    EXPECT_NE(n.name, "script");
    EXPECT_NE(n.name, "img");
    EXPECT_NE(n.name, "link");
    EXPECT_NE(n.name, "iframe");
    EXPECT_FALSE(n.Has("src")) << "<" << n.name << " src=...>";
    for (const auto& [k, v] : n.attributes)
      EXPECT_NE(k.rfind("on", 0), 0u) << "event handler " << k;
    if (n.Has("href")) {
      const std::string href = n.Attribute("href");
      ASSERT_FALSE(href.empty());
      EXPECT_EQ(href[0], '#') << "external link " << href;
      targets.insert(href.substr(1));
    }
    if (n.Has("id")) {
      EXPECT_TRUE(ids.insert(n.Attribute("id")).second) << "duplicate id " << n.Attribute("id");
    }
  });
  for (const auto& t : targets) EXPECT_TRUE(ids.count(t)) << "link to missing #" << t;
  EXPECT_EQ(p.html.find("<script"), std::string::npos);
  EXPECT_EQ(p.html.find("url("), std::string::npos);
}

// The shown number of a cell: its text parsed as a double.
bool ShownNumber(const std::string& text, double* v) {
  char* end = nullptr;
  const std::string t = Unescape(text);
  *v = std::strtod(t.c_str(), &end);
  return end != t.c_str();
}

// Every element with data-json="FILE#POINTER": its data-value equals
// json[FILE] at POINTER (to 1e-9 relative), and its shown text rounds to it.
// Returns the pointers seen per file.
std::map<std::string, std::set<std::string>> CheckNumbers(
    const Parsed& p, const std::map<std::string, nlohmann::json>& files) {
  std::map<std::string, std::set<std::string>> seen;
  p.root->Visit([&](const XmlNode& n) {
    if (!n.Has("data-json")) return;
    const std::string ref = Unescape(n.Attribute("data-json"));
    const std::size_t hash = ref.find('#');
    ASSERT_NE(hash, std::string::npos) << ref;
    const std::string file = ref.substr(0, hash), pointer = ref.substr(hash + 1);
    const auto it = files.find(file);
    if (it == files.end()) return;
    seen[file].insert(pointer);
    const nlohmann::json::json_pointer ptr(pointer);
    ASSERT_TRUE(it->second.contains(ptr)) << ref << " not in " << file;
    const nlohmann::json& expected = it->second.at(ptr);
    const std::string value = Unescape(n.Attribute("data-value"));
    if (expected.is_string()) {
      EXPECT_EQ(value, expected.get<std::string>()) << ref;
      EXPECT_EQ(Unescape(n.AllText()), expected.get<std::string>()) << ref;
      return;
    }
    ASSERT_TRUE(expected.is_number()) << ref;
    const double want = expected.get<double>();
    const double got = std::strtod(value.c_str(), nullptr);
    EXPECT_NEAR(got, want, 1e-9 * std::fabs(want) + 1e-300) << ref;
    double shown = 0;
    ASSERT_TRUE(ShownNumber(n.AllText(), &shown)) << ref << " shows '" << n.AllText() << "'";
    EXPECT_NEAR(shown, want, 0.006 * std::fabs(want) + 1e-12)
        << ref << " shows '" << n.AllText() << "'";
  });
  return seen;
}

// The pointers of every number (and string) leaf of `j`.
std::set<std::string> Leaves(const nlohmann::json& j) {
  std::set<std::string> out;
  const nlohmann::json flat = j.flatten();
  for (const auto& item : flat.items()) out.insert(item.key());
  return out;
}

void CheckSimulationReport(const SimulatedSite& run, const Parsed& p) {
  ExpectSelfContained(p);
  const core::Scene& scene = run.site.scene;
  const nlohmann::json summary = SummaryJson(scene, run.result);
  const nlohmann::json diagnostics = DiagnosticsJson(scene, run.result);
  auto seen = CheckNumbers(p, {{"summary.json", summary}, {"diagnostics.json", diagnostics}});
  // Every number of summary.json is in the report (runout only when a rock stopped).
  for (const std::string& leaf : Leaves(summary)) {
    if (leaf.rfind("/runout", 0) == 0 && summary["outcomes"]["stopped"] == 0) continue;
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
  EXPECT_FALSE(HasSection(p, "shapes")) << "cubes only";
  EXPECT_EQ(p.html.find("Z partition"), std::string::npos);
  // 115 x 210 nodes: runs of cells keep the plan small.
  EXPECT_LT(p.html.size(), 1000000u) << "report of " << p.html.size() << " bytes";
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
        cell = Unescape(n.children[3]->AllText());  // energy above capacity
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

observations::Residual MakeResidual(const std::string& obs, const std::string& q, double sim,
                                    double seen) {
  observations::Residual r;
  r.observation = obs;
  r.quantity = q;
  r.simulated = sim;
  r.observed = seen;
  r.sigma = 0.5;
  r.value = (sim - seen) / r.sigma;
  return r;
}

observations::Misfit MakeMisfit(double offset) {
  observations::Misfit m;
  const char* levels[] = {"p10", "p50", "p90", "max"};
  for (int k = 0; k < 4; ++k) {
    m.residuals.push_back(
        MakeResidual("runout distance", levels[k], 40.0 + 5 * k + offset, 40.0 + 5 * k));
    m.residuals.push_back(
        MakeResidual("tree_scars[0] BP-1", levels[k], 1.0 + k * 0.5 + offset / 10, 1.0 + k * 0.5));
  }
  m.residuals.push_back(MakeResidual("passing[0] BP-2", "fraction", 0.3 + offset / 100, 0.35));
  for (const auto& r : m.residuals) m.value += 0.5 * r.value * r.value;
  return m;
}

calibrate::MethodResult MakeMethod(const std::string& name, const calibrate::ParameterSpace& space,
                                   double misfit) {
  calibrate::MethodResult m;
  m.method = name;
  m.termination = "evaluation budget used";
  for (const auto& p : space.parameters()) m.best.push_back(0.5 * (p.lower + p.upper));
  m.best_misfit = misfit;
  for (int k = 1; k <= 5; ++k) {
    calibrate::Evaluation e;
    e.method = name;
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

CalibrationRecord MakeRecord(const sites::Site& site, int methods) {
  CalibrationRecord record;
  record.site = site.scene.name;
  record.units = site.units;
  record.space = calibrate::ParameterSpace::FromSite(site);
  record.start = record.space.Current(site.scene);
  record.misfit_before = MakeMisfit(8.0);
  record.misfit_after = MakeMisfit(1.0);
  record.methods.push_back(MakeMethod("nlopt:bobyqa", record.space, 3.0));
  if (methods > 1) {
    calibrate::MethodResult ceres = MakeMethod("ceres", record.space, 2.0);
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

TEST(HtmlReportTest, CalibrationSectionsShowTheRecord) {
  const SimulatedSite run = Simulated("tutorial", 6);
  for (int methods : {1, 2}) {
    const CalibrationRecord record = MakeRecord(run.site, methods);
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

TEST(HtmlReportTest, NoFitSectionWithoutResiduals) {
  const SimulatedSite run = Simulated("tutorial", 4);
  CalibrationRecord record = MakeRecord(run.site, 1);
  record.misfit_after = observations::Misfit{};
  ReportInput in = Input(run);
  in.calibration = &record;
  const Parsed p = Render(in);
  EXPECT_TRUE(HasSection(p, "calibration"));
  EXPECT_FALSE(HasSection(p, "fit"));
}

}  // namespace
}  // namespace rockcal::reports
