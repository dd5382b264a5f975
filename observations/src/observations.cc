#include "rockcal/observations/observations.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <random>
#include <sstream>
#include <utility>

#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/core/statistics.h"
#include "rockcal/observations/file_keys.h"
#include "rockcal/sites/geometry.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::observations {
namespace {

using sites::FormatNumber;
using sites::JsonNode;
using sites::ParseNumber;
using sites::SplitFields;
using sites::Units;

std::string FormatPoint(const Eigen::Vector2d& p) {
  return "(" + FormatNumber(p.x()) + ", " + FormatNumber(p.y()) + ")";
}

std::string QuotedList(std::initializer_list<const char*> keys) {
  std::string out;
  for (const char* k : keys) out += std::string(out.empty() ? "'" : ", '") + k + "'";
  return out;
}

// Returns the one key of `keys` present in the object `node`; throws when none
// or more than one is present.
std::string OneOf(const JsonNode& node, std::initializer_list<const char*> keys) {
  std::vector<std::string> present;
  for (const char* k : keys) {
    if (node.Has(k)) present.emplace_back(k);
  }
  if (present.empty()) {
    throw InputError(node.where(),
                     "missing required key (expected exactly one of " + QuotedList(keys) + ")");
  }
  if (present.size() > 1) {
    throw InputError(node.where(), "keys '" + present[0] + "' and '" + present[1] +
                                       "' both given (expected exactly one of " + QuotedList(keys) +
                                       ")");
  }
  return present[0];
}

// ---------------------------------------------------------------------------
// CSV files: one row per line, fields separated by commas (or, on lines
// without a comma, by blanks); blank lines and lines starting with '#' are
// skipped; the first row is a header when every field starts with a letter.

struct CsvRow {
  int line = 0;
  std::vector<std::string> fields;
};

struct CsvTable {
  std::string file;  // resolved path
  std::vector<CsvRow> rows;
};

// The next row of `in` (skipping blank lines, '#' comments and a UTF-8 byte
// order mark; fields unquoted), with its text for messages; false at the end.
bool NextCsvRow(sites::LineReader* in, CsvRow* row, std::string* text) {
  std::string line;
  while (in->Next(&line)) {
    if (in->line() == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (sites::IsBlank(line)) continue;
    *text = line.substr(line.find_first_not_of(" \t"));
    if ((*text)[0] == '#') continue;
    *row = CsvRow{in->line(), SplitFields(*text)};
    for (std::string& f : row->fields)
      if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    return true;
  }
  return false;
}

bool LooksLikeHeader(const std::vector<std::string>& fields) {
  for (const std::string& f : fields) {
    if (f.empty()) return false;
    const unsigned char c = static_cast<unsigned char>(f[0]);
    if (!std::isalpha(c) && c != '_') return false;
  }
  return true;
}

std::string ColumnList(std::initializer_list<const char*> columns) {
  std::string out;
  for (const char* c : columns) out += std::string(out.empty() ? "" : ", ") + c;
  return out;
}

[[noreturn]] void CsvFail(const CsvTable& table, const CsvRow& row, const std::string& what) {
  throw InputError(table.file + ":" + std::to_string(row.line), what);
}

// Field `i` (named `column`) of `row` as a finite number.
double CsvNumber(const CsvTable& table, const CsvRow& row, std::size_t i, const char* column) {
  double v = 0.0;
  if (!ParseNumber(row.fields[i], &v)) {
    CsvFail(table, row,
            std::string("expected a number for '") + column + "' (found " +
                sites::Excerpt(row.fields[i]) + ")");
  }
  if (!(std::abs(v) <= core::kMaxCoordinate)) {
    CsvFail(table, row,
            std::string("'") + column + "' " + sites::Excerpt(row.fields[i]) +
                " is outside the physically sensible range; expected within +-" +
                FormatNumber(core::kMaxCoordinate));
  }
  return v;
}

double CsvNonNegative(const CsvTable& table, const CsvRow& row, std::size_t i, const char* column) {
  const double v = CsvNumber(table, row, i, column);
  if (v < 0) {
    CsvFail(table, row,
            std::string("expected '") + column + "' >= 0 (found " + row.fields[i] + ")");
  }
  return v;
}

// ---------------------------------------------------------------------------

// The unit vector from `from` towards the mean of `stop_points`: the runout
// direction when the file gives none. Throws, naming `node`, when the mean
// stop point is the origin or the direction has no finite normalisation.
Eigen::Vector2d TowardsMeanStop(const JsonNode& node,
                                const std::vector<Eigen::Vector2d>& stop_points,
                                const Eigen::Vector2d& from) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : stop_points) mean += p;
  mean /= static_cast<double>(stop_points.size());
  const Eigen::Vector2d d = mean - from;
  if (!(d.norm() > 1e-9 * (1.0 + from.norm()))) {
    throw InputError(node.where(), "cannot choose a runout direction: the mean stop point " +
                                       FormatPoint(mean) + " m coincides with the origin " +
                                       FormatPoint(from) + " m (expected 'direction' [dx, dy])");
  }
  const Eigen::Vector2d direction = d / d.norm();
  if (!direction.allFinite() || !(std::abs(direction.norm() - 1.0) < 1e-9)) {
    throw InputError(node.where(), "cannot choose a runout direction: the direction from " +
                                       FormatPoint(from) + " to the mean stop point " +
                                       FormatPoint(mean) +
                                       " m has no finite normalisation (expected 'direction')");
  }
  return direction;
}

