#include "rockcal/sites/gridding.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace rockcal::sites {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Points bucketed on a regular plan lattice (compressed rows).
class Buckets final {
 public:
  Buckets(const std::vector<Eigen::Vector3d>& points, double x0, double y0, double size, int nx,
          int ny, bool nearest)
      : x0_(x0), y0_(y0), size_(size), nx_(nx), ny_(ny), nearest_(nearest) {
    start_.assign(static_cast<std::size_t>(nx) * ny + 1, 0);
    std::vector<int> key(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      key[k] = Key(points[k].x(), points[k].y());
      ++start_[static_cast<std::size_t>(key[k]) + 1];
    }
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    items_.resize(points.size());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < points.size(); ++k) items_[fill[key[k]]++] = static_cast<int>(k);
  }
  // The points of bucket (i, j).
  const int* begin(int i, int j) const { return items_.data() + start_[j * nx_ + i]; }
  const int* end(int i, int j) const { return items_.data() + start_[j * nx_ + i + 1]; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int Index(double v, double origin, int n) const {
    const double f = (v - origin) / size_;
    const long k = static_cast<long>(nearest_ ? std::floor(f + 0.5) : std::floor(f));
    return static_cast<int>(std::clamp(k, 0L, static_cast<long>(n - 1)));
  }

 private:
  int Key(double x, double y) const { return Index(y, y0_, ny_) * nx_ + Index(x, x0_, nx_); }

  double x0_, y0_, size_;
  int nx_, ny_;
  bool nearest_;
  std::vector<int> start_;
  std::vector<int> items_;
};

struct Sample {
  double dx, dy, z, w;
};

// True when the samples are not all inside one open half-plane bounded by a
// line through the node (the node is inside or on their convex hull).
// `outside` are extra directions counted as covered (the outward normals of
// the grid edges the node lies on).
bool Surrounds(const std::vector<Sample>& samples, double tiny,
               const std::vector<double>& outside = {}) {
  std::vector<double> angle = outside;
  angle.reserve(samples.size() + outside.size());
  for (const Sample& s : samples) {
    if (std::abs(s.dx) <= tiny && std::abs(s.dy) <= tiny) return true;
    angle.push_back(std::atan2(s.dy, s.dx));
  }
  if (angle.size() < 2) return false;
  std::sort(angle.begin(), angle.end());
  double gap = angle.front() + 2 * kPi - angle.back();
  for (std::size_t k = 1; k < angle.size(); ++k) gap = std::max(gap, angle[k] - angle[k - 1]);
  return gap <= kPi + 1e-9;
}

// True when the (unit-weight) samples spread over the cell: their plan
// covariance has a standard deviation of at least `min_sd` in every direction.
bool Spread(const std::vector<Sample>& samples, double min_sd) {
  if (samples.size() < 3) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Sample& s : samples) mean += Eigen::Vector2d(s.dx, s.dy);
  mean /= static_cast<double>(samples.size());
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  for (const Sample& s : samples) {
    const Eigen::Vector2d d = Eigen::Vector2d(s.dx, s.dy) - mean;
    c += d * d.transpose();
  }
  c /= static_cast<double>(samples.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(c, Eigen::EigenvaluesOnly);
  return eig.eigenvalues().minCoeff() >= min_sd * min_sd;
}

// Weighted least-squares plane through the samples, evaluated at the node
// (dx = dy = 0). A direction in which the samples do not spread (collinear
// points) gets no slope.
double PlaneAtNode(const std::vector<Sample>& samples) {
  double sw = 0, mx = 0, my = 0, mz = 0;
  for (const Sample& s : samples) {
    sw += s.w;
    mx += s.w * s.dx;
    my += s.w * s.dy;
    mz += s.w * s.z;
  }
  mx /= sw;
  my /= sw;
  mz /= sw;
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  Eigen::Vector2d r = Eigen::Vector2d::Zero();
  for (const Sample& s : samples) {
    const Eigen::Vector2d d(s.dx - mx, s.dy - my);
    c += s.w * d * d.transpose();
    r += s.w * d * (s.z - mz);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(c);
  const Eigen::Vector2d lambda = eig.eigenvalues();
  const double threshold = 1e-10 * std::max(lambda.cwiseAbs().maxCoeff(), 0.0);
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  for (int k = 0; k < 2; ++k) {
    if (lambda[k] > threshold && lambda[k] > 0) {
      const Eigen::Vector2d u = eig.eigenvectors().col(k);
      gradient += u * (u.dot(r) / lambda[k]);
    }
  }
  return mz - gradient.dot(Eigen::Vector2d(mx, my));
}

}  // namespace

