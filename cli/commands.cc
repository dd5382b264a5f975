#include "commands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>

#include "args.h"
#include "progress.h"
#include "rockcal/calibrate/class_draws.h"
#include "rockcal/calibrate/posterior_draws.h"
#include "rockcal/calibrate/recording.h"
#include "rockcal/calibrate/score.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/rasters.h"
#include "rockcal/core/simulate.h"
#include "rockcal/observations/observations.h"
#include "rockcal/parallel/parallel.h"
#include "rockcal/reports/forest_outputs.h"
#include "rockcal/reports/html_report.h"
#include "rockcal/reports/output_dir.h"
#include "rockcal/reports/raster_outputs.h"
#include "rockcal/reports/simulation_outputs.h"
#include "rockcal/sites/site.h"
#include "run_inputs.h"

namespace rockcal::cli {

std::string OutFolder(const Args& args, const std::string& input, const std::string& command) {
  if (args.Has("out")) return args.Get("out");
  if (args.Flag("resume"))
    throw InputError("argument --resume",
                     "continues the calibration in the folder --out names; expected --out DIR");
  std::string name = command;
  if (!input.empty()) {
    const std::filesystem::path path(input);
    std::string stem = path.stem().string();
    if (stem == "site" || stem == "campaign") {
      const std::string folder =
          std::filesystem::absolute(path).parent_path().filename().string();
      if (!folder.empty()) stem = folder;
    }
    if (!stem.empty()) name = stem + "-" + command;
  }
  std::string out = name;
  std::error_code ec;
  for (int k = 2; std::filesystem::exists(out, ec) || ec; ++k) out = name + "-" + std::to_string(k);
  parallel::OnRoot([&] { std::printf("output folder: %s (no --out given)\n", out.c_str()); });
  return out;
}

std::string RastersWritten(bool asked, const sites::Site& site) {
  if (!asked && !site.gis) return "";
  return std::string(", rasters.tif, rasters/*.asc") +
         (asked ? "" : " (rasters: on by default for a site read from GIS files)");
}

RankOutputDir::RankOutputDir(const std::string& path, bool force, reports::OutputOrigin origin) {
  parallel::OnRoot(
      [&] { dir_ = std::make_unique<reports::OutputDir>(path, force, std::move(origin)); });
  if (!dir_) {
    scratch_ = parallel::ScratchFolder() + "/out";
    std::filesystem::create_directories(scratch_);
  }
}

std::string RankOutputDir::File(const std::string& name) const {
  return dir_ ? dir_->File(name) : scratch_ + "/" + name;
}

const std::string& RankOutputDir::folder() const { return dir_ ? dir_->folder() : scratch_; }

void RankOutputDir::Commit() {
  if (dir_) dir_->Commit();
}

// ---- simulate --------------------------------------------------------------

namespace {

// What a simulate run reads from its arguments: the site, a calibration's
// values (its point values, or, when it has a posterior and --point-values
// is not given, parameter sets drawn from its samples) and what to record.
struct SimulateInputs {
  sites::Site loaded;
  std::optional<calibrate::CalibratedSite> parameters;
  bool drawn = false;  // parameter sets drawn from the posterior samples (or the class table)
  bool class_draws = false;  // drawn within the class table's intervals (parameters: theirs)
  std::vector<std::vector<double>> samples;
  int draws = 0;                    // --draws, when drawn
  calibrate::RecordingNeeds needs;  // summary.json, rocks.csv, diagnostics.json, trajectories.csv
};

// --class-values (draws, the default, or median) of a site whose materials
// take values from a class table: with draws and a value with an interval,
// parameter sets drawn within the intervals (calibrate/class_draws.h) take
// the place of a posterior's; with median the site's medians stand.
void ReadClassValues(const Args& args, SimulateInputs* in_out) {
  SimulateInputs& in = *in_out;
  const std::string use = args.Get("class-values", "draws");
  if (use != "draws" && use != "median")
    throw InputError("argument --class-values",
                     "'" + use + "' is not a choice; expected draws or median");
  if (args.Has("class-values") && in.loaded.class_materials.empty())
    throw InputError("argument --class-values",
                     "the site has no material that takes its values from a class table "
                     "(a material with a \"class\" and no hardness or roughness)");
  if (use != "draws") return;
  calibrate::CalibratedSite classes = calibrate::ClassParameters(in.loaded);
  if (classes.parameters.empty()) return;
  if (in.parameters)
    throw InputError("argument --parameters",
                     "the site's class values are drawn within the class table's intervals, and "
                     "a calibration's values would set them too; expected --class-values median "
                     "with --parameters");
  const std::uint64_t seed =
      args.Has("seed") ? static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed))
                       : in.loaded.scene.options.seed;
  in.draws =
      static_cast<int>(args.Integer("draws", calibrate::PosteriorDrawOptions{}.draws, 1, 10000));
  in.samples = calibrate::ClassDrawSamples(classes, in.draws, seed);
  in.parameters = std::move(classes);
  in.drawn = true;
  in.class_draws = true;
}