class Loader final {
 public:
  Loader(const std::string& path, const core::Scene& scene) : path_(path), scene_(scene) {}

  Observations Load();

 private:
  double Length(double v) const { return sites::LengthToSI(v, units_); }
  std::string Resolve(const std::string& file) const;
  // The CSV file named by the string at `ref`, resolved, checked to be a
  // file and noted as an input.
  std::string CsvFile(const JsonNode& ref) const;
  CsvTable ReadCsv(const JsonNode& ref, std::initializer_list<const char*> columns) const;

  // Index of the partition named by the string at `node`, or throws listing the ids.
  int FindPartition(const JsonNode& node) const;
  int FindPartition(const std::string& id) const;
  std::string PartitionIds() const;

  // Heights of `node` from its "heights" list or its "heights_file".
  std::vector<double> ReadHeights(const JsonNode& node) const;
  ScarSet ReadScarSet(const JsonNode& node, std::size_t index) const;
  Tree ReadTree(const JsonNode& node) const;
  std::vector<Tree> ReadTreesFile(const JsonNode& ref) const;
  Runout ReadRunout(const JsonNode& node, std::vector<std::string>* notes) const;
  Runout ReadRunoutPositions(const JsonNode& node, std::vector<std::string>* notes) const;
  // Per-run observations: the "runs" array or the "runs_file" CSV.
  Runout ReadRuns(const JsonNode& node, std::vector<std::string>* notes) const;
  Runout ReadRunsFile(const JsonNode& ref, std::vector<std::string>* notes) const;
  // Adds run `id` tied to group `group` (its id) stopped at `stop` (SI) to
  // `runout`; `where` names the JSON path or the CSV file and line of the
  // run for the errors (no such group, a stop off the terrain, a repeated id).
  void AddRun(const std::string& where, const std::string& id, const std::string& group,
              const Eigen::Vector2d& stop, Runout* runout) const;
  void NoteRuns(const Runout& runout, std::vector<std::string>* notes) const;
  std::vector<Passing> ReadPassing(const JsonNode& node) const;
  std::vector<Passing> ReadPassingFile(const JsonNode& ref) const;

  std::string path_;
  const core::Scene& scene_;
  Units units_ = Units::kUS;
  mutable std::vector<std::string> csv_files_;  // the CSV files read, in order
};

std::string Loader::Resolve(const std::string& file) const {
  const std::filesystem::path p(file);
  if (p.is_absolute()) return file;
  const std::filesystem::path base = std::filesystem::path(path_).parent_path();
  return base.empty() ? file : (base / p).string();
}

std::string Loader::CsvFile(const JsonNode& ref) const {
  const std::string name = ref.String();
  if (name.empty()) ref.Fail("expected a CSV file name");
  const std::string file = Resolve(name);
  if (const std::string problem = sites::InputFileProblem(file, "CSV file"); !problem.empty())
    ref.Fail(problem);
  csv_files_.push_back(file);
  return file;
}

CsvTable Loader::ReadCsv(const JsonNode& ref, std::initializer_list<const char*> columns) const {
  CsvTable table;
  table.file = CsvFile(ref);
  sites::LineReader in(table.file);
  CsvRow row;
  std::string text;
  bool first = true;
  while (NextCsvRow(&in, &row, &text)) {
    if (first) {
      first = false;
      if (LooksLikeHeader(row.fields)) continue;
    }
    if (row.fields.size() != columns.size()) {
      CsvFail(table, row,
              "expected " + std::to_string(columns.size()) + " value" +
                  (columns.size() == 1 ? "" : "s") + " per row (" + ColumnList(columns) +
                  "), found " + std::to_string(row.fields.size()) + " in " + sites::Excerpt(text));
    }
    table.rows.push_back(std::move(row));
  }
  if (table.rows.empty()) {
    throw InputError(table.file, "no data rows (expected rows of " + ColumnList(columns) +
                                     "; referenced at " + ref.where() + ")");
  }
  return table;
}

std::string Loader::PartitionIds() const {
  if (scene_.partitions.empty()) return "the site has no partitions";
  std::string ids;
  for (const core::Partition& p : scene_.partitions) ids += (ids.empty() ? "" : ", ") + p.id;
  return "partitions of the site: " + ids;
}

