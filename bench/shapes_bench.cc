// Scanned rock shapes (docs/rock-shapes.md): (1) how well a clump of N equal
// spheres fits each shape file given, for several budgets N (volume, moment
// and side errors of the union against the hull, fit time); (2) the cost of
// a shape: rocks of the shape on the benchmark slope (slope_scene.h) against
// boxes of the same sides, rock-steps per second at one thread, the two
// timed in alternation, medians of several runs.
//   shapes_bench SHAPE_FILE... [--rocks 60] [--runs 5] [--spheres N]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "rockcal/core/error.h"
#include "rockcal/sites/shape_file.h"
#include "slope_scene.h"
#include "timing.h"

int main(int argc, char** argv) {
  using namespace rockcal;
  std::vector<std::string> files;
  int rocks = 60, runs = 5, spheres = core::ClumpOptions().spheres;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--rocks" && k + 1 < argc) rocks = std::atoi(argv[++k]);
    else if (a == "--runs" && k + 1 < argc) runs = std::atoi(argv[++k]);
    else if (a == "--spheres" && k + 1 < argc) spheres = std::atoi(argv[++k]);
    else files.push_back(a);
  }
  if (files.empty() || rocks < 1 || runs < 1) {
    std::fprintf(stderr, "usage: shapes_bench SHAPE_FILE... [--rocks 60] [--runs 5] [--spheres N]\n");
    return 2;
  }
  try {
    std::printf("clump fit: union of N equal spheres against the hull (grid %d)\n",
                core::ClumpOptions().grid);
    std::printf("%-8s %-7s %4s %10s %10s %10s %10s %8s  %s\n", "shape", "target", "N", "volume_%", "moments_%",
                "sides_%", "radius/L3", "fit_ms", "union sides / hull sides");
    for (const std::string& f : files) {
      const std::vector<Eigen::Vector3d> points = sites::ReadShapePoints(f, 1.0);
      const core::Polyhedron hull = sites::ConvexHull(points, f);
      {
        core::MassProperties m;
        const core::Polyhedron p = core::ToPrincipalFrame(hull, &m);
        Eigen::Vector3d lo = p.vertices[0], hi = lo;
        for (const auto& v : p.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
        const Eigen::Vector3d d = hi - lo;
        std::printf("# %s: %zu points, hull %zu vertices, volume %.4g m^3, principal sides "
                    "%.3f x %.3f x %.3f m (L2/L1 %.2f, L3/L1 %.2f)\n",
                    f.c_str(), points.size(), p.vertices.size(), m.volume, d.x(), d.y(), d.z(),
                    d.y() / d.x(), d.z() / d.x());
      }
      for (core::ClumpTarget target : {core::ClumpTarget::kMoments, core::ClumpTarget::kSides})
      for (int n : {1, 2, 4, 6, 8, 12, 16, 24, 32}) {
        core::ClumpOptions o;
        o.spheres = n;
        o.target = target;
        const auto t0 = std::chrono::steady_clock::now();
        const core::ScannedShape s = core::MakeScannedShape(hull, o, f, f);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const core::Clump& c = s.clump;
        const std::size_t slash = f.find_last_of('/');
        const Eigen::Vector3d rs = c.union_sides.cwiseQuotient(c.hull_sides);
        std::printf("%-8s %-7s %4d %10.2f %10.2f %10.2f %10.3f %8.1f  %.3f %.3f %.3f\n",
                    f.substr(slash == std::string::npos ? 0 : slash + 1, 8).c_str(),
                    core::ClumpTargetToString(target), n, 100 * c.volume_error, 100 * c.moment_error, 100 * c.side_error,
                    c.radius / c.hull_sides.z(), ms, rs.x(), rs.y(), rs.z());
      }
    }
    std::printf("\ngrid error: the default clump's union on %d^2 columns against 160^2\n",
                core::ClumpOptions().grid);
    for (const std::string& f : files) {
      const auto shape = sites::LoadScannedShape(f, 1.0, core::ClumpOptions());
      const core::Clump& c = shape->clump;
      Eigen::Vector3d fine;
      const double v = core::UnionIntegrals(c.centres, c.radius, 160, &fine);
      std::printf("%s: volume %+.3f %%, moments %+.3f %% %+.3f %% %+.3f %%\n", f.c_str(),
                  100 * (c.union_volume / v - 1), 100 * (c.union_moments.x() / fine.x() - 1),
                  100 * (c.union_moments.y() / fine.y() - 1),
                  100 * (c.union_moments.z() / fine.z() - 1));
    }
    std::printf("\ncost: %d rocks of L1 0.6-1.2 m on the slope of slope_scene.h, 1 thread, "
                "median of %d runs each (alternating), %d spheres\n",
                rocks, runs, spheres);
    std::printf("%-8s %9s %9s %12s %12s %8s %8s\n", "shape", "elements", "box_elts", "shape_rs/s",
                "box_rs/s", "ratio", "stopped");
    for (const std::string& f : files) {
      core::ClumpOptions o;
      o.spheres = spheres;
      const auto shape = sites::LoadScannedShape(f, 1.0, o);
      core::Scene scanned = bench::SlopeScene(rocks);
      scanned.groups[0].shape = core::Shape::kScanned;
      scanned.groups[0].scanned = shape;
      core::Scene boxes = bench::SlopeScene(rocks);
      boxes.groups[0].shape = core::Shape::kBox;
      boxes.groups[0].box = shape->clump.hull_sides;
      const core::Terrain terrain = core::BuildTerrain(scanned);
      std::vector<double> rate_s, rate_b, ratio;
      long stopped = 0;
      for (int r = 0; r < runs; ++r) {
        const bench::TimedRuns a = bench::TimeSimulation(scanned, terrain, 1, 1);
        const bench::TimedRuns b = bench::TimeSimulation(boxes, terrain, 1, 1);
        rate_s.push_back(a.result.figures.steps / a.median_wall);
        rate_b.push_back(b.result.figures.steps / b.median_wall);
        ratio.push_back(rate_s.back() / rate_b.back());
        stopped = 0;
        for (const auto& rec : a.result.rocks) stopped += rec.outcome == core::Outcome::kStopped;
      }
      const core::RockBody box = core::MakeBoxBody(shape->clump.hull_sides, 1.0);
      const std::size_t slash = f.find_last_of('/');
      std::printf("%-8s %9zu %9zu %12.3g %12.3g %8.2f %5ld/%d\n",
                  f.substr(slash == std::string::npos ? 0 : slash + 1, 8).c_str(),
                  shape->clump.centres.size(), box.elements.size(), bench::Median(rate_s),
                  bench::Median(rate_b), bench::Median(ratio), stopped, rocks);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "shapes_bench: %s\n", e.what());
    return 2;
  }
  return 0;
}