SimulateInputs ReadSimulateInputs(const Args& args, const std::string& site_path) {
  SimulateInputs in;
  in.loaded = sites::LoadSite(site_path);
  if (args.Has("parameters")) in.parameters = calibrate::ReadParametersFile(args.Get("parameters"));
  const auto& parameters = in.parameters;
  if (args.Flag("point-values") && !parameters)
    throw InputError("argument --point-values",
                     "goes with --parameters (a calibration's parameters.json or its folder)");
  in.drawn = parameters && parameters->has_posterior() && !args.Flag("point-values");
  ReadClassValues(args, &in);
  if (args.Has("draws") && !in.drawn)
    throw InputError(
        "argument --draws",
        parameters && parameters->has_posterior()
            ? "draws posterior parameter sets; --point-values takes the point values only"
            : "needs --parameters of a calibration with a posterior (rockcal calibrate "
              "--posterior), or a site whose materials take values from a class table");
  if (in.drawn && !in.class_draws) {
    in.samples = calibrate::ReadPosteriorSamples(*parameters);
    in.draws =
        static_cast<int>(args.Integer("draws", calibrate::PosteriorDrawOptions{}.draws, 1, 10000));
  }
  in.needs.partitions = true;
  in.needs.energy_check = true;
  in.needs.trajectories =
      static_cast<int>(args.Integer("trajectories", in.needs.trajectories, 0, 1000000));
  if (args.Has("sample-seconds") && !args.Has("trajectories"))
    throw InputError("argument --sample-seconds", "goes with --trajectories N");
  in.needs.sample_seconds = args.Number("sample-seconds", in.needs.sample_seconds, 1e-6, 1e6);
  return in;
}

// The scene at `values` (null: the site's own), as the options set it;
// `bare`: without its forest whatever the options (--compare-bare's run).
core::Scene SimulateScene(const Args& args, const SimulateInputs& in,
                          const calibrate::CalibratedSite* values, bool bare = false) {
  sites::Site site = in.loaded;
  if (values) calibrate::ApplyParameters(*values, &site.scene);
  for (const std::string& kv : args.All("set")) sites::ApplySetting(kv, &site);
  core::Scene scene = std::move(site.scene);
  if (args.Has("rocks"))
    scene.SetTotalRocks(static_cast<int>(args.Integer("rocks", 0, 1, core::kMaxRocks)));
  if (args.Has("seed"))
    scene.options.seed = static_cast<std::uint64_t>(args.Integer("seed", 1, 0, core::kMaxSeed));
  scene.options.threads =
      static_cast<int>(args.Integer("threads", scene.options.threads, 0, 1024));
  if (bare || args.Flag("no-forest")) scene.forest = core::Forest{};
  scene.options.record = calibrate::RecordingFor(scene, in.needs);
  return scene;
}

// The simulation of `scene` recorded as `recorded` (which adds what the
// report needs), or of the posterior draws (rock i with the (i mod D)-th
// draw, calibrate/posterior_draws.h) into *run; `bare`: each draw's scene
// without its forest.
core::SimulationResult RunSimulate(const Args& args, const SimulateInputs& in,
                                   const core::Scene& scene, const core::Scene& recorded,
                                   Progress* progress, std::optional<calibrate::PosteriorRun>* run,
                                   bool bare = false) {
  const auto update = [progress](int done, int total) { progress->Update(done, total); };
  if (!in.drawn) return parallel::Simulate(recorded, core::BuildTerrain(scene), update);
  calibrate::PosteriorDrawOptions draw_options;
  draw_options.draws = in.draws;
  draw_options.seed = scene.options.seed;
  *run = calibrate::SimulatePosteriorDraws(
      *in.parameters, in.samples, draw_options,
      [&](const calibrate::CalibratedSite& values) {
        core::Scene s = SimulateScene(args, in, &values, bare);
        s.options.record = recorded.options.record;
        std::string why;
        if (!s.IsValid(&why)) throw InputError(in.parameters->samples_file, why);
        return s;
      },
      "argument --draws", update);
  (*run)->class_draws = in.class_draws;
  core::SimulationResult result = std::move((*run)->pooled);
  (*run)->pooled = core::SimulationResult();
  return result;
}

