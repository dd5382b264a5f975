#include "rockcal/sites/json_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace rockcal::sites {
namespace {

std::string Shorten(const nlohmann::json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

// Line and column of byte offset `pos` in `text`.
void LineColumn(const std::string& text, std::size_t pos, int* line, int* col) {
  *line = 1;
  *col = 1;
  for (std::size_t i = 0; i < pos && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++*line;
      *col = 1;
    } else {
      ++*col;
    }
  }
}

}  // namespace

nlohmann::json ReadJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    int line = 0, col = 0;
    LineColumn(text, e.byte > 0 ? e.byte - 1 : 0, &line, &col);
    throw InputError(path + ":" + std::to_string(line) + ":" + std::to_string(col),
                     "invalid JSON (expected a well-formed JSON document)");
  }
}

JsonNode::JsonNode(const nlohmann::json* value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {}

std::string JsonNode::where() const { return file_ + ": " + path_; }

void JsonNode::Fail(const std::string& what) const {
  throw InputError(where(), what + " (found " + Shorten(*value_) + ")");
}

void JsonNode::Keys(std::initializer_list<const char*> allowed) const {
  if (!value_->is_object()) Fail("expected an object");
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || it.key() == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      throw InputError(where() + "." + it.key(),
                       "unknown key '" + it.key() + "' (allowed keys: " + list + ")");
    }
  }
}

bool JsonNode::Has(const char* key) const {
  return value_->is_object() && value_->contains(key);
}

JsonNode JsonNode::Get(const char* key) const {
  if (!value_->is_object()) Fail("expected an object");
  auto it = value_->find(key);
  if (it == value_->end())
    throw InputError(where(), std::string("missing required key '") + key + "'");
  return JsonNode(&*it, file_, path_ + "." + key);
}

std::optional<JsonNode> JsonNode::Find(const char* key) const {
  if (!Has(key)) return std::nullopt;
  return Get(key);
}

double JsonNode::Number() const {
  if (!value_->is_number()) Fail("expected a number");
  const double v = value_->get<double>();
  if (!std::isfinite(v)) Fail("expected a finite number");
  return v;
}

double JsonNode::Number(double lo, double hi) const {
  const double v = Number();
  if (v < lo || v > hi) {
    std::ostringstream s;
    s << "expected a number in [" << lo << ", " << hi << "]";
    Fail(s.str());
  }
  return v;
}

double JsonNode::Positive() const {
  const double v = Number();
  if (!(v > 0)) Fail("expected a number > 0");
  return v;
}

double JsonNode::NonNegative() const {
  const double v = Number();
  if (v < 0) Fail("expected a number >= 0");
  return v;
}

long JsonNode::Integer(long lo, long hi) const {
  if (!value_->is_number_integer()) Fail("expected a whole number");
  const long v = value_->get<long>();
  if (v < lo || v > hi) {
    Fail("expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v;
}

std::string JsonNode::String() const {
  if (!value_->is_string()) Fail("expected a string");
  return value_->get<std::string>();
}

bool JsonNode::Bool() const {
  if (!value_->is_boolean()) Fail("expected true or false");
  return value_->get<bool>();
}

std::vector<JsonNode> JsonNode::Array(std::size_t min_size) const {
  if (!value_->is_array()) Fail("expected an array");
  if (value_->size() < min_size)
    Fail("expected an array of at least " + std::to_string(min_size) + " entries");
  std::vector<JsonNode> out;
  out.reserve(value_->size());
  for (std::size_t i = 0; i < value_->size(); ++i)
    out.emplace_back(&(*value_)[i], file_, path_ + "[" + std::to_string(i) + "]");
  return out;
}

std::vector<double> JsonNode::Numbers(std::size_t n) const {
  if (!value_->is_array() || value_->size() != n)
    Fail("expected an array of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (const JsonNode& e : Array()) out.push_back(e.Number());
  return out;
}

std::string FormatNumber(double value) {
  std::ostringstream s;
  s.precision(10);
  s << value;
  return s.str();
}

Units ReadUnits(const JsonNode& node) {
  const std::string u = node.String();
  if (u == "us") return Units::kUS;
  if (u == "si") return Units::kSI;
  node.Fail("unknown units (allowed: us, si)");
}

double LengthToSI(double value, Units units) {
  return units == Units::kUS ? value * 0.3048 : value;
}

const char* LengthUnit(Units units) { return units == Units::kUS ? "ft" : "m"; }

double UnitWeightToSI(double value, Units units) {
  // 1 lbf/ft^3 = 4.4482216152605 N / 0.028316846592 m^3 = 157.0874606 N/m^3.
  return units == Units::kUS ? value * 4.4482216152605 / 0.028316846592 : value * 1000.0;
}

}  // namespace rockcal::sites
