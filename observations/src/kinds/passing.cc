#include "passing.h"

#include "../compare.h"
#include "../reader.h"
#include "rockcal/core/error.h"
#include "rockcal/observations/file_keys.h"

namespace rockcal::observations::kinds {
namespace {

using sites::FormatNumber;
using sites::JsonNode;

// ---------------------------------------------------------------------------
// Reader

// The index in `out` of the entry for `partition`, or -1: one fraction per
// partition (two would both enter the misfit).
int EntryOf(const std::vector<Passing>& out, int partition) {
  for (std::size_t i = 0; i < out.size(); ++i)
    if (out[i].partition == partition) return static_cast<int>(i);
  return -1;
}

std::string GivenTwice(const Reader& reader, int partition, const std::string& first) {
  return "partition '" + reader.scene().partitions[static_cast<std::size_t>(partition)].id +
         "' is given twice (first " + first + "); expected each partition once";
}

// The "passing" array.
std::vector<Passing> ReadPassing(const Reader& reader, const JsonNode& node) {
  std::vector<Passing> out;
  for (const JsonNode& e : node.Array(1)) {
    e.Keys(ObservationsKeysAt("$.passing[]"));
    Passing p;
    p.partition = reader.FindPartition(e.Get("partition"));
    if (const int first = EntryOf(out, p.partition); first >= 0) {
      throw InputError(
          e.Get("partition").where(),
          GivenTwice(reader, p.partition, "at " + node.path() + "[" + std::to_string(first) + "]"));
    }
    p.fraction = e.Get("fraction").Number(0.0, 1.0);
    p.label = "passing[" + std::to_string(out.size()) + "] " +
              reader.scene().partitions[static_cast<std::size_t>(p.partition)].id;
    out.push_back(p);
  }
  return out;
}

// The "passing_file" CSV.
std::vector<Passing> ReadPassingFile(const Reader& reader, const JsonNode& ref) {
  const CsvTable table = reader.ReadCsv(ref, {"partition", "fraction"});
  std::vector<Passing> out;
  std::vector<int> lines;
  for (const CsvRow& row : table.rows) {
    Passing p;
    p.partition = reader.FindPartition(row.fields[0]);
    if (p.partition < 0) {
      CsvFail(table, row,
              "unknown partition id " + sites::Excerpt(row.fields[0]) + " (" +
                  reader.PartitionIds() + ")");
    }
    if (const int first = EntryOf(out, p.partition); first >= 0) {
      CsvFail(table, row,
              GivenTwice(reader, p.partition,
                         "on line " + std::to_string(lines[static_cast<std::size_t>(first)])));
    }
    lines.push_back(row.line);
    p.fraction = CsvNumber(table, row, 1, "fraction");
    if (p.fraction < 0 || p.fraction > 1) {
      CsvFail(table, row, "expected 'fraction' in [0, 1] (found " + row.fields[1] + ")");
    }
    p.label = "passing[" + std::to_string(out.size()) + "] " +
              reader.scene().partitions[static_cast<std::size_t>(p.partition)].id;
    out.push_back(p);
  }
  return out;
}

void Read(const Reader& reader, const JsonNode& root, Observations* obs) {
  if (root.Has("passing") && root.Has("passing_file")) {
    throw InputError(root.where(),
                     "keys 'passing' and 'passing_file' both given (expected at most one)");
  }
  if (const auto passing = root.Find("passing")) obs->passing = ReadPassing(reader, *passing);
  if (const auto passing = root.Find("passing_file"))
    obs->passing = ReadPassingFile(reader, *passing);
  for (const Passing& p : obs->passing) {
    obs->notes.push_back(p.label + ": fraction " + FormatNumber(p.fraction));
  }
}

void ReadError(const Reader&, const JsonNode& error, Observations* obs) {
  if (const auto p = error.Find("passing")) {
    obs->error.passing = p->Positive();
    if (obs->error.passing > 1) p->Fail("expected a fraction in (0, 1]");
  }
}

// ---------------------------------------------------------------------------
// Recording and misfit

void Record(const Observations& obs, core::RecordOptions*, bool* partitions) {
  if (!obs.passing.empty()) *partitions = true;
}

// Each fraction against the share of every released rock that crossed its
// partition.
void AddResiduals(const Observations& obs, const MisfitTerms& terms) {
  const core::SimulationResult& result = terms.result;
  const int released = static_cast<int>(result.rocks.size());
  for (std::size_t i = 0; i < obs.passing.size(); ++i) {
    const Passing& passing = obs.passing[i];
    terms.CheckPartition(passing.label, passing.partition);
    const std::size_t p = static_cast<std::size_t>(passing.partition);
    int crossed = 0;
    for (const core::RockRecord& rock : result.rocks) crossed += rock.crossings[p].crossed ? 1 : 0;
    terms.compare.Fraction(
        ResidualId::Of(ObservationKind::kPassing, static_cast<int>(i), passing.label), crossed,
        released, passing.fraction, obs.error.passing);
  }
}

std::string Text(const ResidualId& id) { return id.name; }

std::optional<ResidualId> ParseText(const std::string& text) {
  return IndexedText(ObservationKind::kPassing, "passing", text);
}

// Folds: the fractions are in no fold; they stay in every training set and
// leave every held-out one.
void KeepFold(const Observations&, const observations::Fold&, bool held_out, Observations* out) {
  if (held_out) out->passing.clear();
}

}  // namespace

Kind PassingKind() {
  Kind kind;
  kind.name = "passing";
  kind.root_keys = {"passing", "passing_file"};
  kind.objects = {{"$.passing[]", {"partition", "fraction"}}};
  kind.error_keys = {"passing"};
  kind.residual_kinds = {ObservationKind::kPassing};
  kind.observation_text = Text;
  kind.parse_text = ParseText;
  kind.read = Read;
  kind.read_error = ReadError;
  kind.record = Record;
  kind.misfit = AddResiduals;
  kind.subset = KeepFold;
  return kind;
}

}  // namespace rockcal::observations::kinds