// summary.json's "parameters": the posterior run's, or the point values'
// file (null without --parameters).
nlohmann::json ParametersUsed(const SimulateInputs& in,
                              const std::optional<calibrate::PosteriorRun>& run) {
  if (run) return calibrate::PosteriorRunJson(*run);
  if (!in.parameters) return nullptr;
  return {{"file", in.parameters->file},
          {"use", "point values"},
          {"posterior", in.parameters->has_posterior()}};
}

// tree_impacts.csv and, for stems drawn from stands, trees.csv (site units).
void WriteForestFiles(const RankOutputDir& dir, const sites::Site& site,
                      const core::SimulationResult& result) {
  const double to_site = 1.0 / sites::LengthToSI(1.0, site.units);
  reports::WriteFileAtomically(dir.File("tree_impacts.csv"),
                               reports::TreeImpactsCsv(result, to_site));
  if (site.drawn_stems_first < site.scene.forest.stems.size())
    reports::WriteFileAtomically(
        dir.File("trees.csv"),
        reports::TreesCsv(site.scene.forest, site.drawn_stems_first, to_site));
}

// The console's lines on a simulate run.
void PrintSimulate(const Args& args, const std::string& out, const SimulateInputs& in,
                   const core::Scene& scene, const core::SimulationResult& result,
                   const std::optional<calibrate::PosteriorRun>& run, const sites::Site& site) {
  std::printf("%s: %zu rocks in %.2f s (%ld steps, %ld flights): %d stopped, %d left, %d timeout\n",
              scene.name.c_str(), result.rocks.size(), result.wall_seconds, result.figures.steps,
              result.figures.flights, result.count(core::Outcome::kStopped),
              result.count(core::Outcome::kLeft), result.count(core::Outcome::kTimeout));
  if (run && run->class_draws)
    std::printf(
        "class values: %zu parameter sets drawn within the intervals of %s (rock i with set i "
        "mod %zu; --class-values median for the medians)\n",
        run->draws.size(), in.parameters->file.c_str(), run->draws.size());
  else if (run)
    std::printf(
        "parameters: %zu posterior draws from %d samples of %s (rock i with draw i mod "
        "%zu; --point-values for the point values)\n",
        run->draws.size(), run->samples, in.parameters->samples_file.c_str(), run->draws.size());
  else if (in.parameters)
    std::printf("parameters: the point values of %s%s\n", in.parameters->file.c_str(),
                in.parameters->has_posterior() ? " (--point-values: its posterior not drawn)" : "");
  if (!in.class_draws && !site.class_materials.empty())
    std::printf("class values: the medians of %s (--class-values median, or no interval)\n",
                site.class_materials.front().table.c_str());
  if (!site.class_materials.empty())
    std::printf("class values are other sites' calibrations: a calibration of this site against "
                "field data would narrow them\n");
  std::printf("wrote %s/summary.json, rocks.csv, diagnostics.json, report.html%s%s%s%s\n",
              out.c_str(),
              scene.options.record.trajectories > 0 ? ", trajectories.csv" : "",
              scene.forest.empty()                                 ? ""
              : site.drawn_stems_first < scene.forest.stems.size() ? ", tree_impacts.csv, trees.csv"
                                                                   : ", tree_impacts.csv",
              run ? ", draws.csv" : "", RastersWritten(args.Flag("rasters"), site).c_str());
}

}  // namespace