int Loader::FindPartition(const std::string& id) const {
  for (std::size_t i = 0; i < scene_.partitions.size(); ++i) {
    if (scene_.partitions[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

int Loader::FindPartition(const JsonNode& node) const {
  const int index = FindPartition(node.String());
  if (index < 0) node.Fail("unknown partition id (" + PartitionIds() + ")");
  return index;
}

std::vector<double> Loader::ReadHeights(const JsonNode& node) const {
  std::vector<double> heights;
  if (OneOf(node, {"heights", "heights_file"}) == "heights") {
    for (const JsonNode& h : node.Get("heights").Array(1))
      heights.push_back(Length(h.NonNegative()));
  } else {
    const CsvTable table = ReadCsv(node.Get("heights_file"), {"height"});
    for (const CsvRow& row : table.rows)
      heights.push_back(Length(CsvNonNegative(table, row, 0, "height")));
  }
  return heights;
}

Tree Loader::ReadTree(const JsonNode& node) const {
  node.Keys(ObservationsKeysAt("$.tree_scars[].trees[]"));
  Tree tree;
  tree.x = sites::CoordinateToSI(node.Get("x"), units_);
  tree.y = sites::CoordinateToSI(node.Get("y"), units_);
  tree.radius = Length(node.Get("radius").NonNegative());
  tree.heights = ReadHeights(node);
  return tree;
}

std::vector<Tree> Loader::ReadTreesFile(const JsonNode& ref) const {
  // One scar per row; rows at the same (x, y) belong to the same tree.
  const CsvTable table = ReadCsv(ref, {"x", "y", "radius", "height"});
  std::vector<Tree> trees;
  std::vector<int> first_line;
  for (const CsvRow& row : table.rows) {
    const double x = Length(CsvNumber(table, row, 0, "x"));
    const double y = Length(CsvNumber(table, row, 1, "y"));
    const double radius = Length(CsvNonNegative(table, row, 2, "radius"));
    const double height = Length(CsvNonNegative(table, row, 3, "height"));
    std::size_t k = 0;
    while (k < trees.size() && !(trees[k].x == x && trees[k].y == y)) ++k;
    if (k == trees.size()) {
      Tree tree;
      tree.x = x;
      tree.y = y;
      tree.radius = radius;
      trees.push_back(tree);
      first_line.push_back(row.line);
    } else if (trees[k].radius != radius) {
      CsvFail(table, row,
              "tree at (" + row.fields[0] + ", " + row.fields[1] + ") has radius " + row.fields[2] +
                  " here but a different radius on line " + std::to_string(first_line[k]) +
                  " (expected one radius per tree)");
    }
    trees[k].heights.push_back(height);
  }
  return trees;
}

ScarSet Loader::ReadScarSet(const JsonNode& node, std::size_t index) const {
  node.Keys(ObservationsKeysAt("$.tree_scars[]"));
  ScarSet set;
  const std::string label = "tree_scars[" + std::to_string(index) + "]";
  const std::string form = OneOf(node, {"partition", "trees", "trees_file"});
  if (form == "partition") {
    set.partition = FindPartition(node.Get("partition"));
    set.heights = ReadHeights(node);
    set.label = label + " " + scene_.partitions[static_cast<std::size_t>(set.partition)].id;
    return set;
  }
  for (const char* key : {"heights", "heights_file"}) {
    if (node.Has(key)) {
      throw InputError(node.where() + "." + key,
                       std::string("'") + key +
                           "' belongs to a set with 'partition'; in a set of trees each tree "
                           "has its own heights");
    }
  }
  if (form == "trees") {
    for (const JsonNode& t : node.Get("trees").Array(1)) set.trees.push_back(ReadTree(t));
  } else {
    set.trees = ReadTreesFile(node.Get("trees_file"));
  }
  set.label = label + " trees";
  return set;
}

Runout Loader::ReadRunout(const JsonNode& node, std::vector<std::string>* notes) const {
  Runout runout = ReadRunoutPositions(node, notes);
  const int n = static_cast<int>(runout.distances.size());
  runout.observed_rocks = n;
  if (const auto r = node.Find("observed_rocks")) {
    runout.observed_rocks = static_cast<int>(r->Integer(n, 100'000'000));
  }
  if (const auto f = node.Find("stopped_fraction")) {
    runout.stopped_fraction = f->Number(0.0, 1.0);
    if (!(runout.stopped_fraction > 0)) f->Fail("expected a fraction in (0, 1]: some rocks stopped");
  }
  if (const auto m = node.Find("masses")) {
    const std::vector<JsonNode> items = m->Array(1);
    if (static_cast<int>(items.size()) != n) {
      m->Fail("holds " + std::to_string(items.size()) + " masses; expected one per stop (" +
              std::to_string(n) + ")");
    }
    const double unit = units_ == Units::kSI ? 1.0 : 0.45359237;  // kg or lb
    for (const JsonNode& item : items) {
      const double mass = item.Number() * unit;
      if (!(mass > 0 && mass <= 1e8)) item.Fail("expected a block mass > 0 and at most 1e8 kg");
      runout.masses.push_back(mass);
    }
    runout.mass_classes = std::min(4, n / 4);
    if (runout.mass_classes < 2) runout.mass_classes = 0;
  }
  if (const auto c = node.Find("mass_classes")) {
    if (runout.masses.empty()) c->Fail("goes with 'masses' (the mass of each stopped block)");
    runout.mass_classes = static_cast<int>(c->Integer(0, std::max(0, n / 2)));
    if (runout.mass_classes == 1) c->Fail("expected 0 (off) or at least 2 classes");
  }
  if (runout.mass_classes >= 2) {
    std::string bounds;
    for (double b : runout.MassClassBounds())
      bounds += (bounds.empty() ? "" : ", ") + FormatNumber(b);
    notes->push_back("runout: also compared in " + std::to_string(runout.mass_classes) +
                     " mass classes split at " + bounds + " kg");
  }
  return runout;
}

Runout Loader::ReadRunoutPositions(const JsonNode& node, std::vector<std::string>* notes) const {
  node.Keys(ObservationsKeysAt("$.runout"));
  const std::string form =
      OneOf(node, {"stop_points", "stop_points_file", "distances", "distances_file"});
  std::optional<Eigen::Vector2d> from, direction;
  if (const auto f = node.Find("from")) {
    const std::vector<double> v = sites::CoordinatesToSI(*f, 2, units_);
    from = Eigen::Vector2d(v[0], v[1]);
  }
  if (const auto d = node.Find("direction")) {
    const std::vector<double> v = d->Numbers(2);
    const Eigen::Vector2d dir(v[0], v[1]);
    const Eigen::Vector2d unit = dir / dir.norm();
    if (!(dir.norm() > 0) || !unit.allFinite() || !(std::abs(unit.norm() - 1.0) < 1e-9))
      d->Fail("expected a non-zero direction [dx, dy] whose normalisation is finite");
    direction = unit;
  }

  Runout runout;
  if (form == "distances" || form == "distances_file") {
    if (!from) {
      throw InputError(
          node.where(),
          "missing required key 'from' (the point [x, y] distances are measured from)");
    }
    if (!direction) {
      throw InputError(node.where(),
                       "missing required key 'direction' ([dx, dy] along which distances are "
                       "measured)");
    }
    runout.from = *from;
    runout.direction = *direction;
    if (form == "distances") {
      for (const JsonNode& d : node.Get("distances").Array(1))
        runout.distances.push_back(Length(d.Number()));
    } else {
      const CsvTable table = ReadCsv(node.Get("distances_file"), {"distance"});
      for (const CsvRow& row : table.rows)
        runout.distances.push_back(Length(CsvNumber(table, row, 0, "distance")));
    }
    notes->push_back("runout: " + std::to_string(runout.distances.size()) + " distances from " +
                     FormatPoint(runout.from) + " m along " + FormatPoint(runout.direction));
    return runout;
  }

  if (form == "stop_points") {
    for (const JsonNode& p : node.Get("stop_points").Array(1)) {
      const std::vector<double> v = sites::CoordinatesToSI(p, 2, units_);
      runout.stop_points.emplace_back(v[0], v[1]);
    }
  } else {
    const CsvTable table = ReadCsv(node.Get("stop_points_file"), {"x", "y"});
    for (const CsvRow& row : table.rows) {
      runout.stop_points.emplace_back(Length(CsvNumber(table, row, 0, "x")),
                                      Length(CsvNumber(table, row, 1, "y")));
    }
  }

  std::string from_note = "as given";
  if (from) {
    runout.from = *from;
  } else {
    if (scene_.groups.empty()) {
      throw InputError(node.where(),
                       "missing required key 'from': the site has no rock group whose release "
                       "could be the origin of runout distances");
    }
    runout.from = ReleaseCentroid(scene_.groups[0].release);
    from_note = "the release of the first rock group";
  }
  std::string direction_note = "as given";
  if (direction) {
    runout.direction = *direction;
  } else {
    runout.direction = TowardsMeanStop(node, runout.stop_points, runout.from);
    direction_note = "towards the mean stop point";
  }
  for (const Eigen::Vector2d& p : runout.stop_points) {
    runout.distances.push_back(runout.Distance(p));
    runout.lateral.push_back(runout.Lateral(p));
  }
  notes->push_back("runout: " + std::to_string(runout.stop_points.size()) +
                   " stop points; distances from " + FormatPoint(runout.from) + " m (" + from_note +
                   ") along " + FormatPoint(runout.direction) + " (" + direction_note +
                   "), lateral offsets positive to the left");
  return runout;
}

void Loader::AddRun(const std::string& where, const std::string& id, const std::string& group,
                    const Eigen::Vector2d& stop, Runout* runout) const {
  if (id.empty()) throw InputError(where, "expected a non-empty run id");
  for (const std::string& other : runout->run_ids)
    if (other == id) throw InputError(where, "run id '" + id + "' is given twice; expected each run once");
  int index = -1;
  for (std::size_t g = 0; g < scene_.groups.size(); ++g)
    if (scene_.groups[g].id == group) index = static_cast<int>(g);
  if (index < 0) {
    std::string ids;
    int shown = 0;
    for (const core::RockGroup& g : scene_.groups)
      if (!g.id.empty() && shown++ < 8) ids += (ids.empty() ? "" : ", ") + g.id;
    throw InputError(where, "run '" + id + "': no rock group of the site has the id '" + group +
                                "' (expected the 'id' of the rock group released as this run " +
                                "was; " + (ids.empty() ? "the site's groups have no ids" : "ids: " + ids +
                                (shown > 8 ? ", ..." : "")) + ")");
  }
  if (!sites::OnTerrain(scene_.grid, stop.x(), stop.y()))
    throw InputError(where, "run '" + id + "': stop point " + FormatPoint(stop) +
                                " m is off the terrain (outside the grid or over a hole); "
                                "expected a stop point on the terrain");
  const Eigen::Vector2d origin = ReleaseCentroid(scene_.groups[static_cast<std::size_t>(index)].release);
  runout->run_ids.push_back(id);
  runout->run_groups.push_back(index);
  runout->run_origins.push_back(origin);
  runout->stop_points.push_back(stop);
  runout->distances.push_back((stop - origin).norm());
}

void Loader::NoteRuns(const Runout& runout, std::vector<std::string>* notes) const {
  const std::vector<double>& d = runout.distances;
  notes->push_back("runout: " + std::to_string(d.size()) +
                   " tracked runs, each measured from its own rock group's release (runout " +
                   FormatNumber(*std::min_element(d.begin(), d.end()), "%.4g") + "-" +
                   FormatNumber(*std::max_element(d.begin(), d.end()), "%.4g") +
                   " m) and compared with that group's rocks only");
}

Runout Loader::ReadRuns(const JsonNode& node, std::vector<std::string>* notes) const {
  Runout runout;
  for (const JsonNode& run : node.Array(1)) {
    run.Keys(ObservationsKeysAt("$.runs[]"));
    const std::string id = run.Get("id").String();
    const std::string group = run.Has("group") ? run.Get("group").String() : id;
    const std::vector<double> v = sites::CoordinatesToSI(run.Get("stop"), 2, units_);
    AddRun(run.where(), id, group, Eigen::Vector2d(v[0], v[1]), &runout);
  }
  NoteRuns(runout, notes);
  return runout;
}

Runout Loader::ReadRunsFile(const JsonNode& ref, std::vector<std::string>* notes) const {
  // A table with a header naming its columns: the run's id ("id" or
  // "run"), its rock group ("group", default the run's id) and its stop
  // point ("stop_x", "stop_y", or with the suffix "_m" or "_ft"); other
  // columns (a tracked campaign's release state, masses...) are ignored.
  const CsvTable table{CsvFile(ref), {}};
  sites::LineReader in(table.file);
  CsvRow row;
  std::string text;
  std::vector<std::string> header;
  int id_col = -1, group_col = -1, x_col = -1, y_col = -1;
  Runout runout;
  while (NextCsvRow(&in, &row, &text)) {
    if (header.empty()) {
      header = row.fields;
      auto find = [&](std::initializer_list<const char*> names) {
        for (std::size_t c = 0; c < header.size(); ++c)
          for (const char* n : names)
            if (header[c] == n) return static_cast<int>(c);
        return -1;
      };
      id_col = find({"id", "run"});
      group_col = find({"group"});
      x_col = find({"stop_x", "stop_x_m", "stop_x_ft"});
      y_col = find({"stop_y", "stop_y_m", "stop_y_ft"});
      if (id_col < 0 || x_col < 0 || y_col < 0)
        CsvFail(table, row,
                "expected a header naming the columns 'id' (or 'run'), 'stop_x' and 'stop_y' "
                "(optionally 'group'; found " + sites::Excerpt(text) + ")");
      continue;
    }
    if (row.fields.size() != header.size())
      CsvFail(table, row,
              "expected " + std::to_string(header.size()) + " values per row (as the header), "
              "found " + std::to_string(row.fields.size()) + " in " + sites::Excerpt(text));
    const std::size_t xi = static_cast<std::size_t>(x_col), yi = static_cast<std::size_t>(y_col);
    const Eigen::Vector2d stop(Length(CsvNumber(table, row, xi, "stop_x")),
                               Length(CsvNumber(table, row, yi, "stop_y")));
    const std::string id = row.fields[static_cast<std::size_t>(id_col)];
    const std::string group =
        group_col >= 0 ? row.fields[static_cast<std::size_t>(group_col)] : id;
    AddRun(table.file + ":" + std::to_string(row.line), id, group, stop, &runout);
  }
  if (runout.distances.empty())
    throw InputError(table.file,
                     "no data rows (expected a header and one row per run; referenced at " +
                         ref.where() + ")");
  NoteRuns(runout, notes);
  return runout;
}

std::vector<Passing> Loader::ReadPassing(const JsonNode& node) const {
  std::vector<Passing> out;
  for (const JsonNode& e : node.Array(1)) {
    e.Keys(ObservationsKeysAt("$.passing[]"));
    Passing p;
    p.partition = FindPartition(e.Get("partition"));
    p.fraction = e.Get("fraction").Number(0.0, 1.0);
    p.label = "passing[" + std::to_string(out.size()) + "] " +
              scene_.partitions[static_cast<std::size_t>(p.partition)].id;
    out.push_back(p);
  }
  return out;
}

std::vector<Passing> Loader::ReadPassingFile(const JsonNode& ref) const {
  const CsvTable table = ReadCsv(ref, {"partition", "fraction"});
  std::vector<Passing> out;
  for (const CsvRow& row : table.rows) {
    Passing p;
    p.partition = FindPartition(row.fields[0]);
    if (p.partition < 0) {
      CsvFail(
          table, row,
          "unknown partition id " + sites::Excerpt(row.fields[0]) + " (" + PartitionIds() + ")");
    }
    p.fraction = CsvNumber(table, row, 1, "fraction");
    if (p.fraction < 0 || p.fraction > 1) {
      CsvFail(table, row, "expected 'fraction' in [0, 1] (found " + row.fields[1] + ")");
    }
    p.label = "passing[" + std::to_string(out.size()) + "] " +
              scene_.partitions[static_cast<std::size_t>(p.partition)].id;
    out.push_back(p);
  }
  return out;
}

Observations Loader::Load() {
  const nlohmann::json doc = sites::ReadJsonFile(path_);
  const JsonNode root(&doc, path_, "$");
  root.Keys(ObservationsKeysAt("$"));

  Observations obs;
  obs.path = path_;
  units_ = sites::ReadUnits(root.Get("units"));
  obs.units = units_;

  if (const auto scars = root.Find("tree_scars")) {
    const std::vector<JsonNode> sets = scars->Array(1);
    for (std::size_t i = 0; i < sets.size(); ++i) obs.tree_scars.push_back(ReadScarSet(sets[i], i));
    int probe = 0;
    for (ScarSet& set : obs.tree_scars) {
      for (Tree& tree : set.trees) tree.probe = probe++;
      const std::size_t n = set.ObservedHeights().size();
      obs.notes.push_back(set.label + ": " + std::to_string(n) + " scar height" +
                          (n == 1 ? "" : "s") +
                          (set.at_partition() ? ""
                                              : " at " + std::to_string(set.trees.size()) +
                                                    " tree" + (set.trees.size() == 1 ? "" : "s")));
    }
  }
  {
    const int forms = root.Has("runout") + root.Has("runs") + root.Has("runs_file");
    if (forms > 1)
      throw InputError(root.where(), "expected at most one of 'runout' (stop points pooled about "
                                     "one origin), 'runs' and 'runs_file' (tracked runs)");
  }
  if (const auto runout = root.Find("runout")) obs.runout = ReadRunout(*runout, &obs.notes);
  if (const auto runs = root.Find("runs")) obs.runout = ReadRuns(*runs, &obs.notes);
  if (const auto runs = root.Find("runs_file")) obs.runout = ReadRunsFile(*runs, &obs.notes);
  if (obs.runout && obs.runout->has_runs()) obs.runout->observed_rocks = static_cast<int>(obs.runout->distances.size());
  if (root.Has("passing") && root.Has("passing_file")) {
    throw InputError(root.where(),
                     "keys 'passing' and 'passing_file' both given (expected at most one)");
  }
  if (const auto passing = root.Find("passing")) obs.passing = ReadPassing(*passing);
  if (const auto passing = root.Find("passing_file")) obs.passing = ReadPassingFile(*passing);

  if (obs.empty()) {
    throw InputError(root.where(),
                     "no observations (expected at least one of 'tree_scars', 'runout', "
                     "'passing', 'passing_file')");
  }

  const auto error = root.Find("error");
  bool has_height = false, has_runout = false;
  if (error) {
    error->Keys(ObservationsKeysAt("$.error"));
    if (const auto h = error->Find("height")) {
      obs.error.height =
          sites::NumberInRange(*h, Length(h->Positive()), 0.0, core::kMaxObservationError,
                               "height error", sites::Quantity::kLength, units_);
      has_height = true;
    }
    if (const auto r = error->Find("runout")) {
      obs.error.runout =
          sites::NumberInRange(*r, Length(r->Positive()), 0.0, core::kMaxObservationError,
                               "runout error", sites::Quantity::kLength, units_);
      has_runout = true;
    }
    if (const auto p = error->Find("passing")) {
      obs.error.passing = p->Positive();
      if (obs.error.passing > 1) p->Fail("expected a fraction in (0, 1]");
    }
  }
  if (!error && (!obs.tree_scars.empty() || obs.runout)) {
    throw InputError(root.where(),
                     "missing required key 'error' (the one-sigma measurement errors in the "
                     "file's units: 'height' for tree_scars, 'runout' for runout)");
  }
  const std::string error_where = error ? error->where() : root.where();
  if (!obs.tree_scars.empty() && !has_height) {
    throw InputError(error_where,
                     "missing required key 'height' (the one-sigma error of scar heights, in "
                     "the file's units; needed by 'tree_scars')");
  }
  if (obs.runout && !has_runout) {
    throw InputError(error_where,
                     "missing required key 'runout' (the one-sigma error of stop positions, in "
                     "the file's units; needed by 'runout')");
  }

  for (const Passing& p : obs.passing) {
    obs.notes.push_back(p.label + ": fraction " + FormatNumber(p.fraction));
  }
  obs.inputs.push_back(path_);
  obs.inputs.insert(obs.inputs.end(), csv_files_.begin(), csv_files_.end());
  return obs;
}

}  // namespace

std::vector<double> ScarSet::ObservedHeights() const {
  if (at_partition()) return heights;
  std::vector<double> out;
  for (const Tree& tree : trees) out.insert(out.end(), tree.heights.begin(), tree.heights.end());
  return out;
}

Observations LoadObservations(const std::string& path, const core::Scene& scene) {
  return Loader(path, scene).Load();
}

core::RecordOptions RequiredRecording(const Observations& observations, core::RecordOptions base) {
  bool partitions = !observations.passing.empty();
  base.trees.clear();
  for (const ScarSet& set : observations.tree_scars) {
    if (set.at_partition()) partitions = true;
    for (const Tree& tree : set.trees) {
      core::TreeProbe probe;
      probe.x = tree.x;
      probe.y = tree.y;
      probe.radius = tree.radius;
      base.trees.push_back(probe);
    }
  }
  base.partitions = partitions;
  return base;
}

std::vector<std::string> DuplicateRunWarnings(const Observations& observations) {
  std::vector<std::string> out;
  if (!observations.runout || !observations.runout->has_runs()) return out;
  const Runout& r = *observations.runout;
  constexpr double kSame = 1e-3;  // m
  for (std::size_t i = 0; i < r.run_ids.size(); ++i)
    for (std::size_t j = i + 1; j < r.run_ids.size(); ++j)
      if ((r.run_origins[i] - r.run_origins[j]).norm() <= kSame &&
          (r.stop_points[i] - r.stop_points[j]).norm() <= kSame)
        out.push_back("runs '" + r.run_ids[i] + "' and '" + r.run_ids[j] +
                      "' have the same release point and the same stop point, " +
                      FormatPoint(r.stop_points[i]) +
                      " m: one run written twice counts twice in the misfit; remove the copy "
                      "if it is one");
  return out;
}

namespace {

bool SameBlocks(const std::vector<core::Block>& a, const std::vector<core::Block>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].shape != b[k].shape || a[k].sides != b[k].sides || a[k].mass != b[k].mass ||
        a[k].scanned != b[k].scanned)
      return false;
  return true;
}

// Whether two rock groups release the same rocks (wherever they release them).
bool SameRocks(const core::RockGroup& a, const core::RockGroup& b) {
  return a.shape == b.shape && a.size_min == b.size_min && a.size_max == b.size_max &&
         a.unit_weight == b.unit_weight && a.box == b.box && a.scanned == b.scanned &&
         SameBlocks(a.inventory, b.inventory);
}

}  // namespace

std::string RepeatScatter::Sentence() const {
  return "repeated runs: " + std::to_string(runs) + " runs in " + std::to_string(sets) +
         " sets (the same rocks released within " + FormatNumber(kRepeatRadius, "%g") +
         " m of one another); a run's runout differs from its set's median by " +
         FormatNumber(own_median_error_m, "%.3g") + " m on average, from the median of the " +
         "set's other runs by " + FormatNumber(others_median_error_m, "%.3g") +
         " m: a mean per-run error near these is the campaign's own repeatability";
}

std::optional<RepeatScatter> RunRepeatScatter(const Observations& observations,
                                              const core::Scene& scene) {
  if (!observations.runout || !observations.runout->has_runs()) return std::nullopt;
  const Runout& r = *observations.runout;
  const std::size_t n = r.run_ids.size();
  std::vector<bool> placed(n, false);
  RepeatScatter out;
  double own = 0.0, others = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (placed[i]) continue;
    const core::RockGroup& first = scene.groups[static_cast<std::size_t>(r.run_groups[i])];
    std::vector<std::size_t> set;
    for (std::size_t j = i; j < n; ++j)
      if (!placed[j] &&
          (r.run_origins[j] - r.run_origins[i]).norm() <= RepeatScatter::kRepeatRadius &&
          SameRocks(first, scene.groups[static_cast<std::size_t>(r.run_groups[j])])) {
        placed[j] = true;
        set.push_back(j);
      }
    if (set.size() < 3) continue;
    std::vector<double> runouts;
    for (const std::size_t j : set) runouts.push_back(r.distances[j]);
    const double median = core::Median(runouts);
    for (std::size_t k = 0; k < set.size(); ++k) {
      std::vector<double> rest = runouts;
      rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(k));
      own += std::abs(runouts[k] - median);
      others += std::abs(runouts[k] - core::Median(rest));
    }
    ++out.sets;
    out.runs += static_cast<int>(set.size());
  }
  if (out.sets == 0) return std::nullopt;
  out.own_median_error_m = own / out.runs;
  out.others_median_error_m = others / out.runs;
  return out;
}