long NodeCount(double extent, double spacing) {
  return static_cast<long>(std::floor(extent / spacing + 1e-6)) + 1;
}

core::HeightGrid GridPoints(const std::vector<Eigen::Vector3d>& points, double spacing,
                            GriddingReport* report) {
  GriddingReport rep;
  core::HeightGrid g;
  g.spacing = spacing;
  if (points.empty()) {
    if (report) *report = rep;
    return g;
  }
  double xmin = points[0].x(), xmax = xmin, ymin = points[0].y(), ymax = ymin;
  for (const Eigen::Vector3d& p : points) {
    xmin = std::min(xmin, p.x());
    xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  g.x0 = xmin;
  g.y0 = ymin;
  g.nx = static_cast<int>(NodeCount(xmax - xmin, spacing));
  g.ny = static_cast<int>(NodeCount(ymax - ymin, spacing));
  g.z.assign(static_cast<std::size_t>(g.nx) * g.ny, kNaN);
  g.material.assign(g.z.size(), 0);

  const double s = spacing;
  rep.data_spacing = std::sqrt((xmax - xmin) * (ymax - ymin) / static_cast<double>(points.size()));
  rep.hole_radius = 2.0 * std::max(s, rep.data_spacing);
  const double hole_radius = rep.hole_radius, fit_radius = 2.0 * hole_radius;
  const double tiny = 1e-9 * s;

  // Own cells: nearest node. Neighbourhoods: buckets of size max(s, d).
  const Buckets cells(points, g.x0, g.y0, s, g.nx, g.ny, /*nearest=*/true);
  const double bsize = std::max(s, rep.data_spacing);
  const int bnx = static_cast<int>(std::floor((xmax - xmin) / bsize)) + 1;
  const int bny = static_cast<int>(std::floor((ymax - ymin) / bsize)) + 1;
  const Buckets buckets(points, g.x0, g.y0, bsize, bnx, bny, /*nearest=*/false);
  const int reach = static_cast<int>(std::ceil(fit_radius / bsize)) + 1;

  std::vector<Sample> own, near;
  std::vector<double> outside;
  for (int j = 0; j < g.ny; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x(i), y = g.y(j);
      double& z = g.z[g.index(i, j)];
      own.clear();
      for (const int* k = cells.begin(i, j); k != cells.end(i, j); ++k) {
        const Eigen::Vector3d& p = points[*k];
        own.push_back({p.x() - x, p.y() - y, p.z(), 1.0});
      }
      outside.clear();
      if (i == 0) outside.push_back(kPi);
      if (i == g.nx - 1) outside.push_back(0.0);
      if (j == 0) outside.push_back(-0.5 * kPi);
      if (j == g.ny - 1) outside.push_back(0.5 * kPi);
      if (!own.empty() && (Spread(own, 0.1 * s) || Surrounds(own, tiny, outside))) {
        z = PlaneAtNode(own);
        ++rep.from_cell;
        continue;
      }
      near.clear();
      double nearest = std::numeric_limits<double>::infinity();
      const int bi = buckets.Index(x, g.x0, bnx), bj = buckets.Index(y, g.y0, bny);
      for (int jj = std::max(0, bj - reach); jj <= std::min(bny - 1, bj + reach); ++jj) {
        for (int ii = std::max(0, bi - reach); ii <= std::min(bnx - 1, bi + reach); ++ii) {
          for (const int* k = buckets.begin(ii, jj); k != buckets.end(ii, jj); ++k) {
            const Eigen::Vector3d& p = points[*k];
            const double dx = p.x() - x, dy = p.y() - y, r2 = dx * dx + dy * dy;
            if (r2 > fit_radius * fit_radius) continue;
            nearest = std::min(nearest, r2);
            const double q = r2 + 0.25 * s * s;
            near.push_back({dx, dy, p.z(), 1.0 / (q * q)});
          }
        }
      }
      if (nearest <= hole_radius * hole_radius && Surrounds(near, tiny)) {
        z = PlaneAtNode(near);
        ++rep.from_neighbours;
      } else if (!own.empty()) {
        double sum = 0;
        for (const Sample& o : own) sum += o.z;
        z = sum / static_cast<double>(own.size());
        ++rep.cell_mean;
      } else {
        ++rep.holes;
      }
    }
  }
  if (report) *report = rep;
  return g;
}

}  // namespace rockcal::sites
