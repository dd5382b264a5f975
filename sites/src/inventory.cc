#include "rockcal/sites/inventory.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <functional>

#include "rockcal/core/limits.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::sites {
namespace {

constexpr double kPoundMass = 0.45359237;  // kg
constexpr double kMaxMass = 1e8;           // kg: a 40 000 m^3 block
constexpr double kMaxSide = core::kMaxRockSize;  // m

bool Comment(const std::string& line) {
  const auto first = line.find_first_not_of(" \t");
  return first != std::string::npos && line[first] == '#';
}

}  // namespace

std::vector<core::Block> ReadInventory(const std::string& path, Units units,
                                       std::vector<std::string>* shape_files) {
  LineReader in(path);
  std::string line;
  // The header: the first row that is neither blank nor a comment.
  std::vector<std::string> header;
  while (in.Next(&line)) {
    if (IsBlank(line) || Comment(line)) continue;
    header = SplitFields(line);
    break;
  }
  if (header.empty()) in.Fail("no header row (expected columns mass, L1, L2, L3 [, shape])");
  const std::array<const char*, 4> required = {"mass", "l1", "l2", "l3"};
  std::array<int, 4> column{-1, -1, -1, -1};
  int shape_column = -1;
  for (std::size_t k = 0; k < header.size(); ++k) {
    const std::string name = Lower(header[k]);
    bool known = name == "shape";
    if (known) shape_column = static_cast<int>(k);
    for (std::size_t r = 0; r < required.size(); ++r) {
      if (name == required[r]) {
        column[r] = static_cast<int>(k);
        known = true;
      }
    }
    if (!known) {
      in.Fail("unknown column '" + header[k].substr(0, 40) +
              "' (expected the columns mass, L1, L2, L3 and optionally shape)");
    }
  }
  const std::array<const char*, 4> names = {"mass", "L1", "L2", "L3"};
  for (std::size_t r = 0; r < required.size(); ++r) {
    if (column[r] < 0)
      in.Fail(std::string("missing column '") + names[r] +
              "' (expected the columns mass, L1, L2, L3 and optionally shape)");
  }
  const double length = LengthToSI(1.0, units);
  const double mass_unit = units == Units::kSI ? 1.0 : kPoundMass;
  std::vector<core::Block> blocks;
  while (in.Next(&line)) {
    if (IsBlank(line) || Comment(line)) continue;
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != header.size()) {
      in.Fail(std::to_string(fields.size()) + " fields; expected " + std::to_string(header.size()) +
              " as in the header");
    }
    std::vector<std::string> numeric;
    for (int c : column) numeric.push_back(fields[static_cast<std::size_t>(c)]);
    const std::vector<double> v = in.Numbers(numeric);
    core::Block b;
    b.mass = v[0] * mass_unit;
    if (!(b.mass > 0 && b.mass <= kMaxMass)) {
      in.Fail("mass " + numeric[0].substr(0, 40) + ": expected a mass > 0 and at most " +
              std::to_string(static_cast<long>(kMaxMass / mass_unit)) +
              (units == Units::kSI ? " kg" : " lb"));
    }
    std::array<double, 3> sides = {v[1] * length, v[2] * length, v[3] * length};
    for (std::size_t k = 0; k < 3; ++k) {
      if (!(sides[k] > 0 && sides[k] <= kMaxSide)) {
        in.Fail("L" + std::to_string(k + 1) + " " + numeric[k + 1].substr(0, 40) +
                ": expected a side > 0 and at most " + FormatNumber(kMaxSide / length) + " " +
                LengthUnit(units));
      }
    }
    std::sort(sides.begin(), sides.end(), std::greater<double>());
    b.sides = Eigen::Vector3d(sides[0], sides[1], sides[2]);
    std::string file;
    if (shape_column >= 0) {
      const std::string& field = fields[static_cast<std::size_t>(shape_column)];
      const std::string name = Lower(field);
      const bool is_file = field.find_first_of("./") != std::string::npos;
      if (is_file && shape_files) {
        b.shape = core::Shape::kScanned;
        file = field;
      } else if (!core::StringToShape(name, &b.shape)) {
        in.Fail("shape '" + name.substr(0, 40) + "': expected one of " + core::ShapeNames() +
                (shape_files ? " or a shape file (a name with an extension, e.g. SP1A.xyz)" : ""));
      }
    }
    if (shape_files) shape_files->push_back(file);
    blocks.push_back(b);
  }
  if (blocks.empty()) in.Fail("no blocks after the header (expected one block per row)");
  return blocks;
}

}  // namespace rockcal::sites
