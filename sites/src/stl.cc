#include "rockcal/sites/stl.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "rockcal/core/error.h"
#include "rockcal/core/name_table.h"
#include "rockcal/core/numbers.h"
#include "rockcal/sites/input_file.h"
#include "rockcal/sites/text_reader.h"

namespace rockcal::sites {
namespace {

using core::kNaN;

struct Token {
  std::string text;
  int line;
};

// The largest STL file read (bytes): a binary STL of 20 million triangles.
constexpr std::size_t kMaxStlBytes = 84 + 50 * std::size_t{20'000'000};

std::string ReadAll(const std::string& path) {
  CheckInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open file: ") + std::strerror(errno));
  std::string data;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    data.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (data.size() > kMaxStlBytes)
      throw InputError(path, "larger than " + std::to_string(kMaxStlBytes) +
                                 " bytes (expected an STL file of at most 20 million triangles)");
  }
  return data;
}

// Binary STL: 80-byte header, uint32 triangle count, 50 bytes per triangle.
bool LooksBinary(const std::string& data) {
  if (data.find('\0') != std::string::npos) return true;
  if (data.size() < 84) return false;
  std::uint32_t n = 0;
  for (int k = 3; k >= 0; --k) n = (n << 8) | static_cast<unsigned char>(data[80 + k]);
  const bool sized = data.size() == 84 + 50 * static_cast<std::uint64_t>(n);
  const bool starts_solid = Lower(data.substr(0, 5)) == "solid";
  return sized && !starts_solid;
}

std::vector<Token> Tokenize(const std::string& data) {
  std::vector<Token> tokens;
  int line = 1;
  std::size_t i = 0;
  while (i < data.size()) {
    const char c = data[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else {
      std::size_t j = i;
      while (j < data.size() && !std::isspace(static_cast<unsigned char>(data[j]))) ++j;
      tokens.push_back({data.substr(i, j - i), line});
      i = j;
    }
  }
  return tokens;
}

// A cursor over the tokens that fails with "file:LINE: ...".
class TokenCursor final {
 public:
  TokenCursor(const std::string& path, const std::vector<Token>& tokens)
      : path_(path), tokens_(tokens) {}
  bool done() const { return pos_ >= tokens_.size(); }
  const Token& peek() const { return tokens_[pos_]; }
  int line() const { return done() ? (tokens_.empty() ? 1 : tokens_.back().line) : peek().line; }
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(line()), what);
  }
  void Expect(const char* keyword) {
    if (done()) Fail(std::string("file ends where '") + keyword + "' was expected");
    if (Lower(peek().text) != keyword)
      Fail(std::string("expected '") + keyword + "', found " + Excerpt(peek().text));
    ++pos_;
  }
  double Number(const char* what) {
    if (done()) Fail(std::string("file ends where ") + what + " was expected");
    double v = 0.0;
    if (!ParseNumber(peek().text, &v))
      Fail(std::string("expected ") + what + " (a finite number), found " + Excerpt(peek().text));
    ++pos_;
    return v;
  }
  bool Is(const char* keyword) const { return !done() && Lower(peek().text) == keyword; }
  // Skips the rest of the current token's line (a solid's name).
  void SkipLine() {
    const int l = tokens_[pos_ - 1].line;
    while (!done() && peek().line == l) ++pos_;
  }

 private:
  const std::string& path_;
  const std::vector<Token>& tokens_;
  std::size_t pos_ = 0;
};

}  // namespace

namespace {
constexpr core::Named<StlAxes> kStlAxes[] = {{StlAxes::kXYZ, "xyz"}, {StlAxes::kXZY, "xzy"}};
}  // namespace

bool StringToStlAxes(const std::string& name, StlAxes* axes) {
  return core::IdOf(kStlAxes, name, axes);
}

