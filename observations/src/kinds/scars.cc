#include "scars.h"

#include <cmath>
#include <string>
#include <utility>

#include "../compare.h"
#include "../reader.h"
#include "rockcal/core/error.h"
#include "rockcal/core/limits.h"
#include "rockcal/observations/file_keys.h"

namespace rockcal::observations {

std::vector<double> ScarSet::ObservedHeights() const {
  if (at_partition()) return heights;
  std::vector<double> out;
  for (const Tree& tree : trees) out.insert(out.end(), tree.heights.begin(), tree.heights.end());
  return out;
}

namespace kinds {
namespace {

using sites::JsonNode;

// ---------------------------------------------------------------------------
// Reader

// Heights of `node` from its "heights" list or its "heights_file".
std::vector<double> ReadHeights(const Reader& reader, const JsonNode& node) {
  std::vector<double> heights;
  if (OneOf(node, {"heights", "heights_file"}) == "heights") {
    for (const JsonNode& h : node.Get("heights").Array(1))
      heights.push_back(reader.Length(h.NonNegative()));
  } else {
    const CsvTable table = reader.ReadCsv(node.Get("heights_file"), {"height"});
    for (const CsvRow& row : table.rows)
      heights.push_back(reader.Length(CsvNonNegative(table, row, 0, "height")));
  }
  return heights;
}

Tree ReadTree(const Reader& reader, const JsonNode& node) {
  node.Keys(ObservationsKeysAt("$.tree_scars[].trees[]"));
  Tree tree;
  tree.x = sites::CoordinateToSI(node.Get("x"), reader.units());
  tree.y = sites::CoordinateToSI(node.Get("y"), reader.units());
  tree.radius = reader.Length(node.Get("radius").NonNegative());
  tree.heights = ReadHeights(reader, node);
  return tree;
}

std::vector<Tree> ReadTreesFile(const Reader& reader, const JsonNode& ref) {
  // One scar per row; rows at the same (x, y) belong to the same tree.
  const CsvTable table = reader.ReadCsv(ref, {"x", "y", "radius", "height"});
  std::vector<Tree> trees;
  std::vector<int> first_line;
  for (const CsvRow& row : table.rows) {
    const double x = reader.Length(CsvNumber(table, row, 0, "x"));
    const double y = reader.Length(CsvNumber(table, row, 1, "y"));
    const double radius = reader.Length(CsvNonNegative(table, row, 2, "radius"));
    const double height = reader.Length(CsvNonNegative(table, row, 3, "height"));
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

ScarSet ReadScarSet(const Reader& reader, const JsonNode& node, std::size_t index) {
  node.Keys(ObservationsKeysAt("$.tree_scars[]"));
  ScarSet set;
  const std::string label = "tree_scars[" + std::to_string(index) + "]";
  const std::string form = OneOf(node, {"partition", "trees", "trees_file"});
  if (form == "partition") {
    set.partition = reader.FindPartition(node.Get("partition"));
    set.heights = ReadHeights(reader, node);
    set.label = label + " " + reader.scene().partitions[static_cast<std::size_t>(set.partition)].id;
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
    for (const JsonNode& t : node.Get("trees").Array(1)) set.trees.push_back(ReadTree(reader, t));
  } else {
    set.trees = ReadTreesFile(reader, node.Get("trees_file"));
  }
  set.label = label + " trees";
  return set;
}

// The stem of `forest` that `tree` is (Tree::stem): the nearest whose trunk
// touches or overlaps the tree's in plan; -1 when none does.
int StemOf(const Tree& tree, const core::Forest& forest) {
  int found = -1;
  double nearest = 0.0;
  for (std::size_t k = 0; k < forest.stems.size(); ++k) {
    const core::Stem& stem = forest.stems[k];
    const double d = std::hypot(stem.x - tree.x, stem.y - tree.y);
    if (d <= 0.5 * stem.dbh + tree.radius && (found < 0 || d < nearest)) {
      found = static_cast<int>(k);
      nearest = d;
    }
  }
  return found;
}

void Read(const Reader& reader, const JsonNode& root, Observations* obs) {
  const auto scars = root.Find("tree_scars");
  if (!scars) return;
  const std::vector<JsonNode> sets = scars->Array(1);
  for (std::size_t i = 0; i < sets.size(); ++i)
    obs->tree_scars.push_back(ReadScarSet(reader, sets[i], i));
  int probe = 0;
  for (ScarSet& set : obs->tree_scars) {
    int at_stems = 0;
    for (Tree& tree : set.trees) {
      tree.probe = probe++;
      tree.stem = StemOf(tree, reader.scene().forest);
      at_stems += tree.stem >= 0;
    }
    const std::size_t n = set.ObservedHeights().size();
    std::string note = set.label + ": " + std::to_string(n) + " scar height" + (n == 1 ? "" : "s");
    if (!set.at_partition()) {
      note +=
          " at " + std::to_string(set.trees.size()) + " tree" + (set.trees.size() == 1 ? "" : "s");
      if (at_stems > 0)
        note += "; " + std::to_string(at_stems) +
                " of them at stems of the forest, compared with " +
                "the heights at which rocks strike those stems";
    }
    obs->notes.push_back(note);
  }
}

void ReadError(const Reader& reader, const JsonNode& error, Observations* obs) {
  if (const auto h = error.Find("height")) {
    obs->error.height =
        sites::NumberInRange(*h, reader.Length(h->Positive()), 0.0, core::kMaxObservationError,
                             "height error", sites::Quantity::kLength, reader.units());
  }
}

std::string MissingError(const Observations& obs, const JsonNode* error) {
  if (obs.tree_scars.empty() || (error != nullptr && error->Has("height"))) return "";
  return "missing required key 'height' (the one-sigma error of scar heights, in the file's "
         "units; needed by 'tree_scars')";
}

// ---------------------------------------------------------------------------
// Recording and misfit

void Record(const Observations& obs, core::RecordOptions* base, bool* partitions) {
  for (const ScarSet& set : obs.tree_scars) {
    if (set.at_partition()) *partitions = true;
    for (const Tree& tree : set.trees) {
      core::TreeProbe probe;
      probe.x = tree.x;
      probe.y = tree.y;
      probe.radius = tree.radius;
      base->trees.push_back(probe);
      if (tree.stem >= 0) base->tree_strikes = true;
    }
  }
}

// Each set's heights against the bounce heights of the rocks that crossed
// its partition, or those at its trees pooled (a rock passing two trees
// counts twice): at a tree that is a stem of the forest, the heights at
// which rocks struck it; at any other tree, the heights at which they
// passed it.
void AddResiduals(const Observations& obs, const MisfitTerms& terms) {
  const core::SimulationResult& result = terms.result;
  for (std::size_t i = 0; i < obs.tree_scars.size(); ++i) {
    const ScarSet& set = obs.tree_scars[i];
    std::vector<double> simulated;
    if (set.at_partition()) {
      terms.CheckPartition(set.label, set.partition);
      const std::size_t p = static_cast<std::size_t>(set.partition);
      for (const core::RockRecord& rock : result.rocks) {
        if (rock.crossings[p].crossed) simulated.push_back(rock.crossings[p].height);
      }
    } else {
      for (const Tree& tree : set.trees) {
        if (tree.stem >= 0) {
          for (const core::RockRecord& rock : result.rocks)
            for (const core::TreeStrike& strike : rock.strikes)
              if (strike.tree == tree.stem) simulated.push_back(strike.height);
          continue;
        }
        terms.CheckProbe(set.label, tree.probe);
        const std::size_t k = static_cast<std::size_t>(tree.probe);
        for (const core::RockRecord& rock : result.rocks) {
          if (rock.trees[k].crossed) simulated.push_back(rock.trees[k].height);
        }
      }
    }
    terms.compare.Distributions(
        ResidualId::Of(ObservationKind::kTreeScars, static_cast<int>(i), set.label),
        std::move(simulated), set.ObservedHeights(), obs.error.height);
  }
}

std::string Text(const ResidualId& id) { return id.name; }

std::optional<ResidualId> ParseText(const std::string& text) {
  return IndexedText(ObservationKind::kTreeScars, "tree_scars", text);
}

// ---------------------------------------------------------------------------
// Folds: each set's heights dealt on their own.

void DealFolds(const Observations& obs, int k, std::mt19937_64* rng,
               std::vector<observations::Fold>* folds) {
  for (const ScarSet& set : obs.tree_scars) {
    const std::size_t n = set.ObservedHeights().size();
    if (n < static_cast<std::size_t>(k))
      throw InputError(obs.path, set.label + ": " + std::to_string(n) +
                                     " heights, fewer than the " + std::to_string(k) +
                                     " folds of --holdout");
    const auto dealt = Deal(n, k, rng);
    for (int f = 0; f < k; ++f)
      (*folds)[static_cast<std::size_t>(f)].scars.push_back(dealt[static_cast<std::size_t>(f)]);
  }
}

// A set left without heights is dropped; tree probes are renumbered in order.
void KeepFold(const Observations& obs, const observations::Fold& fold, bool held_out,
              Observations* out) {
  out->tree_scars.clear();
  int probe = 0;
  for (std::size_t s = 0; s < obs.tree_scars.size(); ++s) {
    const ScarSet& set = obs.tree_scars[s];
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
    out->tree_scars.push_back(std::move(kept));
  }
}

}  // namespace

Kind ScarsKind() {
  Kind kind;
  kind.name = "tree_scars";
  kind.root_keys = {"tree_scars"};
  kind.objects = {
      {"$.tree_scars[]", {"partition", "heights", "heights_file", "trees", "trees_file"}},
      {"$.tree_scars[].trees[]", {"x", "y", "radius", "heights", "heights_file"}},
  };
  kind.error_keys = {"height"};
  kind.residual_kinds = {ObservationKind::kTreeScars};
  kind.observation_text = Text;
  kind.parse_text = ParseText;
  kind.read = Read;
  kind.read_error = ReadError;
  kind.missing_error = MissingError;
  kind.record = Record;
  kind.misfit = AddResiduals;
  kind.fold = DealFolds;
  kind.subset = KeepFold;
  return kind;
}

}  // namespace kinds
}  // namespace rockcal::observations
