#include "rockcal/sites/json_reader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "rockcal/core/limits.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/text_reader.h"

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

// The JSON path of the value being parsed, kept from nlohmann's parser
// events, so that a duplicate key or an out-of-range number can be named.
class PathTracker final {
 public:
  explicit PathTracker(std::string file) : file_(std::move(file)) {}

  bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
        NextElement();
        frames_.push_back(Frame{true, -1, "", {}});
        break;
      case Event::array_start:
        NextElement();
        frames_.push_back(Frame{false, -1, "", {}});
        break;
      case Event::key: {
        Frame& f = frames_.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second)
          throw InputError(file_ + ": " + Path(),
                           "duplicate key '" + f.key + "' (expected each key once in an object)");
        break;
      }
      case Event::value:
        NextElement();
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        break;
    }
    return true;
  }

  // The path of the current value ("$" outside any container).
  std::string Path() const {
    std::string path = "$";
    for (const Frame& f : frames_)
      path += f.object ? "." + f.key : "[" + std::to_string(std::max(f.index, 0)) + "]";
    return path;
  }
  // The path of the value after the current one (where a parse stopped).
  std::string NextPath() const {
    if (frames_.empty() || frames_.back().object) return Path();
    PathTracker next = *this;
    next.NextElement();
    return next.Path();
  }

 private:
  struct Frame {
    bool object;
    int index;
    std::string key;
    std::set<std::string> keys;
  };
  void NextElement() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }

  std::string file_;
  std::vector<Frame> frames_;
};

}  // namespace

nlohmann::json ReadJsonFile(const std::string& path) {
  CheckInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open file: ") + std::strerror(errno));
  // The largest JSON file read: a site or observation file is far smaller.
  constexpr std::size_t kMaxJsonBytes = std::size_t{1} << 28;
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxJsonBytes)
      throw InputError(path, "larger than " + std::to_string(kMaxJsonBytes) +
                                 " bytes (expected a JSON site or observation file)");
  }
  CheckJsonDepth(text, path);
  PathTracker tracker(path);
  try {
    return nlohmann::json::parse(text, std::ref(tracker));
  } catch (const nlohmann::json::parse_error& e) {
    int line = 0, col = 0;
    LineColumn(text, e.byte > 0 ? e.byte - 1 : 0, &line, &col);
    throw InputError(path + ":" + std::to_string(line) + ":" + std::to_string(col),
                     "invalid JSON (expected a well-formed JSON document)");
  } catch (const nlohmann::json::out_of_range& e) {
    // nlohmann's number overflow (e.g. 1e400): the value after the last one
    // parsed; its text is quoted in nlohmann's message.
    const std::string said = e.what();
    const std::size_t open = said.find('\''), close = said.rfind('\'');
    const std::string value =
        open != std::string::npos && close > open ? said.substr(open + 1, close - open - 1) : "";
    throw InputError(path + ": " + tracker.NextPath(),
                     "number " + (value.empty() ? std::string() : Excerpt(value) + " ") +
                         "out of range (expected a finite number, at most about 1.8e308)");
  }
}