std::vector<Triangle> ReadStl(const std::string& path, StlAxes axes, double length_scale) {
  const std::string data = ReadAll(path);
  if (LooksBinary(data)) {
    throw InputError(path,
                     "binary STL is not supported (expected ASCII STL starting with "
                     "'solid'; export the surface as ASCII STL)");
  }
  const std::vector<Token> tokens = Tokenize(data);
  TokenCursor cur(path, tokens);
  if (cur.done()) throw InputError(path, "empty file (expected ASCII STL starting with 'solid')");
  std::vector<Triangle> triangles;
  while (!cur.done()) {
    cur.Expect("solid");
    cur.SkipLine();
    while (!cur.Is("endsolid")) {
      if (cur.done()) cur.Fail("file ends inside a solid (expected 'facet' or 'endsolid')");
      cur.Expect("facet");
      cur.Expect("normal");
      for (int k = 0; k < 3; ++k) cur.Number("a normal component");
      cur.Expect("outer");
      cur.Expect("loop");
      Eigen::Vector3d v[3];
      for (Eigen::Vector3d& p : v) {
        cur.Expect("vertex");
        double xyz[3];
        for (double& c : xyz) c = cur.Number("a vertex coordinate");
        p = axes == StlAxes::kXYZ ? Eigen::Vector3d(xyz[0], xyz[1], xyz[2])
                                  : Eigen::Vector3d(xyz[0], xyz[2], xyz[1]);
        p *= length_scale;
      }
      cur.Expect("endloop");
      cur.Expect("endfacet");
      triangles.push_back({v[0], v[1], v[2]});
    }
    cur.Expect("endsolid");
    cur.SkipLine();
  }
  if (triangles.empty()) throw InputError(path, "no triangles (expected 'facet' entries)");
  return triangles;
}

core::HeightGrid SampleTriangles(const std::vector<TriangleSet>& sets, double spacing) {
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin;
  double xmax = -xmin, ymax = -xmin;
  for (const TriangleSet& set : sets) {
    for (const Triangle& t : set.triangles) {
      for (const Eigen::Vector3d* p : {&t.a, &t.b, &t.c}) {
        xmin = std::min(xmin, p->x());
        xmax = std::max(xmax, p->x());
        ymin = std::min(ymin, p->y());
        ymax = std::max(ymax, p->y());
      }
    }
  }
  core::HeightGrid g;
  if (!(xmax >= xmin)) return g;
  g.x0 = xmin;
  g.y0 = ymin;
  g.spacing = spacing;
  g.nx = static_cast<int>(std::floor((xmax - xmin) / spacing + 1e-6)) + 1;
  g.ny = static_cast<int>(std::floor((ymax - ymin) / spacing + 1e-6)) + 1;
  g.z.assign(static_cast<std::size_t>(g.nx) * g.ny, kNaN);
  g.material.assign(g.z.size(), 0);
  for (const TriangleSet& set : sets) {
    for (const Triangle& t : set.triangles) {
      const Eigen::Vector2d a = t.a.head<2>(), b = t.b.head<2>(), c = t.c.head<2>();
      const Eigen::Vector2d ab = b - a, ac = c - a;
      const double area2 = ab.x() * ac.y() - ab.y() * ac.x();
      const double scale2 = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
      if (!(std::abs(area2) > 1e-12 * scale2)) continue;  // vertical or degenerate
      const double lo_x = std::min({a.x(), b.x(), c.x()}), hi_x = std::max({a.x(), b.x(), c.x()});
      const double lo_y = std::min({a.y(), b.y(), c.y()}), hi_y = std::max({a.y(), b.y(), c.y()});
      const int i0 = std::max(0, static_cast<int>(std::ceil((lo_x - g.x0) / spacing - 1e-9)));
      const int i1 =
          std::min(g.nx - 1, static_cast<int>(std::floor((hi_x - g.x0) / spacing + 1e-9)));
      const int j0 = std::max(0, static_cast<int>(std::ceil((lo_y - g.y0) / spacing - 1e-9)));
      const int j1 =
          std::min(g.ny - 1, static_cast<int>(std::floor((hi_y - g.y0) / spacing + 1e-9)));
      const double tol = 1e-9;
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const Eigen::Vector2d p(g.x(i), g.y(j));
          // Barycentric coordinates of p (relative to the signed area).
          const Eigen::Vector2d pb = b - p, pc = c - p, pa = a - p;
          const double la = (pb.x() * pc.y() - pb.y() * pc.x()) / area2;
          const double lb = (pc.x() * pa.y() - pc.y() * pa.x()) / area2;
          const double lc = 1.0 - la - lb;
          if (la < -tol || lb < -tol || lc < -tol) continue;
          const double z = la * t.a.z() + lb * t.b.z() + lc * t.c.z();
          const int n = g.index(i, j);
          if (std::isnan(g.z[n]) || z > g.z[n] + 1e-9 * (1.0 + std::abs(z))) {
            g.z[n] = z;
            g.material[n] = set.material;
          }
        }
      }
    }
  }
  return g;
}

}  // namespace rockcal::sites
