// Scattered x y z points from text files: plain point files (CSV or blank
// separated) and the two CRSP LIDAR text formats. Coordinates are returned in
// the file's own units; the caller converts them.
#ifndef ROCKCAL_SITES_POINT_FILES_H_
#define ROCKCAL_SITES_POINT_FILES_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace rockcal::sites {

// Reads a points file: one point "x y z" or "x,y,z" per line. The first
// non-blank line may be a header (a line none of whose fields is a number,
// e.g. "x,y,z"); blank lines are skipped; any other line that is not exactly
// three finite numbers is an InputError "file:LINE: ...".
std::vector<Eigen::Vector3d> ReadPointsFile(const std::string& path);

// Reads a CRSP LIDAR text file: any number of header lines, then a line that
// is exactly the column names "X Y Z" or "X Y Z R G B" (any case, blank or
// comma separated), then one point per line with as many values as there are
// columns (R G B are read, checked and dropped). Blank lines are skipped.
// Errors: no column line, or a row with a missing, extra or non-numeric value
// ("file:LINE: ...").
std::vector<Eigen::Vector3d> ReadLidarFile(const std::string& path);

// The placement of LIDAR data in the site frame: first the offset is
// subtracted, then the points turn by spin_deg about the vertical axis through
// the origin, counter-clockwise seen from above:
//   x' = x cos(a) - y sin(a),  y' = x sin(a) + y cos(a),  z' = z.
struct LidarTransform {
  // When true the offset is (min x, min y, 0) of the data (elevations are
  // kept, so Z partitions keep their meaning); otherwise `offset`.
  bool auto_offset = false;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // file units
  double spin_deg = 0.0;
};

// Applies `transform` to `points` in place; returns the offset subtracted.
Eigen::Vector3d ApplyLidarTransform(const LidarTransform& transform,
                                    std::vector<Eigen::Vector3d>* points);

}  // namespace rockcal::sites

#endif  // ROCKCAL_SITES_POINT_FILES_H_