int Simulate(const std::vector<std::string>& argv) {
  const Args args(argv, FlagsOf("simulate"));
  const std::string site_path = args.OnlyPositional("SITE.json");
  const SimulateInputs in = ReadSimulateInputs(args, site_path);
  sites::Site site = in.loaded;
  site.scene = SimulateScene(args, in, in.parameters ? &*in.parameters : nullptr);
  const core::Scene& scene = site.scene;
  std::string error;
  if (!scene.IsValid(&error)) throw InputError(site_path, error);
  if (args.Flag("compare-bare") && scene.forest.empty())
    throw InputError("argument --compare-bare",
                     args.Flag("no-forest")
                         ? "compares the forest with the bare slope, and --no-forest leaves the "
                           "forest out: expected one of them"
                         : "the site has no 'forest' to compare the bare slope with (expected a "
                           "site with a forest)");

  const std::string out = OutFolder(args, site_path, "simulate");
  RunInputs inputs;
  inputs.Add(site).Add(args.Get("parameters", ""));
  if (in.drawn && !in.class_draws) inputs.Add(in.parameters->samples_file);
  RankOutputDir dir(out, args.Flag("force"), inputs.Origin("simulate"));
  PrintNotes(site.resampled, args.Flag("quiet"));
  Progress progress("simulate", args.Flag("quiet"));
  // The report's views need the passages per cell and a few trajectories;
  // they are recorded on a copy so that trajectories.csv is still written
  // only when --trajectories asks for it.
  core::Scene recorded = scene;
  calibrate::RecordingNeeds report_needs = in.needs;
  report_needs.report = true;
  recorded.options.record = calibrate::RecordingFor(scene, report_needs);
  std::optional<calibrate::PosteriorRun> run;
  const core::SimulationResult result = RunSimulate(args, in, scene, recorded, &progress, &run);
  // --compare-bare: the same rocks (seed, count, parameters or draws) on the
  // slope without its forest, for the report's runout with and without it.
  std::optional<core::SimulationResult> bare;
  if (args.Flag("compare-bare")) {
    core::Scene bare_scene = scene;
    bare_scene.forest = core::Forest{};
    bare_scene.options.record = calibrate::RecordingFor(bare_scene, calibrate::RecordingNeeds{});
    Progress bare_progress("simulate, bare", args.Flag("quiet"));
    std::optional<calibrate::PosteriorRun> bare_run;
    bare = RunSimulate(args, in, bare_scene, bare_scene, &bare_progress, &bare_run, true);
  }
  // One set of maps for rasters.tif and the report's plan view.
  core::RasterSet rasters = core::ComputeRasters(recorded, result);
  if (run)
    for (const core::RasterBand& b : run->raster_bands) rasters.bands.push_back(b);
  reports::WriteSimulationFiles(
      dir.folder(), scene, result, ParametersUsed(in, run),
      site.class_materials.empty() ? nlohmann::json(nullptr)
                                   : reports::ClassValuesJson(site.class_materials, in.class_draws));
  reports::WriteBarriersFile(dir.folder(), scene, result, site.units);
  if (run) reports::WriteFileAtomically(dir.File("draws.csv"), calibrate::DrawsCsv(*run));
  if (!scene.forest.empty()) WriteForestFiles(dir, site, result);
  if (args.Flag("rasters") || site.gis)
    reports::WriteRasterFiles(dir.folder(), rasters, reports::SiteRasterFrame(site));
  reports::ReportInput report = reports::SiteReport(site, scene, result, &rasters);
  report.posterior_run = run ? &*run : nullptr;
  if (report.classes) report.classes->drawn = in.class_draws;
  report.bare = bare ? &*bare : nullptr;
  reports::WriteFileAtomically(dir.File("report.html"), reports::HtmlReport(report));
  dir.Commit();
  if (!args.Flag("quiet")) {
    PrintSimulate(args, out, in, scene, result, run, site);
    if (bare) {
      const core::RunoutStats with = core::ComputeRunout(result.rocks);
      const core::RunoutStats without = core::ComputeRunout(bare->rocks);
      const auto length = [](double m) {
        char text[32];
        std::snprintf(text, sizeof text, "%.4g m", m);
        return std::isfinite(m) ? std::string(text) : std::string("beyond the edge");
      };
      std::printf(
          "without the forest (--compare-bare, report.html's Forest section): %d stopped, %d "
          "left; runout 90 %% %s (with the forest %s)\n",
          bare->count(core::Outcome::kStopped), bare->count(core::Outcome::kLeft),
          length(without.distance_m.p90).c_str(), length(with.distance_m.p90).c_str());
    }
  }
  if (result.figures.non_finite > 0) {
    std::fprintf(stderr, "rockcal: failed: %d rocks reached a non-finite state\n",
                 result.figures.non_finite);
    return 1;
  }
  return 0;
}

// ---- validate --------------------------------------------------------------

