#include "rockcal/sites/text_reader.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "rockcal/sites/input_file.h"

namespace rockcal::sites {
namespace {

bool IsBlankChar(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string Trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && IsBlankChar(s[b])) ++b;
  while (e > b && IsBlankChar(s[e - 1])) --e;
  return s.substr(b, e - b);
}

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// True when `s` matches [+-]?(d+(.d*)?|.d+)([eE][+-]?d+)?
bool IsDecimal(const std::string& s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < s.size() && IsDigit(s[i])) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && IsDigit(s[i])) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t exp_digits = 0;
    while (i < s.size() && IsDigit(s[i])) ++i, ++exp_digits;
    if (exp_digits == 0) return false;
  }
  return i == s.size();
}

}  // namespace

bool ParseNumber(const std::string& text, double* value) {
  const std::string s = Trim(text);
  if (!IsDecimal(s)) return false;
  const double v = std::strtod(s.c_str(), nullptr);
  if (!std::isfinite(v)) return false;  // overflow, e.g. 1e999
  *value = v;
  return true;
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> out;
  if (line.find(',') != std::string::npos) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      out.push_back(
          Trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return out;
  }
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsBlankChar(line[i])) ++i;
    if (i == line.size()) break;
    std::size_t j = i;
    // A field in double quotes is one field, blanks and all (" 0.7 ").
    if (line[j] == '"') {
      const std::size_t close = line.find('"', j + 1);
      if (close != std::string::npos) j = close + 1;
    }
    while (j < line.size() && !IsBlankChar(line[j])) ++j;
    out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

std::string Excerpt(const std::string& text) {
  std::string out = "'";
  std::size_t shown = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (shown >= kMaxExcerpt) {
      out += "...";
      break;
    }
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f && c != '\\' && c != '\'') {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", c);
      out += hex;
    }
    ++shown;
  }
  return out + "'";
}

bool IsBlank(const std::string& line) {
  for (char c : line)
    if (!IsBlankChar(c)) return false;
  return true;
}

LineReader::LineReader(std::string path) : path_(std::move(path)) {
  CheckInputFile(path_);
  in_.open(path_, std::ios::binary);
  if (!in_) throw InputError(path_, std::string("cannot open file: ") + std::strerror(errno));
}

bool LineReader::Next(std::string* line) {
  line->clear();
  std::streambuf* buf = in_.rdbuf();
  int c = buf->sbumpc();
  if (c == std::char_traits<char>::eof()) return false;
  ++line_;
  for (; c != std::char_traits<char>::eof() && c != '\n'; c = buf->sbumpc()) {
    if (line->size() >= kMaxLineBytes)
      Fail("line " + std::to_string(line_) + " longer than " + std::to_string(kMaxLineBytes) +
           " bytes (expected a text data file)");
    line->push_back(static_cast<char>(c));
  }
  if (!line->empty() && line->back() == '\r') line->pop_back();
  return true;
}

std::string LineReader::where() const { return path_ + ":" + std::to_string(line_); }

void LineReader::Fail(const std::string& what) const { throw InputError(where(), what); }

std::vector<double> LineReader::Numbers(const std::vector<std::string>& fields) const {
  std::vector<double> out(fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    if (fields[k].empty()) Fail("value " + std::to_string(k + 1) + " is missing");
    if (!ParseNumber(fields[k], &out[k])) {
      Fail("value " + std::to_string(k + 1) + " " + Excerpt(fields[k]) + " is not a finite number");
    }
  }
  return out;
}

}  // namespace rockcal::sites
