// The site file's "forest" (docs/reference/site-file.md, `$.forest`): a
// tree file, inline trees and stands whose stems are drawn from the site's
// seed, into core::Forest (SI units).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rockcal/core/forest.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/polygon.h"
#include "rockcal/core/random.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/geometry.h"
#include "rockcal/sites/surface.h"
#include "rockcal/sites/text_reader.h"
#include "site_readers.h"

namespace rockcal::sites {
namespace {

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A species name -> its class; false for another name.
bool ParseSpecies(const std::string& text, core::SpeciesClass* species) {
  const std::string name = Lower(text);
  if (name == "conifer") {
    *species = core::SpeciesClass::kConifer;
    return true;
  }
  if (name == "broadleaf") {
    *species = core::SpeciesClass::kBroadleaf;
    return true;
  }
  return false;
}
constexpr const char* kSpeciesNames = "\"conifer\" or \"broadleaf\"";

// The checks of one stem; an empty string when it is fine, else what was
// expected (the caller names the file and line or the JSON path).
std::string StemFault(double dbh_cm, double height_m, double x, double y,
                      const core::HeightGrid& grid) {
  if (!(dbh_cm >= kMinDbhCm && dbh_cm <= kMaxDbhCm))
    return "dbh_cm " + FormatNumber(dbh_cm) + ": expected a diameter at breast height in [" +
           FormatNumber(kMinDbhCm) + ", " + FormatNumber(kMaxDbhCm) + "] cm";
  if (!(height_m > 0 && height_m <= kMaxStemHeightM))
    return "height: expected a stem height > 0 and at most " + FormatNumber(kMaxStemHeightM) + " m";
  if (!OnTerrain(grid, x, y))
    return "the stem at (" + FormatNumber(x) + ", " + FormatNumber(y) +
           ") m is off the terrain (outside the grid or over a hole); expected stems on the "
           "terrain";
  return "";
}

// The tree file: a header naming x, y, dbh_cm and optionally species and
// height (any order, any case), then one stem a row.
void ReadTreesFile(const std::string& path, Units units, const core::HeightGrid& grid,
                   core::Forest* forest) {
  LineReader in(path);
  std::string line;
  std::vector<std::string> header;
  while (in.Next(&line)) {
    if (IsBlank(line) || line[line.find_first_not_of(" \t")] == '#') continue;
    header = SplitFields(line);
    break;
  }
  constexpr const char* kColumns = "x, y, dbh_cm and optionally species and height";
  if (header.empty()) in.Fail(std::string("no header row (expected the columns ") + kColumns + ")");
  int cx = -1, cy = -1, cd = -1, cs = -1, ch = -1;
  for (std::size_t k = 0; k < header.size(); ++k) {
    const std::string name = Lower(header[k]);
    int* column = name == "x"         ? &cx
                  : name == "y"       ? &cy
                  : name == "dbh_cm"  ? &cd
                  : name == "species" ? &cs
                  : name == "height"  ? &ch
                                      : nullptr;
    if (!column)
      in.Fail("unknown column " + Excerpt(header[k]) + " (expected the columns " + kColumns + ")");
    if (*column >= 0) in.Fail("column " + Excerpt(header[k]) + " appears twice");
    *column = static_cast<int>(k);
  }
  if (cx < 0 || cy < 0 || cd < 0)
    in.Fail(std::string("missing column ") +
            (cx < 0   ? "x"
             : cy < 0 ? "y"
                      : "dbh_cm") +
            " (expected the columns " + kColumns + ")");
  int stems = 0;
  while (in.Next(&line)) {
    if (IsBlank(line) || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != header.size())
      in.Fail(std::to_string(fields.size()) + " fields; expected " + std::to_string(header.size()) +
              " as in the header");
    std::vector<std::string> numeric = {fields[static_cast<std::size_t>(cx)],
                                        fields[static_cast<std::size_t>(cy)],
                                        fields[static_cast<std::size_t>(cd)]};
    if (ch >= 0) numeric.push_back(fields[static_cast<std::size_t>(ch)]);
    const std::vector<double> v = in.Numbers(numeric);
    const double x = LengthToSI(v[0], units), y = LengthToSI(v[1], units);
    const double height = ch >= 0 ? LengthToSI(v[3], units) : kDefaultStemHeightM;
    core::SpeciesClass species = core::SpeciesClass::kConifer;
    if (cs >= 0 && !ParseSpecies(fields[static_cast<std::size_t>(cs)], &species))
      in.Fail("species " + Excerpt(fields[static_cast<std::size_t>(cs)]) + ": expected " +
              kSpeciesNames);
    const std::string fault = StemFault(v[2], height, x, y, grid);
    if (!fault.empty()) in.Fail(fault);
    forest->Add(x, y, v[2] / 100.0, height, species);
    ++stems;
  }
  if (stems == 0) in.Fail("no stems (expected one row per stem after the header)");
}

// One entry of "trees".
void ReadTree(const JsonNode& t, Units units, const core::HeightGrid& grid, core::Forest* forest) {
  t.Keys(SiteKeysAt("$.forest.trees[]"));
  const double x = CoordinateToSI(t.Get("x"), units), y = CoordinateToSI(t.Get("y"), units);
  const JsonNode d = t.Get("dbh_cm");
  const double dbh = d.Number();
  double height = kDefaultStemHeightM;
  if (auto h = t.Find("height")) height = LengthToSI(h->Positive(), units);
  core::SpeciesClass species = core::SpeciesClass::kConifer;
  if (auto s = t.Find("species"))
    if (!ParseSpecies(s->String(), &species))
      s->Fail("\"" + s->String() + "\": expected " + kSpeciesNames);
  const std::string fault = StemFault(dbh, height, x, y, grid);
  if (!fault.empty()) t.Fail(fault);
  forest->Add(x, y, dbh / 100.0, height, species);
}

// A stand's stems, drawn from stream `stream` of the site's seed: a Poisson
// count of mean density times area (unit exponential gaps), then for each
// stem a position uniform in the polygon (rejection from its bounding box,
// again while it falls over a hole), a DBH normal of the stand's mean and
// spread redrawn until it lies in [kMinStandDbhCm, kMaxDbhCm], and a
// conifer with probability conifer_percent / 100. Each position is rounded
// to 0.001 of the site's length unit and each DBH to 0.1 cm, as trees.csv
// writes them, so that trees.csv read back as a trees_file gives the same
// stems bit for bit (docs/reference/site-file.md, `$.forest.stands[]`).
int DrawStand(const JsonNode& st, Units units, const core::HeightGrid& grid, std::uint64_t seed,
              std::uint64_t stream, core::Forest* forest) {
  st.Keys(SiteKeysAt("$.forest.stands[]"));
  const JsonNode zone = st.Get("zone");
  const Polygon polygon = ReadPolygon(zone, units);
  if (auto off = FindOffTerrain(grid, polygon, grid.spacing / 4))
    zone.Fail("stand zone point (" + FormatNumber(off->x() / LengthToSI(1.0, units)) + ", " +
              FormatNumber(off->y() / LengthToSI(1.0, units)) + ") " + LengthUnit(units) +
              " is off the terrain; expected a zone entirely on the terrain");
  const double density = st.Get("stems_per_ha").Number(0.0, kMaxStemsPerHa) / 1e4;  // per m^2
  const double mean = st.Get("dbh_mean_cm").Number(kMinStandDbhCm, kMaxDbhCm);
  const double sd = st.Get("dbh_sd_cm").Number(0.0, kMaxDbhCm);
  const double conifer = st.Get("conifer_percent").Number(0.0, 100.0) / 100.0;
  double height = kDefaultStemHeightM;
  if (auto h = st.Find("height")) {
    height = LengthToSI(h->Positive(), units);
    if (height > kMaxStemHeightM)
      h->Fail("expected a stem height of at most " + FormatNumber(kMaxStemHeightM) + " m");
  }
  double x0 = polygon[0].x(), x1 = x0, y0 = polygon[0].y(), y1 = y0;
  for (const Eigen::Vector2d& p : polygon) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  core::RandomStream rng(seed, stream);
  const double expected = density * std::abs(SignedArea(polygon));
  int count = 0;
  for (double t = -std::log(1.0 - rng.Uniform()); t < expected; t += -std::log(1.0 - rng.Uniform()))
    ++count;
  // A length in SI as the site's unit writes it at 0.001 of it, read back.
  const double to_si = LengthToSI(1.0, units);
  const auto written = [units, to_si](double si) {
    return LengthToSI(std::round(si / to_si * 1000.0) / 1000.0, units);
  };
  for (int k = 0; k < count; ++k) {
    Eigen::Vector2d p;
    do {
      const double x = written(rng.Uniform(x0, x1));  // x, then y: a fixed order
      p = Eigen::Vector2d(x, written(rng.Uniform(y0, y1)));
    } while (!core::PointInPolygon(polygon, p) || !OnTerrain(grid, p.x(), p.y()));
    double dbh;
    do {
      dbh = std::round((mean + sd * rng.Normal()) * 10.0) / 10.0;
    } while (!(dbh >= kMinStandDbhCm && dbh <= kMaxDbhCm));
    const bool is_conifer = rng.Uniform() < conifer;
    forest->Add(p.x(), p.y(), dbh / 100.0, height,
                is_conifer ? core::SpeciesClass::kConifer : core::SpeciesClass::kBroadleaf);
  }
  return count;
}

void ReadContact(const JsonNode& c, core::TrunkContact* contact) {
  c.Keys(SiteKeysAt("$.forest.contact"));
  if (auto e = c.Find("restitution")) {
    contact->restitution = e->Number();
    if (!(contact->restitution > 0 && contact->restitution < 1))
      e->Fail("expected a value in (0, 1)");
  }
  if (auto t = c.Find("contact_time"))
    contact->contact_time = t->Number(core::kMinContactTime, core::kMaxContactTime);
  if (auto f = c.Find("friction")) contact->friction = f->Number(0.0, 10.0);
}

}  // namespace

void ReadForest(const JsonNode& node, Units units, const std::string& base_dir, Site* site) {
  node.Keys(SiteKeysAt("$.forest"));
  core::Forest& forest = site->scene.forest;
  const core::HeightGrid& grid = site->scene.grid;
  if (auto c = node.Find("contact")) ReadContact(*c, &forest.contact);
  if (auto f = node.Find("capacity_factor")) forest.capacity_factor = f->Number(0.01, 100.0);
  // The forest's values calibrated like a material's (core::kForestEntry).
  if (auto c = node.Find("calibrate")) {
    c->Keys(SiteKeysAt("$.forest.calibrate"));
    for (const core::MaterialFieldInfo& f : core::MaterialFields()) {
      if (!f.forest) continue;
      if (auto b = c->Find(f.name))
        site->calibrate.push_back(ReadBound(*b, core::kForestEntry, core::kForestEntry, f.name,
                                            f.min, f.max, false,
                                            core::ForestFieldValue(forest, f.field), 1.0, ""));
    }
  }
  std::string note = "forest:";
  if (auto file = node.Find("trees_file")) {
    const std::string path = ResolveDataFile(*file, base_dir);
    ReadTreesFile(path, units, grid, &forest);
    site->inputs.push_back(path);
    note += " " + std::to_string(forest.stems.size()) + " stems from " + file->String();
  }
  if (auto trees = node.Find("trees")) {
    const std::size_t before = forest.stems.size();
    for (const JsonNode& t : trees->Array(1)) ReadTree(t, units, grid, &forest);
    note += " " + std::to_string(forest.stems.size() - before) + " inline stems";
  }
  site->drawn_stems_first = forest.stems.size();
  if (auto stands = node.Find("stands")) {
    const std::vector<JsonNode> list = stands->Array(1);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const int n = DrawStand(list[k], units, grid, site->scene.options.seed,
                              kStandStreams + static_cast<std::uint64_t>(k), &forest);
      note += " stand " + std::to_string(k + 1) + ": " + std::to_string(n) + " stems drawn";
    }
  }
  if (forest.stems.empty())
    node.Fail("no stems: expected at least one of trees_file, trees, stands giving a stem");
  site->notes.push_back(note + " (" + std::to_string(forest.stems.size()) + " in all)");
}

}  // namespace rockcal::sites
