// Line-by-line reading of the text data files a site refers to (point
// clouds, CRSP LIDAR text, ESRI ASCII grids, ASCII STL). Every error names the
// file and the line ("file:LINE: what"), and numbers are parsed strictly: a
// row with a letter, a missing value, NaN or infinity is an error, never a
// silently dropped value.
#ifndef ROCKCAL_SITES_TEXT_READER_H_
#define ROCKCAL_SITES_TEXT_READER_H_

#include <fstream>
#include <string>
#include <vector>

#include "rockcal/core/error.h"

namespace rockcal::sites {

// Parses `text` as one finite decimal number (optional sign, digits, point,
// exponent; surrounding blanks allowed). False for anything else, including
// "nan", "inf", hexadecimal and trailing characters.
bool ParseNumber(const std::string& text, double* value);

// Splits a data row into fields. A row holding a comma is split at commas
// (each field trimmed; an empty field is kept as ""); otherwise at runs of
// blanks (spaces, tabs), a field in double quotes being one field with its
// blanks (the quotes kept). A trailing '\r' is ignored.
std::vector<std::string> SplitFields(const std::string& line);

// True when the line holds only blanks.
bool IsBlank(const std::string& line);

// `text` in lower case (ASCII): keywords, column names and extensions are
// read case-insensitively.
std::string Lower(std::string text);

// "a, b, c": the names a message lists.
std::string Join(const std::vector<std::string>& items);

// At most kMaxExcerpt characters of `text` for a message, quoted, with
// non-printable bytes, the backslash and the quote escaped (\xNN: 'foo\x27'
// for foo', not 'foo'') and "..." when cut: a message never carries a whole
// line of another file, nor its control characters.
inline constexpr std::size_t kMaxExcerpt = 80;
std::string Excerpt(const std::string& text);

// The longest line a text data file may have (bytes); a longer one (e.g.
// /dev/zero or a binary file given as text) is an error at once.
inline constexpr std::size_t kMaxLineBytes = 1 << 20;

// Reads a text file one line at a time, counting lines from 1.
class LineReader final {
 public:
  // Throws InputError when the file cannot be opened.
  explicit LineReader(std::string path);

  // Reads the next line (without its end of line); false at the end.
  // Throws InputError "file:LINE: line longer than ..." past kMaxLineBytes.
  bool Next(std::string* line);
  const std::string& path() const { return path_; }
  int line() const { return line_; }
  // "file:LINE".
  std::string where() const;
  // Throws InputError("file:LINE", what).
  [[noreturn]] void Fail(const std::string& what) const;
  // Parses every field of `fields` as a number, failing at this line with a
  // message that names the bad field (its 1-based column and text).
  std::vector<double> Numbers(const std::vector<std::string>& fields) const;

 private:
  std::string path_;
  std::ifstream in_;
  int line_ = 0;
};

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_TEXT_READER_H_