int Validate(const std::vector<std::string>& argv) {
  const Args args(argv, FlagsOf("validate"));
  const std::string site_path = args.OnlyPositional("SITE.json");
  if (args.Has("write-impacts") && !args.Has("observations"))
    throw InputError("argument --write-impacts",
                     "expected --observations with a 'tracks_file' too");
  const sites::Site site = sites::LoadSite(site_path);
  const core::Scene& scene = site.scene;
  // Lengths and masses in the site's units (docs/reference/commands.md).
  const auto length = [&](double m) { return sites::LengthText(m, site.units, "%.4g"); };
  const auto mass = [&](double kg) { return sites::MassText(kg, site.units, "%.4g"); };
  std::printf("site '%s' (%s): OK\n", scene.name.c_str(), site_path.c_str());
  for (const std::string& note : site.notes) std::printf("  %s\n", note.c_str());
  const core::Terrain terrain = core::BuildTerrain(scene);
  std::printf("materials:\n");
  std::vector<int> nodes(scene.materials.size(), 0);
  for (std::size_t n = 0; n < scene.grid.z.size(); ++n)
    if (!std::isnan(scene.grid.z[n])) ++nodes[static_cast<std::size_t>(scene.grid.material[n])];
  for (std::size_t k = 0; k < scene.materials.size(); ++k) {
    const core::Material& m = scene.materials[k];
    const core::ContactLaw law = core::DeriveContactLaw(m, scene.hardness_model);
    std::printf(
        "  %-12s %7d nodes  hardness %.3f  roughness %s (sphere r %s)  e %.3f  f %.3f  "
        "t_c %.4g s  zeta %.3f (eq. 13: %.3f)\n",
        m.id.c_str(), nodes[k], m.hardness, length(m.roughness_m).c_str(),
        length(core::VirtualSphereRadius(m.roughness_m, scene.grid.spacing)).c_str(),
        law.restitution, law.friction, law.contact_time, law.damping_ratio,
        law.eq13_damping_ratio);
  }
  std::printf("partitions:\n");
  for (const auto& p : scene.partitions) {
    if (p.kind == core::Partition::Kind::kLine) {  // a barrier
      std::printf("  %-10s line of %zu vertices, %s high, %.4g kJ%s\n", p.id.c_str(),
                  p.line.size(), length(p.height).c_str(), p.capacity * 1e-3,
                  p.stops ? ", stops rocks" : "");
      continue;
    }
    std::printf("  %-10s %s = %s\n", p.id.c_str(), p.kind == core::Partition::Kind::kX ? "x" : "z",
                length(p.value).c_str());
  }
  std::printf("rock groups:\n");
  for (const auto& g : scene.groups) {
    const core::GroupExtent extent = core::GroupBodies(g, scene.gravity);
    const core::RockBody& lo = extent.lightest;
    const core::RockBody& hi = extent.heaviest;
    bool shrunk = false;
    const double dt = core::GroupContactStep(scene, g, &shrunk);
    std::printf("  %5d %-11s size %s to %s  mass %s to %s  contact step %.3g s%s\n", g.count,
                core::ShapeToString(g.shape), length(std::min(lo.size, hi.size)).c_str(),
                length(std::max(lo.size, hi.size)).c_str(), mass(lo.mass).c_str(),
                mass(hi.mass).c_str(), dt, shrunk ? " (shrunk for stability)" : "");
  }
  PrintWarnings(sites::IdenticalCopyWarnings(scene));
  if (args.Has("observations")) {
    const observations::Observations obs =
        observations::LoadObservations(args.Get("observations"), scene);
    std::printf("observations '%s': OK\n", args.Get("observations").c_str());
    for (const std::string& note : obs.notes) std::printf("  %s\n", note.c_str());
    if (const auto scatter = observations::RunRepeatScatter(obs, scene))
      std::printf("  %s\n", scatter->Sentence().c_str());
    PrintWarnings(observations::DuplicateRunWarnings(obs));
    if (args.Has("write-impacts")) {
      // The tracks' detected impacts as an impacts file
      // (docs/field-campaigns.md, section 6).
      if (!obs.tracks)
        throw InputError("argument --write-impacts",
                         "the observations have no 'tracks_file' to read "
                         "impacts from (expected one)");
      const std::string path = args.Get("write-impacts");
      const std::string csv = observations::DetectedImpactsCsv(obs, scene);
      reports::WriteFileAtomically(path, csv);
      const long rows = static_cast<long>(std::count(csv.begin(), csv.end(), '\n')) - 1;
      std::printf("wrote %s: %ld impacts detected in the tracks\n", path.c_str(), rows);
    }
  }
  return 0;
}

}  // namespace rockcal::cli
