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
#include "rockcal/core/error.h"
#include "rockcal/sites/crs.h"
#include "rockcal/sites/file_keys.h"
#include "rockcal/sites/geometry.h"
#include "rockcal/sites/raster.h"
#include "rockcal/sites/surface.h"
#include "rockcal/sites/text_reader.h"
#include "site_readers.h"

namespace rockcal::sites {
namespace {

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

// What a stand draws from: its polygon (SI) and its values; a stand of the
// site file and a cell of the stand rasters alike.
struct StandValues {
  double density = 0.0;  // stems per m^2
  double dbh_mean_cm = 0.0, dbh_sd_cm = 0.0;
  double conifer = 0.0;  // share in [0, 1]
  double height = kDefaultStemHeightM;
};

// What a drawn position off the terrain does: a stand (whose zone is on the
// terrain) draws it again, a raster cell (which may reach past the
// terrain's edge) drops it, so that the part of the cell on the terrain
// keeps the cell's density.
enum class OffTerrain { kRedraw, kDrop };

// The one draw of a stand's stems, from stream `stream` of the site's seed:
// a Poisson count of mean density times area (unit exponential gaps), then
// for each stem a position uniform in the polygon (rejection from its
// bounding box; over a hole or off the terrain drawn again or dropped as
// `off` says), a DBH normal of the stand's mean and spread redrawn until it
// lies in [kMinStandDbhCm, kMaxDbhCm], and a conifer with probability
// conifer. Each position is rounded to 0.001 of the site's length unit and
// each DBH to 0.1 cm, as trees.csv writes them, so that trees.csv read back
// as a trees_file gives the same stems bit for bit
// (docs/reference/site-file.md, `$.forest.stands[]`). Returns the stems
// added.
int DrawStems(const Polygon& polygon, const StandValues& v, Units units,
              const core::HeightGrid& grid, std::uint64_t seed, std::uint64_t stream,
              OffTerrain off, core::Forest* forest) {
  double x0 = polygon[0].x(), x1 = x0, y0 = polygon[0].y(), y1 = y0;
  for (const Eigen::Vector2d& p : polygon) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  core::RandomStream rng(seed, stream);
  const double expected = v.density * std::abs(SignedArea(polygon));
  int count = 0;
  for (double t = -std::log(1.0 - rng.Uniform()); t < expected; t += -std::log(1.0 - rng.Uniform()))
    ++count;
  // A length in SI as the site's unit writes it at 0.001 of it, read back.
  const double to_si = LengthToSI(1.0, units);
  const auto written = [units, to_si](double si) {
    return LengthToSI(std::round(si / to_si * 1000.0) / 1000.0, units);
  };
  int added = 0;
  for (int k = 0; k < count; ++k) {
    Eigen::Vector2d p;
    bool on = false;
    do {
      const double x = written(rng.Uniform(x0, x1));  // x, then y: a fixed order
      p = Eigen::Vector2d(x, written(rng.Uniform(y0, y1)));
      if (!core::PointInPolygon(polygon, p)) continue;
      on = OnTerrain(grid, p.x(), p.y());
      if (on || off == OffTerrain::kDrop) break;
    } while (true);
    double dbh;
    do {
      dbh = std::round((v.dbh_mean_cm + v.dbh_sd_cm * rng.Normal()) * 10.0) / 10.0;
    } while (!(dbh >= kMinStandDbhCm && dbh <= kMaxDbhCm));
    const bool is_conifer = rng.Uniform() < v.conifer;
    if (!on) continue;  // dropped, its draws made all the same
    forest->Add(p.x(), p.y(), dbh / 100.0, v.height,
                is_conifer ? core::SpeciesClass::kConifer : core::SpeciesClass::kBroadleaf);
    ++added;
  }
  return added;
}

// A stem height key ("height" of a stand or of the rasters), SI.
double ReadStemHeight(const JsonNode& node, Units units) {
  double height = kDefaultStemHeightM;
  if (auto h = node.Find("height")) {
    height = LengthToSI(h->Positive(), units);
    if (height > kMaxStemHeightM)
      h->Fail("expected a stem height of at most " + FormatNumber(kMaxStemHeightM) + " m");
  }
  return height;
}

// One entry of "stands", drawn from stream `stream`.
int DrawStand(const JsonNode& st, Units units, const core::HeightGrid& grid, std::uint64_t seed,
              std::uint64_t stream, core::Forest* forest) {
  st.Keys(SiteKeysAt("$.forest.stands[]"));
  const JsonNode zone = st.Get("zone");
  const Polygon polygon = ReadPolygon(zone, units);
  if (auto off = FindOffTerrain(grid, polygon, grid.spacing / 4))
    zone.Fail("stand zone point (" + FormatNumber(off->x() / LengthToSI(1.0, units)) + ", " +
              FormatNumber(off->y() / LengthToSI(1.0, units)) + ") " + LengthUnit(units) +
              " is off the terrain; expected a zone entirely on the terrain");
  StandValues v;
  v.density = st.Get("stems_per_ha").Number(0.0, kMaxStemsPerHa) / 1e4;  // per m^2
  v.dbh_mean_cm = st.Get("dbh_mean_cm").Number(kMinStandDbhCm, kMaxDbhCm);
  v.dbh_sd_cm = st.Get("dbh_sd_cm").Number(0.0, kMaxDbhCm);
  v.conifer = st.Get("conifer_percent").Number(0.0, 100.0) / 100.0;
  v.height = ReadStemHeight(st, units);
  return DrawStems(polygon, v, units, grid, seed, stream, OffTerrain::kRedraw, forest);
}

// The four stand rasters (docs/reference/site-file.md, `$.forest.rasters`):
// each cell is a stand of its own values over its square, drawn from
// stream `first_stream` + its index in the file's order (row 0 the
// northern, west to east). Cells with no stems (0 or nodata stems per ha)
// draw nothing; a cell with stems needs the other three values in range.
// Returns the stems drawn and sets *cells to the cells that drew.
int DrawRasters(const JsonNode& node, Units units, const std::string& base_dir,
                std::uint64_t seed, std::uint64_t first_stream, Site* site, int* cells) {
  node.Keys(SiteKeysAt("$.forest.rasters"));
  struct Layer {
    const char* key;
    const char* what;
    double min, max;
    std::string path;
    RasterFile raster;
  };
  Layer layers[] = {{"stems_per_ha", "a stem density in", 0.0, kMaxStemsPerHa, "", {}},
                    {"dbh_mean_cm", "a mean DBH in", kMinStandDbhCm, kMaxDbhCm, "", {}},
                    {"dbh_sd_cm", "a DBH standard deviation in", 0.0, kMaxDbhCm, "", {}},
                    {"conifer_percent", "a conifer share in", 0.0, 100.0, "", {}}};
  for (Layer& l : layers) {
    const JsonNode file = node.Get(l.key);
    l.path = ResolveDataFile(file, base_dir);
    l.raster = ReadRaster(l.path);
    const RasterGrid& g = l.raster.grid;
    const RasterGrid& first = layers[0].raster.grid;
    const auto same = [](double a, double b, double scale) {
      return std::abs(a - b) <= 1e-9 * scale;
    };
    if (&l != &layers[0] &&
        (g.ncols != first.ncols || g.nrows != first.nrows ||
         !same(g.cellsize, first.cellsize, first.cellsize) ||
         !same(g.x_center, first.x_center, first.cellsize) ||
         !same(g.y_center, first.y_center, first.cellsize)))
      throw InputError(l.path, std::to_string(g.ncols) + " x " + std::to_string(g.nrows) +
                                   " cells of " + FormatNumber(g.cellsize) + " from (" +
                                   FormatNumber(g.x_center) + ", " + FormatNumber(g.y_center) +
                                   "); expected the cells of " + layers[0].path + " (" +
                                   std::to_string(first.ncols) + " x " +
                                   std::to_string(first.nrows) + " of " +
                                   FormatNumber(first.cellsize) + " from (" +
                                   FormatNumber(first.x_center) + ", " +
                                   FormatNumber(first.y_center) + "))");
    if (!l.raster.crs_wkt.empty() && !site->crs_wkt.empty() &&
        !SameCrs(site->crs_wkt, l.raster.crs_wkt))
      throw InputError(l.path, "the CRS " + CrsLabel(l.raster.crs_wkt) + ", the terrain's " +
                                   CrsLabel(site->crs_wkt) +
                                   "; expected the same CRS (reproject it first, e.g. gdalwarp "
                                   "-t_srs)");
    for (const std::string& f : l.raster.files) site->inputs.push_back(f);
  }
  const double height = ReadStemHeight(node, units);
  const core::HeightGrid& grid = site->scene.grid;
  const RasterGrid& g = layers[0].raster.grid;
  const double to_si = LengthToSI(1.0, units);
  const double half = g.cellsize / 2;
  // The terrain's extent in the site's unit, to leave out cells beyond it.
  const double tx0 = grid.x0 / to_si, tx1 = grid.x(grid.nx - 1) / to_si;
  const double ty0 = grid.y0 / to_si, ty1 = grid.y(grid.ny - 1) / to_si;
  int drawn = 0, with_stems = 0;
  *cells = 0;
  for (int row = 0; row < g.nrows; ++row) {
    for (int i = 0; i < g.ncols; ++i) {
      const int j = g.nrows - 1 - row;  // from the south
      const double cx = g.x_center + i * g.cellsize, cy = g.y_center + j * g.cellsize;
      const auto where = [&] {
        return "the cell at column " + std::to_string(i + 1) + ", row " + std::to_string(row + 1) +
               " (centre " + FormatNumber(cx) + ", " + FormatNumber(cy) + " " + LengthUnit(units) +
               ")";
      };
      double value[4];
      for (int k = 0; k < 4; ++k) value[k] = layers[k].raster.grid.at(i, j);
      if (value[0] < 0 || value[0] > kMaxStemsPerHa)
        throw InputError(layers[0].path, where() + ": " + FormatNumber(value[0]) +
                                             " stems per ha; expected a stem density in [0, " +
                                             FormatNumber(kMaxStemsPerHa) + "] (or nodata)");
      if (!(value[0] > 0)) continue;  // nodata or none
      for (int k = 1; k < 4; ++k) {
        const Layer& l = layers[k];
        if (!(value[k] >= l.min && value[k] <= l.max))
          throw InputError(l.path, where() + ": " +
                                       (std::isnan(value[k]) ? std::string("nodata")
                                                             : FormatNumber(value[k])) +
                                       " where the stems raster has " + FormatNumber(value[0]) +
                                       " stems per ha; expected " + l.what + " [" +
                                       FormatNumber(l.min) + ", " + FormatNumber(l.max) + "]");
      }
      ++with_stems;
      if (cx + half < tx0 || cx - half > tx1 || cy + half < ty0 || cy - half > ty1) continue;
      ++*cells;
      const Polygon square = {Eigen::Vector2d(cx - half, cy - half) * to_si,
                              Eigen::Vector2d(cx + half, cy - half) * to_si,
                              Eigen::Vector2d(cx + half, cy + half) * to_si,
                              Eigen::Vector2d(cx - half, cy + half) * to_si};
      StandValues v;
      v.density = value[0] / 1e4;
      v.dbh_mean_cm = value[1];
      v.dbh_sd_cm = value[2];
      v.conifer = value[3] / 100.0;
      v.height = height;
      const std::uint64_t cell = static_cast<std::uint64_t>(row) * g.ncols + i;
      drawn += DrawStems(square, v, units, grid, seed, first_stream + cell, OffTerrain::kDrop,
                         &site->scene.forest);
    }
  }
  if (with_stems > 0 && *cells == 0)
    throw InputError(layers[0].path,
                     "no cell with stems overlaps the terrain (the raster's cells span x " +
                         FormatNumber(g.x_center - half) + " to " +
                         FormatNumber(g.x_center + (g.ncols - 1) * g.cellsize + half) + ", y " +
                         FormatNumber(g.y_center - half) + " to " +
                         FormatNumber(g.y_center + (g.nrows - 1) * g.cellsize + half) +
                         ", the terrain x " + FormatNumber(tx0) + " to " + FormatNumber(tx1) +
                         ", y " + FormatNumber(ty0) + " to " + FormatNumber(ty1) + " " +
                         LengthUnit(units) +
                         "); expected rasters in the site's frame and length unit over the "
                         "terrain");
  return drawn;
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
  std::size_t stand_count = 0;
  if (auto stands = node.Find("stands")) {
    const std::vector<JsonNode> list = stands->Array(1);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const int n = DrawStand(list[k], units, grid, site->scene.options.seed,
                              kStandStreams + static_cast<std::uint64_t>(k), &forest);
      note += " stand " + std::to_string(k + 1) + ": " + std::to_string(n) + " stems drawn";
    }
    stand_count = list.size();
  }
  // The rasters' cells are stands after the site file's, their streams next.
  if (auto rasters = node.Find("rasters")) {
    int cells = 0;
    const int n = DrawRasters(*rasters, units, base_dir, site->scene.options.seed,
                              kStandStreams + static_cast<std::uint64_t>(stand_count), site, &cells);
    note += " rasters: " + std::to_string(n) + " stems drawn in " + std::to_string(cells) +
            " cells";
  }
  if (forest.stems.empty())
    node.Fail("no stems: expected at least one of trees_file, trees, stands, rasters giving a stem");
  site->notes.push_back(note + " (" + std::to_string(forest.stems.size()) + " in all)");
}

}  // namespace rockcal::sites
