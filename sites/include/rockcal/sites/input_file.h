// What every reader of an input file checks before opening it: the path
// names a regular file. Opening a FIFO blocks until a writer comes (for
// ever), a device may never end (/dev/zero) and a folder is not a file, so
// each is refused by its kind, without opening it.
#ifndef ROCKCAL_SITES_INPUT_FILE_H_
#define ROCKCAL_SITES_INPUT_FILE_H_

#include <string>

namespace rockcal::sites {

// Throws InputError naming `path` when it exists and is not a regular file
// (after links): "is a folder, expected a file", "is a FIFO (named pipe),
// expected a regular file", a socket, a character or block device. A path
// that does not exist is left to the reader ("cannot open file").
void CheckInputFile(const std::string& path);

// Why `path` cannot be read as an input file (`what`: "CSV file"), as a
// sentence naming it, for a reader that reports at a JSON path: empty when
// it is a regular file it may open; "'P' is a folder, expected a file" and
// the other kinds as CheckInputFile names them; "cannot open CSV file 'P':
// " and the system's reason (no such file, too many levels of symbolic
// links, permission denied).
std::string InputFileProblem(const std::string& path, const std::string& what);

// The deepest nesting of arrays and objects a JSON input may have. The
// deepest file rockcal reads nests 6 levels (a site's zone polygons); a
// deeper one is refused before it is parsed, naming the depth.
inline constexpr int kMaxJsonDepth = 64;

// The nesting depth of the JSON text `text` (brackets in strings skipped); 0
// for a scalar. Linear, without recursion: safe on any text.
int JsonDepth(const std::string& text);

// Throws InputError at `where` naming the depth when `text` nests deeper than
// kMaxJsonDepth.
void CheckJsonDepth(const std::string& text, const std::string& where);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_INPUT_FILE_H_
