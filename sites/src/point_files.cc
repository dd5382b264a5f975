#include "rockcal/sites/point_files.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "rockcal/core/numbers.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::sites {
namespace {

using core::kPi;

// Number of columns named by a LIDAR column line (3 or 6), or 0 if the line
// is not one.
std::size_t LidarColumns(const std::string& line) {
  const std::vector<std::string> f = SplitFields(line);
  static const char* const kNames[] = {"x", "y", "z", "r", "g", "b"};
  if (f.size() != 3 && f.size() != 6) return 0;
  for (std::size_t k = 0; k < f.size(); ++k)
    if (Lower(f[k]) != kNames[k]) return 0;
  return f.size();
}

}  // namespace

std::vector<Eigen::Vector3d> ReadPointsFile(const std::string& path) {
  LineReader reader(path);
  std::vector<Eigen::Vector3d> points;
  std::string line;
  bool first = true;
  while (reader.Next(&line)) {
    if (IsBlank(line)) continue;
    const std::vector<std::string> fields = SplitFields(line);
    if (first) {
      first = false;
      // The first line is a header when none of its fields is a number.
      bool any_number = false;
      double v = 0.0;
      for (const std::string& f : fields) any_number = any_number || ParseNumber(f, &v);
      if (!any_number) continue;
    }
    if (fields.size() != 3) {
      reader.Fail("expected 3 values 'x y z' (blank or comma separated), found " +
                  std::to_string(fields.size()) + " in " + Excerpt(line));
    }
    const std::vector<double> v = reader.Numbers(fields);
    points.emplace_back(v[0], v[1], v[2]);
  }
  if (points.empty()) throw InputError(path, "no points (expected lines 'x y z')");
  return points;
}

std::vector<Eigen::Vector3d> ReadLidarFile(const std::string& path) {
  LineReader reader(path);
  std::string line;
  std::size_t columns = 0;
  while (columns == 0 && reader.Next(&line)) columns = LidarColumns(line);
  if (columns == 0) {
    throw InputError(path,
                     "no column line found (expected a line 'X Y Z' or 'X Y Z R G B' "
                     "before the data rows)");
  }
  const int header_line = reader.line();
  std::vector<Eigen::Vector3d> points;
  while (reader.Next(&line)) {
    if (IsBlank(line)) continue;
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != columns) {
      reader.Fail("expected " + std::to_string(columns) + " values (columns " +
                  (columns == 3 ? "X Y Z" : "X Y Z R G B") + " named at line " +
                  std::to_string(header_line) + "), found " + std::to_string(fields.size()) +
                  " in " + Excerpt(line));
    }
    const std::vector<double> v = reader.Numbers(fields);
    // Colours are 8-bit channels: whole numbers from 0 to 255.
    for (std::size_t k = 3; k < v.size(); ++k)
      if (!(v[k] >= 0 && v[k] <= 255 && v[k] == std::floor(v[k])))
        reader.Fail(std::string("colour ") + "RGB"[k - 3] + " is " + Excerpt(fields[k]) +
                    "; expected a whole number from 0 to 255");
    points.emplace_back(v[0], v[1], v[2]);
  }
  if (points.empty()) {
    throw InputError(path, "no data rows after the column line " + std::to_string(header_line));
  }
  return points;
}

Eigen::Vector3d ApplyLidarTransform(const LidarTransform& transform,
                                    std::vector<Eigen::Vector3d>* points) {
  Eigen::Vector3d offset = transform.offset;
  if (transform.auto_offset) {
    offset = Eigen::Vector3d(std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::infinity(), 0.0);
    for (const Eigen::Vector3d& p : *points) {
      offset.x() = std::min(offset.x(), p.x());
      offset.y() = std::min(offset.y(), p.y());
    }
    if (points->empty()) offset.setZero();
  }
  const double a = transform.spin_deg * kPi / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  for (Eigen::Vector3d& p : *points) {
    const Eigen::Vector3d q = p - offset;
    p = Eigen::Vector3d(c * q.x() - s * q.y(), s * q.x() + c * q.y(), q.z());
  }
  return offset;
}

}  // namespace rockcal::sites
