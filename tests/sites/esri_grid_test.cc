#include "rockcal/sites/esri_grid.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

double Plane(double x, double y) { return 0.5 * x + 0.25 * y + 100.0; }

// An ESRI grid of Plane() with cells of `cell`, lower-left centre (xc, yc).
std::string PlaneGrid(int ncols, int nrows, double xc, double yc, double cell) {
  std::ostringstream s;
  s.precision(17);
  s << "ncols " << ncols << "\nnrows " << nrows << "\nxllcorner " << xc - cell / 2 << "\nYLLCORNER "
    << yc - cell / 2 << "\ncellsize " << cell << "\n";
  for (int r = 0; r < nrows; ++r) {
    const int j = nrows - 1 - r;  // rows run north to south
    for (int i = 0; i < ncols; ++i) s << (i ? " " : "") << Plane(xc + i * cell, yc + j * cell);
    s << "\n";
  }
  return s.str();
}

TEST(ReadEsriGrid, HeaderRowsAndNodata) {
  TempDir dir;
  const std::string path = dir.Write("g.asc",
                                     "ncols 3\nnrows 2\nxllcenter 10\nyllcenter 20\ncellsize 5\n"
                                     "NODATA_value -9999\n"
                                     "1 2 3\n"
                                     "4 -9999 6\n");
  const RasterGrid g = ReadEsriGrid(path);
  EXPECT_EQ(g.ncols, 3);
  EXPECT_EQ(g.nrows, 2);
  EXPECT_EQ(g.x_center, 10);
  EXPECT_EQ(g.y_center, 20);
  // Row 0 of the file is the north row (j = 1).
  EXPECT_EQ(g.at(0, 1), 1);
  EXPECT_EQ(g.at(2, 1), 3);
  EXPECT_EQ(g.at(0, 0), 4);
  EXPECT_TRUE(std::isnan(g.at(1, 0)));
  const core::HeightGrid h = RasterToHeightGrid(g, 1.0, 5.0);
  EXPECT_EQ(h.nx, 3);
  EXPECT_EQ(h.x0, 10);
  EXPECT_EQ(h.y0, 20);
  EXPECT_EQ(h.z[h.index(2, 1)], 3);
  EXPECT_TRUE(std::isnan(h.z[h.index(1, 0)]));
}

TEST(ReadEsriGrid, CornerIsHalfACellFromTheCentre) {
  TempDir dir;
  const std::string path =
      dir.Write("g.asc", "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 100\ncellsize 2\n1 2\n3 4\n");
  const RasterGrid g = ReadEsriGrid(path);
  EXPECT_EQ(g.x_center, 1);
  EXPECT_EQ(g.y_center, 101);
  EXPECT_FALSE(g.nodata.has_value());
}

TEST(ReadEsriGrid, ErrorsNameFileAndLine) {
  TempDir dir;
  struct Case {
    const char* text;
    const char* expected;
  };
  const std::string head = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  for (const Case& c : {
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5\n",
                ":7: row 2 has 2 values, expected ncols = 3"},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 x 6\n",
                ":7: value 2 'x' is not a finite number"},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n",
                ":6: file ends after 1 rows, expected nrows = 2"},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n7 8 9\n",
                ":8: more rows than nrows = 2"},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ndx 1\n",
                ":5: unknown header key 'dx' (allowed: "},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\nfoo' 1\n",
                ":5: unknown header key 'foo\\x27' (allowed: "},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\n1 2 3\n", ": header lacks 'cellsize'"},
           Case{"ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n",
                ": header 'ncols' = 2.5: expected a whole number >= 2"},
           Case{"ncols 3\nnrows 2\nxllcorner 0\nxllcenter 0\n",
                ":4: header key 'xllcenter' given twice"},
       }) {
    const std::string path = dir.Write("bad.asc", c.text);
    EXPECT_THAT(ErrorOf([&] { ReadEsriGrid(path); }), HasSubstr(path + c.expected)) << c.text;
  }
}

TEST(RasterToHeightGrid, ConvertsUnitsAndResamplesBilinearly) {
  TempDir dir;
  const std::string path = dir.Write("g.asc", PlaneGrid(11, 6, 0.0, 0.0, 4.0));
  const RasterGrid esri = ReadEsriGrid(path);
  // Same spacing, feet to metres: nodes are the cell centres, every value scaled.
  const core::HeightGrid ft = RasterToHeightGrid(esri, 0.3048, 4.0 * 0.3048);
  EXPECT_EQ(ft.nx, 11);
  EXPECT_EQ(ft.ny, 6);
  EXPECT_DOUBLE_EQ(ft.z[ft.index(3, 2)], 0.3048 * Plane(12, 8));
  // Half the spacing: twice the nodes, bilinear interpolation of a plane is exact.
  const core::HeightGrid fine = RasterToHeightGrid(esri, 1.0, 2.0);
  EXPECT_EQ(fine.nx, 21);
  EXPECT_EQ(fine.ny, 11);
  for (int j = 0; j < fine.ny; ++j)
    for (int i = 0; i < fine.nx; ++i)
      EXPECT_NEAR(fine.z[fine.index(i, j)], Plane(fine.x(i), fine.y(j)), 1e-9);
}

TEST(RasterToHeightGrid, ResampledNodeNextToNodataIsAHoleOnlyIfItUsesIt) {
  TempDir dir;
  const std::string path =
      dir.Write("g.asc",
                "ncols 3\nnrows 2\nxllcenter 0\nyllcenter 0\ncellsize 2\nnodata_value -1\n"
                "1 1 1\n1 1 -1\n");
  const core::HeightGrid g = RasterToHeightGrid(ReadEsriGrid(path), 1.0, 1.0);
  ASSERT_EQ(g.nx, 5);
  EXPECT_EQ(g.z[g.index(2, 0)], 1.0);           // on the centre (1, 0), weight 0 for (2, 0)
  EXPECT_TRUE(std::isnan(g.z[g.index(3, 0)]));  // between (1, 0) and the NODATA (2, 0)
  EXPECT_TRUE(std::isnan(g.z[g.index(4, 0)]));
  EXPECT_EQ(g.z[g.index(4, 2)], 1.0);
}

}  // namespace
}  // namespace rockcal::sites