std::vector<double> Runout::MassClassBounds() const {
  std::vector<double> bounds;
  if (mass_classes < 2 || masses.empty()) return bounds;
  std::vector<double> sorted = masses;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 1; k < mass_classes; ++k)
    bounds.push_back(core::Quantile(sorted, static_cast<double>(k) / mass_classes));
  return bounds;
}

namespace {

// Deals indices 0..n-1, shuffled with `rng`, round-robin into k lists.
std::vector<std::vector<std::size_t>> Deal(std::size_t n, int k, std::mt19937_64* rng) {
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  for (std::size_t i = n; i > 1; --i) {  // Fisher-Yates, independent of the library's shuffle
    const std::size_t j = static_cast<std::size_t>((*rng)() % i);
    std::swap(order[i - 1], order[j]);
  }
  std::vector<std::vector<std::size_t>> out(static_cast<std::size_t>(k));
  for (std::size_t i = 0; i < n; ++i) out[i % static_cast<std::size_t>(k)].push_back(order[i]);
  for (auto& fold : out) std::sort(fold.begin(), fold.end());
  return out;
}

// Whether index i is (held_out) or is not (training) in `fold_indices`.
bool Keep(const std::vector<std::size_t>& fold_indices, std::size_t i, bool held_out) {
  return std::binary_search(fold_indices.begin(), fold_indices.end(), i) == held_out;
}

}  // namespace

