#include "tracks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "../compare.h"
#include "../reader.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/file_keys.h"
#include "rockcal/sites/geometry.h"

namespace rockcal::observations {

std::vector<double> Tracks::Levels() { return {0.25, 0.5, 0.75}; }

using sites::FormatNumber;

namespace kinds {
namespace {

using sites::JsonNode;

// The residual names of the three distributions, in order (ResidualId::index).
constexpr const char* kHeight = "jump height";
constexpr const char* kLength = "jump length";
constexpr const char* kSpeed = "impact speed";

// ---------------------------------------------------------------------------
// Reader

// Index of run `id` in the runs given, -1 when none has it.
int RunIndex(const Runout& runout, const std::string& id) {
  for (std::size_t i = 0; i < runout.run_ids.size(); ++i)
    if (runout.run_ids[i] == id) return static_cast<int>(i);
  return -1;
}

std::string RunIdList(const Runout& runout) {
  std::string ids;
  for (std::size_t i = 0; i < runout.run_ids.size() && i < 8; ++i)
    ids += (i ? ", " : "") + runout.run_ids[i];
  return ids + (runout.run_ids.size() > 8 ? ", ..." : "");
}

// The "tracks_file" CSV: a header naming the columns run, t, x, y, z (in any
// order; other columns ignored), then one row per sample; each run's rows in
// increasing time (a run's rows need not be contiguous).
Tracks ReadTracksFile(const Reader& reader, const JsonNode& ref, const Runout& runout) {
  Tracks tracks;
  tracks.file = reader.CsvFile(ref);
  const CsvTable table{tracks.file, {}};
  sites::LineReader in(table.file);
  CsvRow row;
  std::string text;
  std::vector<std::string> header;
  const char* const names[] = {"run", "t", "x", "y", "z"};
  std::size_t col[5] = {0, 0, 0, 0, 0};
  std::map<std::string, std::size_t> by_run;  // run id -> index in tracks.tracks
  while (NextCsvRow(&in, &row, &text)) {
    if (header.empty()) {
      header = row.fields;
      for (int c = 0; c < 5; ++c) {
        const auto it = std::find(header.begin(), header.end(), names[c]);
        if (it == header.end())
          CsvFail(table, row,
                  std::string("expected a header naming the columns 'run', 't', 'x', 'y' and "
                              "'z' (no column '") +
                      names[c] + "'; found " + sites::Excerpt(text) + ")");
        col[c] = static_cast<std::size_t>(it - header.begin());
      }
      continue;
    }
    if (row.fields.size() != header.size())
      CsvFail(table, row,
              "expected " + std::to_string(header.size()) + " values per row (as the header), " +
                  "found " + std::to_string(row.fields.size()) + " in " + sites::Excerpt(text));
    const std::string& id = row.fields[col[0]];
    if (RunIndex(runout, id) < 0)
      CsvFail(table, row,
              "column 'run': " + sites::Excerpt(id) +
                  " is not a run given with 'runs' or 'runs_file' (expected one of: " +
                  RunIdList(runout) + ")");
    TrackSample s;
    s.t = CsvNumber(table, row, col[1], "t");
    s.x = Eigen::Vector3d(reader.Length(CsvNumber(table, row, col[2], "x")),
                          reader.Length(CsvNumber(table, row, col[3], "y")),
                          reader.Length(CsvNumber(table, row, col[4], "z")));
    auto [it, added] = by_run.emplace(id, tracks.tracks.size());
    if (added) {
      Track track;
      track.run = id;
      track.line = row.line;
      tracks.tracks.push_back(std::move(track));
    }
    Track& track = tracks.tracks[it->second];
    if (!track.samples.empty() && !(s.t > track.samples.back().t))
      CsvFail(table, row,
              "column 't': " + row.fields[col[1]] + " s does not come after run '" + id +
                  "''s previous sample at " + FormatNumber(track.samples.back().t) +
                  " s (expected each run's samples in increasing time)");
    track.samples.push_back(s);
  }
  if (tracks.tracks.empty())
    throw InputError(table.file,
                     "no data rows (expected a header 'run,t,x,y,z' and one row per "
                     "sample; referenced at " +
                         ref.where() + ")");
  std::vector<double> steps;
  for (const Track& track : tracks.tracks) {
    if (static_cast<int>(track.samples.size()) < tracks.flight.min_samples) {
      CsvRow first;
      first.line = track.line;
      CsvFail(table, first,
              "column 'run': run '" + track.run + "' has " + std::to_string(track.samples.size()) +
                  " sample" + (track.samples.size() == 1 ? "" : "s") + "; expected at least " +
                  std::to_string(tracks.flight.min_samples) +
                  " (the fewest a flight can be found in)");
    }
    for (std::size_t k = 1; k < track.samples.size(); ++k)
      steps.push_back(track.samples[k].t - track.samples[k - 1].t);
  }
  tracks.sample_seconds = core::Median(steps);
  return tracks;
}

void Read(const Reader& reader, const JsonNode& root, Observations* obs) {
  const auto ref = root.Find("tracks_file");
  if (!ref) return;
  if (!obs->runout || !obs->runout->has_runs())
    ref->Fail("tracks need the runs they belong to (expected 'runs' or 'runs_file' too)");
  obs->tracks = ReadTracksFile(reader, *ref, *obs->runout);
  std::size_t samples = 0;
  for (const Track& t : obs->tracks->tracks) samples += t.samples.size();
  obs->notes.push_back("tracks: " + std::to_string(obs->tracks->tracks.size()) + " of " +
                       std::to_string(obs->runout->run_ids.size()) + " runs tracked, " +
                       std::to_string(samples) + " samples, every " +
                       FormatNumber(obs->tracks->sample_seconds, "%.3g") +
                       " s (median; the simulated paths are sampled so)");
}

// The ground below a plan point: the site's triangulated surface
// (sites::ElevationAt, the terrain the rocks run on); NaN off the terrain.
Ground SiteGround(const core::HeightGrid& grid) {
  return [&grid](double x, double y) {
    const std::optional<double> z = sites::ElevationAt(grid, x, y);
    return z ? *z : std::numeric_limits<double>::quiet_NaN();
  };
}

// A path's flights and impacts, measured as the tracks' are.
void Measure(const std::vector<TrackSample>& samples, const FlightOptions& options,
             const Ground& ground, std::vector<double>* heights, std::vector<double>* lengths,
             std::vector<double>* speeds) {
  const TrackFlights found = DetectFlights(samples, options, ground);
  for (const Flight& f : found.flights) {
    const double h = f.JumpHeight(ground);
    if (std::isfinite(h)) heights->push_back(h);
    lengths->push_back(f.Length());
  }
  for (const TrackImpact& i : found.impacts) speeds->push_back(i.v_in.norm());
}

void ReadError(const Reader& reader, const JsonNode& error, Observations* obs) {
  if (const auto e = error.Find("track"))
    obs->error.track =
        sites::NumberInRange(*e, reader.Length(e->Positive()), 0.0, core::kMaxObservationError,
                             "track error", sites::Quantity::kLength, reader.units());
  if (const auto e = error.Find("impact_speed"))
    obs->error.impact_speed =
        sites::NumberInRange(*e, reader.Length(e->Positive()), 0.0, core::kMaxObservationError,
                             "impact speed error", sites::Quantity::kSpeed, reader.units());
  if (!obs->tracks || !(obs->error.track > 0)) return;
  // The track error is the detector's noise: the flights are read off now.
  Tracks& tracks = *obs->tracks;
  tracks.flight.noise = obs->error.track;
  tracks.flight.gravity = reader.scene().gravity;
  const Ground ground = SiteGround(reader.scene().grid);
  std::size_t flights = 0, impacts = 0;
  for (Track& t : tracks.tracks) {
    Measure(t.samples, tracks.flight, ground, &t.jump_heights, &t.jump_lengths, &t.impact_speeds);
    flights += t.jump_lengths.size();
    impacts += t.impact_speeds.size();
  }
  if (flights < 2)
    throw InputError(tracks.file,
                     std::to_string(flights) + " flight" + (flights == 1 ? "" : "s") +
                         " found in the tracks (error.track " +
                         FormatNumber(tracks.flight.noise, "%.3g") + " m: no flight shorter than " +
                         FormatNumber(tracks.flight.MinFlightTime(), "%.3g") +
                         " s can be told from ground contact); expected at least 2 to compare "
                         "(docs/field-campaigns.md, section 6)");
  obs->notes.push_back("tracks: " + std::to_string(flights) + " flights and " +
                       std::to_string(impacts) + " impacts found (flights of at least " +
                       FormatNumber(tracks.flight.MinFlightTime(), "%.3g") + " s)");
}

std::string MissingError(const Observations& obs, const JsonNode* error) {
  if (!obs.tracks) return "";
  for (const char* key : {"track", "impact_speed"})
    if (error == nullptr || !error->Has(key))
      return std::string("missing required key '") + key +
             "' (the one-sigma error of a track sample's position per axis ('track', in the "
             "file's length units) and of an impact speed ('impact_speed', in its units per "
             "second); needed by 'tracks_file')";
  return "";
}

// ---------------------------------------------------------------------------
// Recording and misfit

void Record(const Observations& obs, core::RecordOptions* base, bool*) {
  if (!obs.tracks || !obs.runout) return;
  std::vector<int> groups = base->trajectory_groups;
  for (const Track& t : obs.tracks->tracks) {
    const int i = RunIndex(*obs.runout, t.run);
    if (i >= 0) groups.push_back(obs.runout->run_groups[static_cast<std::size_t>(i)]);
  }
  std::sort(groups.begin(), groups.end());
  groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
  base->trajectory_groups = groups;
  base->sample_seconds = obs.tracks->sample_seconds;
}

// The three distributions of the tracks against those of the simulated
// rocks of the tracked runs' groups, each rock's path measured as the tracks
// are (DetectFlights with the same options and ground; docs/field-campaigns.md,
// section 6). Each rock counts once, even when its group is tracked twice (a
// rock counted twice would shrink its quantiles' errors). Quantiles at
// Tracks::Levels(), no maximum; the errors: error.track for heights,
// sqrt(2) error.track for lengths (two ends), error.impact_speed for speeds.
void AddResiduals(const Observations& obs, const MisfitTerms& terms) {
  if (!obs.tracks || !obs.runout) return;
  const Tracks& tracks = *obs.tracks;
  const Ground ground = SiteGround(terms.scene.grid);
  std::vector<std::vector<const core::RockRecord*>> by_group;
  for (const core::RockRecord& rock : terms.result.rocks) {
    const std::size_t g = static_cast<std::size_t>(rock.group);
    if (by_group.size() <= g) by_group.resize(g + 1);
    by_group[g].push_back(&rock);
  }
  std::set<int> measured;  // rock indices: a group tracked twice counts its rocks once
  TrackFit& fit = terms.misfit->tracks;
  // Which track (observed) or rock (simulated) each value came from: the
  // flights of one path are not independent draws (Comparer::Sample).
  std::vector<int> observed_by[3], simulated_by[3];
  std::vector<double>* const observed_values[3] = {&fit.observed_heights, &fit.observed_lengths,
                                                   &fit.observed_speeds};
  std::vector<double>* const simulated_values[3] = {&fit.simulated_heights, &fit.simulated_lengths,
                                                    &fit.simulated_speeds};
  auto label = [](std::vector<double>* const values[3], std::vector<int> by[3], int cluster) {
    for (int k = 0; k < 3; ++k) by[k].resize(values[k]->size(), cluster);
  };
  int track_index = 0;
  for (const Track& track : tracks.tracks) {
    const int run = RunIndex(*obs.runout, track.run);
    ++track_index;
    if (run < 0) continue;
    ++fit.tracks;
    fit.observed_heights.insert(fit.observed_heights.end(), track.jump_heights.begin(),
                                track.jump_heights.end());
    fit.observed_lengths.insert(fit.observed_lengths.end(), track.jump_lengths.begin(),
                                track.jump_lengths.end());
    fit.observed_speeds.insert(fit.observed_speeds.end(), track.impact_speeds.begin(),
                               track.impact_speeds.end());
    label(observed_values, observed_by, track_index);
    const std::size_t g =
        static_cast<std::size_t>(obs.runout->run_groups[static_cast<std::size_t>(run)]);
    if (g >= by_group.size()) continue;
    for (const core::RockRecord* rock : by_group[g]) {
      if (rock->trajectory.empty())
        throw std::invalid_argument("ComputeMisfit: tracks: rock " + std::to_string(rock->rock) +
                                    " of group " + std::to_string(g) +
                                    " recorded no path (simulate with RequiredRecording("
                                    "observations, ...))");
      if (!measured.insert(rock->rock).second) continue;  // its group tracked before
      std::vector<TrackSample> samples;
      samples.reserve(rock->trajectory.size());
      for (const core::TrajectorySample& s : rock->trajectory)
        if (samples.empty() || s.t > samples.back().t) samples.push_back({s.t, s.x});
      ++fit.rocks;
      if (samples.size() >= static_cast<std::size_t>(tracks.flight.min_samples))
        Measure(samples, tracks.flight, ground, &fit.simulated_heights, &fit.simulated_lengths,
                &fit.simulated_speeds);
      label(simulated_values, simulated_by, rock->rock);
    }
  }
  const std::vector<double> levels = Tracks::Levels();
  const char* const names[3] = {kHeight, kLength, kSpeed};
  const double errors[3] = {obs.error.track, std::sqrt(2.0) * obs.error.track,
                            obs.error.impact_speed};
  for (int k = 0; k < 3; ++k) {
    if (observed_values[k]->empty()) continue;  // e.g. a fold's tracks with no impact
    terms.compare.Quantiles(ResidualId::Of(ObservationKind::kTracks, k, names[k]),
                            Comparer::Sample{*simulated_values[k], simulated_by[k]},
                            Comparer::Sample{*observed_values[k], observed_by[k]}, errors[k],
                            levels, false);
  }
  for (std::vector<double>* v :
       {&fit.observed_heights, &fit.simulated_heights, &fit.observed_lengths,
        &fit.simulated_lengths, &fit.observed_speeds, &fit.simulated_speeds})
    std::sort(v->begin(), v->end());
}

std::string Text(const ResidualId& id) { return "tracks " + id.name; }

std::optional<ResidualId> ParseText(const std::string& text) {
  const auto name = After(text, "tracks ");
  if (!name) return std::nullopt;
  const char* const names[] = {kHeight, kLength, kSpeed};  // indices 0, 1, 2 (AddResiduals)
  for (int k = 0; k < 3; ++k)
    if (*name == names[k]) return ResidualId::Of(ObservationKind::kTracks, k, *name);
  return ResidualId::Of(ObservationKind::kTracks, -1, *name);
}

// Folds: a track goes with its run (the runs' folds, runout.cc): kept when
// its run is kept. Tracks left without a run are dropped.
void KeepFold(const Observations& observations, const observations::Fold&, bool,
              Observations* out) {
  if (!observations.tracks) return;
  if (!out->runout || !out->runout->has_runs()) {
    out->tracks.reset();
    return;
  }
  Tracks kept = *observations.tracks;
  kept.tracks.clear();
  for (const Track& t : observations.tracks->tracks)
    if (RunIndex(*out->runout, t.run) >= 0) kept.tracks.push_back(t);
  if (kept.tracks.empty())
    out->tracks.reset();
  else
    out->tracks = std::move(kept);
}

}  // namespace

Kind TracksKind() {
  Kind kind;
  kind.name = "tracks_file";
  kind.root_keys = {"tracks_file"};
  kind.error_keys = {"track", "impact_speed"};
  kind.residual_kinds = {ObservationKind::kTracks};
  kind.observation_text = Text;
  kind.parse_text = ParseText;
  kind.read = Read;
  kind.read_error = ReadError;
  kind.missing_error = MissingError;
  kind.record = Record;
  kind.misfit = AddResiduals;
  kind.subset = KeepFold;
  return kind;
}

}  // namespace kinds

std::string DetectedImpactsCsv(const Observations& observations, const core::Scene& scene) {
  std::string out = "id,group,x,y,z,vx_in,vy_in,vz_in,vx_out,vy_out,vz_out\n";
  if (!observations.tracks || !observations.runout) return out;
  const double unit = sites::LengthToSI(1.0, observations.units);  // m per file unit
  const Ground ground = kinds::SiteGround(scene.grid);
  for (const Track& track : observations.tracks->tracks) {
    const int run = kinds::RunIndex(*observations.runout, track.run);
    if (run < 0) continue;
    const std::size_t g =
        static_cast<std::size_t>(observations.runout->run_groups[static_cast<std::size_t>(run)]);
    const std::string group = g < scene.groups.size() ? scene.groups[g].id : "";
    const TrackFlights found = DetectFlights(track.samples, observations.tracks->flight, ground);
    int k = 0;
    for (const TrackImpact& impact : found.impacts) {
      out += track.run + "-" + std::to_string(++k) + "," + group;
      for (const Eigen::Vector3d* v : {&impact.x, &impact.v_in, &impact.v_out})
        for (int d = 0; d < 3; ++d) out += "," + FormatNumber((*v)[d] / unit, "%.10g");
      out += "\n";
    }
  }
  return out;
}

}  // namespace rockcal::observations
