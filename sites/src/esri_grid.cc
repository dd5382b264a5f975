#include "rockcal/sites/esri_grid.h"

#include <cctype>
#include <cmath>

#include "rockcal/sites/json_reader.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::sites {
namespace {

constexpr long kMaxCells = 100'000'000;

bool StartsWithLetter(const std::string& line) {
  for (char c : line) {
    if (c == ' ' || c == '\t') continue;
    return std::isalpha(static_cast<unsigned char>(c)) != 0;
  }
  return false;
}

}  // namespace

RasterGrid ReadEsriGrid(const std::string& path) {
  LineReader reader(path);
  std::optional<double> ncols, nrows, cellsize, nodata;
  std::optional<double> xll, yll;
  bool x_corner = false, y_corner = false;
  std::string line;
  bool have_data_line = false;
  while (reader.Next(&line)) {
    if (IsBlank(line)) continue;
    if (!StartsWithLetter(line)) {
      have_data_line = true;
      break;
    }
    const std::vector<std::string> f = SplitFields(line);
    if (f.size() != 2) reader.Fail("expected a header line 'key value', found " + Excerpt(line));
    const std::string key = Lower(f[0]);
    double v = 0.0;
    if (!ParseNumber(f[1], &v))
      reader.Fail("header " + Excerpt(f[0]) + ": " + Excerpt(f[1]) + " is not a number");
    std::optional<double>* slot = nullptr;
    if (key == "ncols") {
      slot = &ncols;
    } else if (key == "nrows") {
      slot = &nrows;
    } else if (key == "cellsize") {
      slot = &cellsize;
    } else if (key == "nodata_value") {
      slot = &nodata;
    } else if (key == "xllcorner" || key == "xllcenter") {
      slot = &xll;
      x_corner = key == "xllcorner";
    } else if (key == "yllcorner" || key == "yllcenter") {
      slot = &yll;
      y_corner = key == "yllcorner";
    } else {
      reader.Fail("unknown header key " + Excerpt(f[0]) +
                  " (allowed: ncols, nrows, xllcorner, xllcenter, yllcorner, yllcenter, "
                  "cellsize, NODATA_value)");
    }
    if (slot->has_value())
      reader.Fail("header key " + Excerpt(f[0]) + " given twice (or both corner and center)");
    *slot = v;
  }
  const char* missing = !ncols      ? "ncols"
                        : !nrows    ? "nrows"
                        : !xll      ? "xllcorner or xllcenter"
                        : !yll      ? "yllcorner or yllcenter"
                        : !cellsize ? "cellsize"
                                    : nullptr;
  if (missing) throw InputError(path, std::string("header lacks '") + missing + "'");
  auto count = [&](double v, const char* name) {
    if (!(v >= 2 && v <= kMaxCells && v == std::floor(v))) {
      throw InputError(path, std::string("header '") + name + "' = " + FormatNumber(v) +
                                 ": expected a whole number >= 2");
    }
    return static_cast<int>(v);
  };
  RasterGrid g;
  g.ncols = count(*ncols, "ncols");
  g.nrows = count(*nrows, "nrows");
  if (static_cast<long>(g.ncols) * g.nrows > kMaxCells)
    throw InputError(path, "grid of " + std::to_string(g.ncols) + " x " + std::to_string(g.nrows) +
                               " cells is too large (limit 1e8 cells)");
  if (!(*cellsize > 0)) throw InputError(path, "header 'cellsize' must be > 0");
  g.cellsize = *cellsize;
  g.x_center = *xll + (x_corner ? 0.5 * g.cellsize : 0.0);
  g.y_center = *yll + (y_corner ? 0.5 * g.cellsize : 0.0);
  g.nodata = nodata;
  g.values.reserve(static_cast<std::size_t>(g.ncols) * g.nrows);
  int rows = 0;
  while (have_data_line) {
    if (!IsBlank(line)) {
      const std::vector<std::string> f = SplitFields(line);
      if (rows == g.nrows) {
        reader.Fail("more rows than nrows = " + std::to_string(g.nrows) + " declared");
      }
      if (f.size() != static_cast<std::size_t>(g.ncols)) {
        reader.Fail("row " + std::to_string(rows + 1) + " has " + std::to_string(f.size()) +
                    " values, expected ncols = " + std::to_string(g.ncols));
      }
      const std::vector<double> v = reader.Numbers(f);
      g.values.insert(g.values.end(), v.begin(), v.end());
      ++rows;
    }
    have_data_line = reader.Next(&line);
  }
  if (rows != g.nrows) {
    throw InputError(reader.where(), "file ends after " + std::to_string(rows) +
                                         " rows, expected nrows = " + std::to_string(g.nrows));
  }
  return g;
}

}  // namespace rockcal::sites