std::vector<Fold> MakeFolds(const Observations& observations, int k, std::uint64_t seed) {
  if (k < 2) throw InputError("--holdout", std::to_string(k) + ": expected at least 2 folds");
  std::mt19937_64 rng(seed);
  std::vector<Fold> folds(static_cast<std::size_t>(k));
  for (int f = 0; f < k; ++f) {
    folds[static_cast<std::size_t>(f)].index = f;
    folds[static_cast<std::size_t>(f)].count = k;
  }
  for (const ScarSet& set : observations.tree_scars) {
    const std::size_t n = set.ObservedHeights().size();
    if (n < static_cast<std::size_t>(k))
      throw InputError(observations.path, set.label + ": " + std::to_string(n) +
                                              " heights, fewer than the " + std::to_string(k) +
                                              " folds of --holdout");
    const auto dealt = Deal(n, k, &rng);
    for (int f = 0; f < k; ++f) folds[static_cast<std::size_t>(f)].scars.push_back(dealt[static_cast<std::size_t>(f)]);
  }
  if (observations.runout) {
    const std::size_t n = observations.runout->distances.size();
    if (n < static_cast<std::size_t>(k))
      throw InputError(observations.path, "runout: " + std::to_string(n) +
                                              " stop points, fewer than the " + std::to_string(k) +
                                              " folds of --holdout");
    const auto dealt = Deal(n, k, &rng);
    for (int f = 0; f < k; ++f) folds[static_cast<std::size_t>(f)].runout = dealt[static_cast<std::size_t>(f)];
  }
  return folds;
}

