#include "rockcal/sites/point_files.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "test_files.h"

namespace rockcal::sites {
namespace {

using testing::ErrorOf;
using ::testing::HasSubstr;
using testing::TempDir;

TEST(ReadPointsFile, CsvWithHeader) {
  TempDir dir;
  const std::string path = dir.Write("p.csv", "x,y,z\n0,0,1\n\n10, 0, 2.5\r\n0,10,-3e1\n");
  const std::vector<Eigen::Vector3d> p = ReadPointsFile(path);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[1], Eigen::Vector3d(10, 0, 2.5));
  EXPECT_EQ(p[2], Eigen::Vector3d(0, 10, -30));
}

TEST(ReadPointsFile, BlankSeparatedWithoutHeader) {
  TempDir dir;
  const std::string path = dir.Write("p.txt", "1 2 3\n4\t5 6\n");
  const std::vector<Eigen::Vector3d> p = ReadPointsFile(path);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0], Eigen::Vector3d(1, 2, 3));
}

TEST(ReadPointsFile, HeaderOnlyOnTheFirstLine) {
  TempDir dir;
  const std::string path = dir.Write("p.csv", "x,y,z\n0,0,1\nx,y,z\n");
  EXPECT_THAT(ErrorOf([&] { ReadPointsFile(path); }),
              HasSubstr(path + ":3: value 1 'x' is not a finite number"));
}

TEST(ReadPointsFile, BadRowsNameFileAndLine) {
  TempDir dir;
  struct Case {
    const char* text;
    const char* expected;
  };
  for (const Case& c :
       {Case{"0 0 0\n1 2\n", ":2: expected 3 values"},
        Case{"0 0 0\n1 2 3 4\n", ":2: expected 3 values"},
        Case{"0 0 0\n1,,3\n", ":2: value 2 is missing"},
        Case{"0 0 0\n0 0 0\n1 2 NaN\n", ":3: value 3 'NaN' is not a finite number"},
        Case{"0 0 0\n1 2 inf\n", ":2: value 3 'inf'"}, Case{"1 2\n", ":1: expected 3 values"}}) {
    const std::string path = dir.Write("bad.txt", c.text);
    EXPECT_THAT(ErrorOf([&] { ReadPointsFile(path); }), HasSubstr(path + c.expected)) << c.text;
  }
  const std::string empty = dir.Write("empty.txt", "x y z\n\n");
  EXPECT_THAT(ErrorOf([&] { ReadPointsFile(empty); }), HasSubstr(empty + ": no points"));
}

TEST(ReadLidarFile, XyzWithHeaderLines) {
  TempDir dir;
  const std::string path = dir.Write("scan.txt",
                                     "Exported by scanner v2\n"
                                     "points: 2 1 3\n"
                                     "x y Z\n"
                                     "100.5 200.25 30\n"
                                     "101 201 31\n");
  const std::vector<Eigen::Vector3d> p = ReadLidarFile(path);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0], Eigen::Vector3d(100.5, 200.25, 30));
}

TEST(ReadLidarFile, XyzrgbDropsColours) {
  TempDir dir;
  const std::string path = dir.Write("scan.txt", "X,Y,Z,R,G,B\n1,2,3,255,0,10\n4,5,6,1,2,3\n");
  const std::vector<Eigen::Vector3d> p = ReadLidarFile(path);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1], Eigen::Vector3d(4, 5, 6));
}

TEST(ReadLidarFile, BadRowsAreErrorsNeverDropped) {
  TempDir dir;
  struct Case {
    const char* text;
    const char* expected;
  };
  for (const Case& c : {Case{"head\nX Y Z\n1 2 3\n1 2\n", ":4: expected 3 values"},
                        Case{"X Y Z R G B\n1 2 3 4 5 6\n1 2 3\n", ":3: expected 6 values"},
                        Case{"X Y Z\n1 2 3\n1 b 3\n", ":3: value 2 'b' is not a finite number"},
                        Case{"X Y Z\n1 2 nan\n", ":2: value 3 'nan'"},
                        Case{"X Y Z\n1 2 -inf\n", ":2: value 3 '-inf'"}}) {
    const std::string path = dir.Write("bad.txt", c.text);
    EXPECT_THAT(ErrorOf([&] { ReadLidarFile(path); }), HasSubstr(path + c.expected)) << c.text;
  }
}

TEST(ReadLidarFile, NeedsTheColumnLine) {
  TempDir dir;
  const std::string path = dir.Write("scan.txt", "1 2 3\n4 5 6\n");
  EXPECT_THAT(ErrorOf([&] { ReadLidarFile(path); }),
              HasSubstr(path + ": no column line found (expected a line 'X Y Z' or 'X Y Z R G B'"));
  const std::string none = dir.Write("none.txt", "X Y Z\n");
  EXPECT_THAT(ErrorOf([&] { ReadLidarFile(none); }), HasSubstr("no data rows"));
}

TEST(ApplyLidarTransform, OffsetThenSpin) {
  std::vector<Eigen::Vector3d> p = {{11, 20, 5}, {10, 21, 6}};
  LidarTransform t;
  t.offset = Eigen::Vector3d(10, 20, 1);
  t.spin_deg = 90;
  ApplyLidarTransform(t, &p);
  EXPECT_NEAR((p[0] - Eigen::Vector3d(0, 1, 4)).norm(), 0, 1e-12) << p[0].transpose();
  EXPECT_NEAR((p[1] - Eigen::Vector3d(-1, 0, 5)).norm(), 0, 1e-12) << p[1].transpose();
}

TEST(ApplyLidarTransform, AutoOffsetKeepsElevations) {
  std::vector<Eigen::Vector3d> p = {{1000, 5000, 300}, {1010, 5020, 250}};
  LidarTransform t;
  t.auto_offset = true;
  const Eigen::Vector3d offset = ApplyLidarTransform(t, &p);
  EXPECT_EQ(offset, Eigen::Vector3d(1000, 5000, 0));
  EXPECT_EQ(p[0], Eigen::Vector3d(0, 0, 300));
  EXPECT_EQ(p[1], Eigen::Vector3d(10, 20, 250));
}

}  // namespace
}  // namespace rockcal::sites
