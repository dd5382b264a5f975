#include "rockcal/calibrate/posterior_draws.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "rockcal/core/statistics.h"
#include "rockcal/core/error.h"
#include "rockcal/core/random.h"
#include "table_text.h"

namespace rockcal::calibrate {
namespace {

// The random stream of the draws' choice ("DRAW").
constexpr std::uint64_t kDrawStream = 0x4452415700000000ull;

// The quantity names of a partition's bands and how to read them from the stats.
struct PartitionQuantity {
  const char* name;
  const char* unit;
  double scale;
  const core::Stats core::PartitionStats::*stats;
  double core::Stats::*value;
};

const PartitionQuantity kPartitionQuantities[] = {
    {"height_m.p50", "m", 1.0, &core::PartitionStats::height, &core::Stats::p50},
    {"height_m.p95", "m", 1.0, &core::PartitionStats::height, &core::Stats::p95},
    {"height_m.max", "m", 1.0, &core::PartitionStats::height, &core::Stats::max},
    {"velocity_mps.p95", "m/s", 1.0, &core::PartitionStats::velocity, &core::Stats::p95},
    {"energy_kj.p50", "kJ", 1e-3, &core::PartitionStats::energy, &core::Stats::p50},
    {"energy_kj.p95", "kJ", 1e-3, &core::PartitionStats::energy, &core::Stats::p95},
    {"energy_kj.max", "kJ", 1e-3, &core::PartitionStats::energy, &core::Stats::max},
};

}  // namespace

std::vector<DrawValue> DrawStatistics(const core::Scene& scene, const core::ResultStats& stats,
                                      int rocks) {
  std::vector<DrawValue> out;
  const std::pair<const char*, double core::Stats::*> runout[] = {{"x_m.p50", &core::Stats::p50},
                                                                  {"x_m.p90", &core::Stats::p90},
                                                                  {"x_m.p95", &core::Stats::p95},
                                                                  {"x_m.max", &core::Stats::max}};
  for (const auto& [name, value] : runout)
    out.push_back({"runout", name, "m", stats.runout_x.*value});
  for (std::size_t p = 0; p < scene.partitions.size() && p < stats.partitions.size(); ++p) {
    const std::string& id = scene.partitions[p].id;
    out.push_back({id, "passed_fraction", "1",
                   rocks > 0 ? static_cast<double>(stats.partitions[p].passed) / rocks : 0.0});
    for (const PartitionQuantity& q : kPartitionQuantities)
      out.push_back({id, q.name, q.unit, (stats.partitions[p].*q.stats).*q.value * q.scale});
  }
  return out;
}

std::vector<DrawBand> BandsOverDraws(const std::vector<std::vector<DrawValue>>& draws) {
  std::vector<DrawBand> bands;
  std::map<std::pair<std::string, std::string>, std::vector<double>> values;
  for (const std::vector<DrawValue>& draw : draws)
    for (const DrawValue& v : draw) {
      std::vector<double>& of = values[{v.where, v.quantity}];
      if (of.empty()) bands.push_back({v.where, v.quantity, v.unit, 0.0, 0.0, 0.0});
      of.push_back(v.value);
    }
  for (DrawBand& b : bands) {
    std::vector<double>& v = values[{b.where, b.quantity}];
    b.p05 = core::QuantileOf(&v, 0.05);
    b.median = core::QuantileOf(&v, 0.5);
    b.p95 = core::QuantileOf(&v, 0.95);
  }
  return bands;
}

bool PosteriorDrawOptions::IsValid(std::string* error) const {
  if (draws < 1 || draws > 10000) {
    *error = "draws = " + std::to_string(draws) + ": must be in [1, 10000]";
    return false;
  }
  return true;
}

std::vector<int> DrawSampleIndices(int samples, int draws, std::uint64_t seed) {
  std::vector<int> index(static_cast<std::size_t>(std::max(samples, 0)));
  for (std::size_t k = 0; k < index.size(); ++k) index[k] = static_cast<int>(k);
  core::RandomStream rng(seed, kDrawStream);
  const int n = std::min(draws, samples);
  for (int k = 0; k < n; ++k) {
    const int span = samples - k;
    const int pick = k + std::min(span - 1, static_cast<int>(rng.Uniform() * span));
    std::swap(index[static_cast<std::size_t>(k)], index[static_cast<std::size_t>(pick)]);
  }
  index.resize(static_cast<std::size_t>(n));
  return index;
}

namespace {

// What each draw's simulation left behind: its rocks and, with passages
// recorded, its maps; the scene of the first draw (the partitions').
struct DrawResults {
  std::vector<core::SimulationResult> results;
  std::vector<core::RasterSet> maps;
  core::Scene first_scene;
};

// Simulates rock i of scene_for's scenes with the (i mod D)-th of the
// picked samples, filling run->draws; throws when a draw would get no rock.
DrawResults SimulateDraws(const std::vector<std::vector<double>>& samples,
                          const std::vector<int>& picked, const SceneForValues& scene_for,
                          const std::string& what_draws, const core::ProgressFn& progress,
                          PosteriorRun* run) {
  const int d = static_cast<int>(picked.size());
  DrawResults out;
  int total = 0, done_before = 0;
  for (int k = 0; k < d; ++k) {
    PosteriorDraw draw;
    draw.sample = picked[static_cast<std::size_t>(k)];
    draw.values = samples[static_cast<std::size_t>(draw.sample)];
    CalibratedSite values = run->parameters;
    for (std::size_t j = 0; j < values.parameters.size(); ++j)
      values.parameters[j].value = draw.values[j];
    const core::Scene scene = scene_for(values);
    if (k == 0) {
      out.first_scene = scene;
      total = scene.total_rocks();
      if (total < d)
        throw InputError(what_draws, std::to_string(d) + " draws for " + std::to_string(total) +
                                         " rocks; expected at most one draw per rock (give more "
                                         "rocks or fewer draws)");
    }
    const core::Terrain terrain = core::BuildTerrain(scene);
    core::SimulationResult result = core::SimulateEveryNthRock(
        scene, terrain, k, d, [&](int done, int) {
          if (progress) progress(done_before + done, total);
        });
    done_before += static_cast<int>(result.rocks.size());
    draw.rocks = static_cast<int>(result.rocks.size());
    draw.stats = core::ComputeStats(scene, result);
    if (result.cells_recorded) out.maps.push_back(core::ComputeRasters(scene, result));
    run->draws.push_back(std::move(draw));
    out.results.push_back(std::move(result));
  }
  return out;
}

// The bands of the statistics (PosteriorRun::bands) over run->draws.
void StatisticBands(const core::Scene& scene, PosteriorRun* run) {
  std::vector<std::vector<DrawValue>> values;
  for (const PosteriorDraw& draw : run->draws)
    values.push_back(DrawStatistics(scene, draw.stats, draw.rocks));
  run->bands = BandsOverDraws(values);
}

// The maps' bands (PosteriorRun::raster_bands) over the draws' maps.
std::vector<core::RasterBand> MapBands(const std::vector<core::RasterSet>& maps) {
  std::vector<core::RasterBand> out;
  if (maps.empty()) return out;
  const std::size_t cells = maps.front().bands.front().values.size();
  for (const char* name : {"reach_probability", "energy_p95", "height_p95"}) {
    const core::RasterBand* any = maps.front().Find(name);
    core::RasterBand lo{std::string(name) + "_q05", any->unit,
                        std::string("5 % quantile over the posterior draws of each draw's ") + name,
                        std::vector<double>(cells, std::numeric_limits<double>::quiet_NaN())};
    core::RasterBand hi = lo;
    hi.name = std::string(name) + "_q95";
    hi.description = std::string("95 % quantile over the posterior draws of each draw's ") + name;
    const core::RasterBand* reach0 = maps.front().Find("reach_probability");
    for (std::size_t c = 0; c < cells; ++c) {
      if (std::isnan(reach0->values[c])) continue;  // a hole of the terrain
      std::vector<double> v;
      bool reached = false;
      for (const core::RasterSet& m : maps) {
        const double x = m.Find(name)->values[c];
        reached = reached || m.Find("passages")->values[c] > 0.0;
        v.push_back(std::isnan(x) ? 0.0 : x);
      }
      if (!reached && std::string(name) != "reach_probability") continue;
      lo.values[c] = core::QuantileOf(&v, 0.05);
      hi.values[c] = core::QuantileOf(&v, 0.95);
    }
    out.push_back(std::move(lo));
    out.push_back(std::move(hi));
  }
  return out;
}

}  // namespace

PosteriorRun SimulatePosteriorDraws(const CalibratedSite& parameters,
                                    const std::vector<std::vector<double>>& samples,
                                    const PosteriorDrawOptions& options,
                                    const SceneForValues& scene_for, const std::string& what_draws,
                                    const core::ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw InputError(what_draws, error);
  const int d = options.draws;
  if (static_cast<int>(samples.size()) < d)
    throw InputError(what_draws, std::to_string(d) + " draws from " +
                                     std::to_string(samples.size()) + " posterior samples (" +
                                     parameters.samples_file + "); expected at most the samples");
  PosteriorRun run;
  run.parameters = parameters;
  run.samples = static_cast<int>(samples.size());
  const std::vector<int> picked = DrawSampleIndices(run.samples, d, options.seed);
  DrawResults drawn = SimulateDraws(samples, picked, scene_for, what_draws, progress, &run);
  // The pooled run, in rock order.
  run.pooled = core::JoinRockBlocks(std::move(drawn.results));
  std::sort(run.pooled.rocks.begin(), run.pooled.rocks.end(),
            [](const core::RockRecord& a, const core::RockRecord& b) { return a.rock < b.rock; });
  run.pooled.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  StatisticBands(drawn.first_scene, &run);
  run.raster_bands = MapBands(drawn.maps);
  return run;
}

nlohmann::json DrawBandsJson(const std::vector<DrawBand>& bands) {
  using text::JsonNum;
  nlohmann::json runout = nlohmann::json::object();
  nlohmann::json partitions = nlohmann::json::array();
  for (const DrawBand& b : bands) {
    const nlohmann::json band = {
        {"p05", JsonNum(b.p05)}, {"median", JsonNum(b.median)}, {"p95", JsonNum(b.p95)}};
    const std::size_t dot = b.quantity.find('.');
    const std::string head = b.quantity.substr(0, dot);
    if (b.where == "runout") {
      runout[head][b.quantity.substr(dot + 1)] = band;
      continue;
    }
    if (partitions.empty() || partitions.back()["id"] != b.where)
      partitions.push_back({{"id", b.where}});
    if (dot == std::string::npos)
      partitions.back()[head] = band;
    else
      partitions.back()[head][b.quantity.substr(dot + 1)] = band;
  }
  return {{"runout", runout}, {"partitions", partitions}};
}

nlohmann::json PosteriorRunJson(const PosteriorRun& run) {
  int lo = run.draws.empty() ? 0 : run.draws.front().rocks, hi = lo;
  for (const PosteriorDraw& d : run.draws) {
    lo = std::min(lo, d.rocks);
    hi = std::max(hi, d.rocks);
  }
  if (run.class_draws)
    return {{"file", run.parameters.file},
            {"use", "class draws"},
            {"draws", static_cast<int>(run.draws.size())},
            {"rocks_per_draw", {{"min", lo}, {"max", hi}}},
            {"bands", DrawBandsJson(run.bands)}};
  return {{"file", run.parameters.file},
          {"use", "posterior draws"},
          {"samples_file", run.parameters.samples_file},
          {"samples", run.samples},
          {"draws", static_cast<int>(run.draws.size())},
          {"rocks_per_draw", {{"min", lo}, {"max", hi}}},
          {"bands", DrawBandsJson(run.bands)}};
}

std::string DrawsCsv(const PosteriorRun& run) {
  std::ostringstream out;
  out << "draw,sample,rocks";
  for (const CalibratedParameter& p : run.parameters.parameters)
    out << ',' << text::CsvField(p.material + "." + p.name);
  out << '\n';
  for (std::size_t k = 0; k < run.draws.size(); ++k) {
    const PosteriorDraw& d = run.draws[k];
    out << k << ',' << d.sample << ',' << d.rocks;
    for (double v : d.values) out << ',' << text::Num(v, "%.8g");
    out << '\n';
  }
  return out.str();
}

}  // namespace rockcal::calibrate