JsonNode::JsonNode(const nlohmann::json* value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {}

std::string JsonNode::where() const { return file_ + ": " + path_; }

void JsonNode::Fail(const std::string& what) const {
  throw InputError(where(), what + " (found " + Shorten(*value_) + ")");
}

void JsonNode::Keys(std::initializer_list<const char*> allowed) const {
  Keys(std::vector<const char*>(allowed));
}

void JsonNode::Keys(const std::vector<const char*>& allowed) const {
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

namespace {

// The first control character (U+0000 to U+001F, U+007F) of `text` that
// `allowed` does not list, or npos.
std::size_t ControlCharacter(const std::string& text, const char* allowed) {
  for (std::size_t k = 0; k < text.size(); ++k) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if ((c < 0x20 || c == 0x7f) && (c == 0 || !std::strchr(allowed, c))) return k;
  }
  return std::string::npos;
}

}  // namespace

std::string JsonNode::String() const { return StringAllowing(""); }

std::string JsonNode::Text() const { return StringAllowing("\t\n\r"); }

std::string JsonNode::StringAllowing(const char* allowed) const {
  if (!value_->is_string()) Fail("expected a string");
  std::string text = value_->get<std::string>();
  const std::size_t at = ControlCharacter(text, allowed);
  if (at != std::string::npos) {
    char code[8];
    std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned char>(text[at]));
    Fail(std::string("holds the control character ") + code + " at character " +
         std::to_string(at + 1) +
         "; expected printable text (names, ids and file names hold no control characters)");
  }
  return text;
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

double NumberInRange(const JsonNode& node, double value, double lo, double hi, const char* what,
                     Quantity kind, Units units, const char* why) {
  if (value >= lo && value <= hi) return value;
  double scale = 1.0;  // SI -> the file's units
  std::string unit;
  switch (kind) {
    case Quantity::kLength:
      scale = 1.0 / LengthToSI(1.0, units);
      unit = LengthUnit(units);
      break;
    case Quantity::kSpeed:
      scale = 1.0 / LengthToSI(1.0, units);
      unit = std::string(LengthUnit(units)) + "/s";
      break;
    case Quantity::kUnitWeight:
      scale = 1.0 / UnitWeightToSI(1.0, units);
      unit = units == Units::kUS ? "lbf/ft^3" : "kN/m^3";
      break;
    case Quantity::kTime:
      unit = "s";
      break;
    case Quantity::kStress:
      scale = 1.0 / StressToSI(1.0, units);
      unit = StressUnit(units);
      break;
  }
  node.Fail(std::string(what) + " " + FormatNumber(value * scale) + " " + unit +
            " is outside the physically sensible range; expected [" + FormatNumber(lo * scale) +
            ", " + FormatNumber(hi * scale) + "] " + unit + (why ? std::string(" ") + why : ""));
}

double CoordinateToSI(const JsonNode& node, Units units) {
  return NumberInRange(node, LengthToSI(node.Number(), units), -core::kMaxCoordinate,
                       core::kMaxCoordinate, "coordinate", Quantity::kLength, units);
}

std::vector<double> CoordinatesToSI(const JsonNode& node, std::size_t n, Units units) {
  if (!node.is_array() || node.raw().size() != n)
    node.Fail("expected an array of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (const JsonNode& e : node.Array()) out.push_back(CoordinateToSI(e, units));
  return out;
}

double StressToSI(double value, Units units) {
  // 1 lbf/ft^2 = 4.4482216152605 N / 0.09290304 m^2 = 47.88025898 Pa.
  return units == Units::kUS ? value * 4.4482216152605 / 0.09290304 : value * 1000.0;
}

const char* StressUnit(Units units) { return units == Units::kUS ? "lbf/ft^2" : "kPa"; }

std::string LengthText(double metres, Units units, const char* format) {
  return FormatNumber(metres / LengthToSI(1.0, units), format) + " " + LengthUnit(units);
}

std::string MassText(double kg, Units units, const char* format) {
  // 1 lb = 0.45359237 kg.
  return units == Units::kUS ? FormatNumber(kg / 0.45359237, format) + " lb"
                             : FormatNumber(kg, format) + " kg";
}

std::string UnitWeightText(double n_per_m3, Units units) {
  return FormatNumber(n_per_m3 / UnitWeightToSI(1.0, units)) +
         (units == Units::kUS ? " lbf/ft^3" : " kN/m^3");
}

const char* FieldUnitText(core::FieldUnit unit, Units units) {
  switch (unit) {
    case core::FieldUnit::kLength:
      return LengthUnit(units);
    case core::FieldUnit::kStress:
      return StressUnit(units);
    case core::FieldUnit::kTime:
      return "s";
    case core::FieldUnit::kNone:
      break;
  }
  return "";
}

double FieldToSI(double value, core::FieldUnit unit, Units units) {
  switch (unit) {
    case core::FieldUnit::kLength:
      return LengthToSI(value, units);
    case core::FieldUnit::kStress:
      return StressToSI(value, units);
    case core::FieldUnit::kNone:
    case core::FieldUnit::kTime:
      break;
  }
  return value;
}

double UnitWeightToSI(double value, Units units) {
  // 1 lbf/ft^3 = 4.4482216152605 N / 0.028316846592 m^3 = 157.0874606 N/m^3.
  return units == Units::kUS ? value * 4.4482216152605 / 0.028316846592 : value * 1000.0;
}

}  // namespace rockcal::sites