Observations Subset(const Observations& observations, const Fold& fold, bool held_out) {
  Observations out = observations;
  out.tree_scars.clear();
  int probe = 0;
  for (std::size_t s = 0; s < observations.tree_scars.size(); ++s) {
    const ScarSet& set = observations.tree_scars[s];
    const std::vector<std::size_t>& in_fold = fold.scars.at(s);
    ScarSet kept = set;
    std::size_t i = 0;  // index into ObservedHeights()
    if (set.at_partition()) {
      kept.heights.clear();
      for (double h : set.heights)
        if (Keep(in_fold, i++, held_out)) kept.heights.push_back(h);
    } else {
      kept.trees.clear();
      for (const Tree& tree : set.trees) {
        Tree t = tree;
        t.heights.clear();
        for (double h : tree.heights)
          if (Keep(in_fold, i++, held_out)) t.heights.push_back(h);
        if (!t.heights.empty()) kept.trees.push_back(t);
      }
    }
    if (kept.ObservedHeights().empty()) continue;
    for (Tree& t : kept.trees) t.probe = probe++;
    out.tree_scars.push_back(std::move(kept));
  }
  if (observations.runout) {
    const Runout& r = *observations.runout;
    Runout kept = r;
    kept.distances.clear();
    kept.stop_points.clear();
    kept.lateral.clear();
    kept.masses.clear();
    kept.run_ids.clear();
    kept.run_groups.clear();
    kept.run_origins.clear();
    for (std::size_t i = 0; i < r.distances.size(); ++i) {
      if (!Keep(fold.runout, i, held_out)) continue;
      kept.distances.push_back(r.distances[i]);
      if (i < r.stop_points.size()) kept.stop_points.push_back(r.stop_points[i]);
      if (i < r.lateral.size()) kept.lateral.push_back(r.lateral[i]);
      if (i < r.masses.size()) kept.masses.push_back(r.masses[i]);
      if (i < r.run_ids.size()) {
        kept.run_ids.push_back(r.run_ids[i]);
        kept.run_groups.push_back(r.run_groups[i]);
        kept.run_origins.push_back(r.run_origins[i]);
      }
    }
    // The observed share stands for the kept rocks as for all of them; the
    // mass classes keep at least four blocks each (none below two classes).
    const int n = static_cast<int>(kept.distances.size());
    const int all = static_cast<int>(r.distances.size());
    kept.observed_rocks =
        r.observed_rocks > all ? static_cast<int>(std::lround(1.0 * r.observed_rocks * n / all)) : n;
    kept.mass_classes = std::min(r.mass_classes, n / 4);
    if (kept.mass_classes < 2) kept.mass_classes = 0;
    if (kept.distances.empty()) out.runout.reset();
    else out.runout = std::move(kept);
  }
  if (held_out) out.passing.clear();
  return out;
}

Eigen::Vector2d ReleaseCentroid(const core::Release& release) {
  const std::vector<Eigen::Vector2d>& zone = release.zone;
  if (zone.empty()) return release.point;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : zone) mean += p;
  mean /= static_cast<double>(zone.size());
  // Area centroid (shoelace), relative to the vertex mean for accuracy.
  double twice_area = 0.0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double extent = 0.0;
  for (std::size_t i = 0; i < zone.size(); ++i) {
    const Eigen::Vector2d a = zone[i] - mean;
    const Eigen::Vector2d b = zone[(i + 1) % zone.size()] - mean;
    const double cross = a.x() * b.y() - b.x() * a.y();
    twice_area += cross;
    sum += (a + b) * cross;
    extent = std::max(extent, a.norm());
  }
  if (!(std::abs(twice_area) > 1e-12 * extent * extent)) return mean;
  return mean + sum / (3.0 * twice_area);
}

}  // namespace rockcal::observations
