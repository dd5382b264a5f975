#include "rockcal/reports/svg.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rockcal/core/format.h"

namespace rockcal::reports::svg {
namespace {

constexpr const char* kGrid = "#e4e4e4";
constexpr const char* kInk = "#222";

// Drops trailing zeros of a fixed-point number ("1.500" -> "1.5", "2.0" -> "2").
std::string TrimZeros(std::string s) {
  if (s.find('.') == std::string::npos) return s;
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

// Widens an empty or bad range [*lo, *hi] of a linear or log axis.
void WidenRange(bool log, double* lo, double* hi) {
  if (log) {
    if (!(*lo > 0.0)) *lo = *hi > 0.0 ? *hi * 1e-3 : 1e-3;
    if (!(*hi > *lo)) {
      *lo /= 2.0;
      *hi = *lo * 4.0;
    }
  } else if (!(*hi > *lo)) {
    const double pad = *lo != 0.0 ? std::fabs(*lo) * 0.1 : 1.0;
    *lo -= pad;
    *hi += pad;
  }
}

// Where v lies between lo and hi, 0 to 1, on a linear or log axis.
double Fraction(bool log, double v, double lo, double hi) {
  if (log)
    return (std::log10(std::max(v, 1e-300)) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  return (v - lo) / (hi - lo);
}

}  // namespace

std::string Escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Px(double v) {
  if (!std::isfinite(v)) v = 0.0;
  return TrimZeros(core::FormatNumber(v, "%.1f"));
}

std::string Label(double v, int digits) {
  if (!std::isfinite(v)) return std::isnan(v) ? "NaN" : (v > 0 ? "inf" : "-inf");
  if (v == 0.0) return "0";
  const double a = std::fabs(v);
  if (a >= 1e-4 && a < 1e7) {
    const int magnitude = static_cast<int>(std::floor(std::log10(a)));
    const int decimals = std::max(0, digits - 1 - magnitude);
    return TrimZeros(core::FormatNumber(v, ("%." + std::to_string(decimals) + "f").c_str()));
  }
  return core::FormatNumber(v, ("%." + std::to_string(digits) + "g").c_str());
}

double NiceStep(double span, int count) {
  if (!(span > 0.0) || !std::isfinite(span)) return 1.0;
  const double raw = span / std::max(count, 1);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / p;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * p;
}

std::vector<double> Ticks(double lo, double hi, int count) {
  std::vector<double> out;
  if (!(hi > lo)) return {lo};
  const double step = NiceStep(hi - lo, count);
  const double eps = step * 1e-9;
  for (double k = std::ceil((lo - eps) / step);; k += 1.0) {
    double t = k * step;
    if (t > hi + eps) break;
    if (std::fabs(t) < eps) t = 0.0;
    out.push_back(t);
    if (out.size() > 100) break;
  }
  return out;
}

std::vector<double> LogTicks(double lo, double hi) {
  std::vector<double> out;
  if (!(lo > 0.0) || !(hi > lo)) return out;
  const int k0 = static_cast<int>(std::floor(std::log10(lo)));
  const int k1 = static_cast<int>(std::ceil(std::log10(hi)));
  std::vector<double> powers, all;
  for (int k = k0; k <= k1; ++k) {
    const double p = std::pow(10.0, k);
    for (double m : {1.0, 2.0, 5.0}) {
      const double t = m * p;
      if (t < lo * (1 - 1e-9) || t > hi * (1 + 1e-9)) continue;
      all.push_back(t);
      if (m == 1.0) powers.push_back(t);
    }
  }
  if (powers.size() >= 3) return powers;
  return all;
}

const char* Colour(int index) {
  static const char* const kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                         "#E69F00", "#56B4E9", "#000000", "#8c6d31"};
  const int n = static_cast<int>(sizeof kColours / sizeof kColours[0]);
  return kColours[((index % n) + n) % n];
}

Plot::Plot(double xlo, double xhi, double ylo, double yhi, const Options& options)
    : xlo_(xlo), xhi_(xhi), ylo_(ylo), yhi_(yhi), options_(options) {
  WidenRange(options_.log_x, &xlo_, &xhi_);
  WidenRange(options_.log_y, &ylo_, &yhi_);
}

double Plot::X(double x) const {
  return left() + Fraction(options_.log_x, x, xlo_, xhi_) * (right() - left());
}

double Plot::Y(double y) const {
  return bottom() - Fraction(options_.log_y, y, ylo_, yhi_) * (bottom() - top());
}

bool Plot::Drawable(double x, double y) const {
  return std::isfinite(x) && std::isfinite(y) && (!options_.log_x || x > 0.0) &&
         (!options_.log_y || y > 0.0);
}

void Plot::Axes(const std::string& x_label, const std::string& y_label) {
  std::string g = "<g class=\"axes\">";
  const std::vector<double> xt =
      options_.log_x ? LogTicks(xlo_, xhi_)
                     : Ticks(xlo_, xhi_, std::max(3, static_cast<int>((right() - left()) / 70)));
  const std::vector<double> yt =
      options_.log_y ? LogTicks(ylo_, yhi_)
                     : Ticks(ylo_, yhi_, std::max(3, static_cast<int>((bottom() - top()) / 45)));
  std::vector<std::pair<double, std::string>> xticks;
  if (!options_.log_x) xticks = options_.x_ticks;
  if (xticks.empty())
    for (double t : xt) xticks.emplace_back(t, Label(t));
  for (const auto& [t, label] : xticks) {
    const std::string x = Px(X(t));
    g += "<line x1=\"" + x + "\" y1=\"" + Px(top()) + "\" x2=\"" + x + "\" y2=\"" + Px(bottom()) +
         "\" stroke=\"" + kGrid + "\"/>";
    g += "<line x1=\"" + x + "\" y1=\"" + Px(bottom()) + "\" x2=\"" + x + "\" y2=\"" +
         Px(bottom() + 4) + "\" stroke=\"" + kInk + "\"/>";
    g += "<text x=\"" + x + "\" y=\"" + Px(bottom() + 15) + "\" text-anchor=\"middle\">" +
         Escape(label) + "</text>";
  }
  for (double t : yt) {
    const std::string y = Px(Y(t));
    g += "<line x1=\"" + Px(left()) + "\" y1=\"" + y + "\" x2=\"" + Px(right()) + "\" y2=\"" + y +
         "\" stroke=\"" + kGrid + "\"/>";
    g += "<line x1=\"" + Px(left() - 4) + "\" y1=\"" + y + "\" x2=\"" + Px(left()) + "\" y2=\"" +
         y + "\" stroke=\"" + kInk + "\"/>";
    g += "<text x=\"" + Px(left() - 6) + "\" y=\"" + Px(Y(t) + 4) + "\" text-anchor=\"end\">" +
         Escape(Label(t)) + "</text>";
  }
  g += "<rect x=\"" + Px(left()) + "\" y=\"" + Px(top()) + "\" width=\"" + Px(right() - left()) +
       "\" height=\"" + Px(bottom() - top()) + "\" fill=\"none\" stroke=\"" + kInk + "\"/>";
  g += "<text x=\"" + Px((left() + right()) / 2) + "\" y=\"" + Px(options_.height - 8) +
       "\" text-anchor=\"middle\">" + Escape(x_label) + "</text>";
  const std::string yc = Px((top() + bottom()) / 2);
  g += "<text x=\"14\" y=\"" + yc + "\" text-anchor=\"middle\" transform=\"rotate(-90 14 " + yc +
       ")\">" + Escape(y_label) + "</text>";
  g += "</g>";
  body_ = g + body_;  // under the data
}

void Plot::TopAxis(double scale, const std::string& label) {
  if (!(scale > 0.0) || options_.log_x) return;
  std::string g = "<g class=\"axis2\">";
  for (double u :
       Ticks(xlo_ * scale, xhi_ * scale, std::max(3, static_cast<int>((right() - left()) / 70)))) {
    const std::string x = Px(X(u / scale));
    g += "<line x1=\"" + x + "\" y1=\"" + Px(top() - 4) + "\" x2=\"" + x + "\" y2=\"" + Px(top()) +
         "\" stroke=\"" + kInk + "\"/>";
    g += "<text x=\"" + x + "\" y=\"" + Px(top() - 7) + "\" text-anchor=\"middle\" fill=\"#555\">" +
         Escape(Label(u)) + "</text>";
  }
  g += "<text x=\"" + Px((left() + right()) / 2) + "\" y=\"" + Px(top() - 22) +
       "\" text-anchor=\"middle\" fill=\"#555\">" + Escape(label) + "</text></g>";
  body_ += g;
}

void Plot::RightAxis(double scale, const std::string& label) {
  if (!(scale > 0.0) || options_.log_y) return;
  std::string g = "<g class=\"axis2\">";
  for (double u :
       Ticks(ylo_ * scale, yhi_ * scale, std::max(3, static_cast<int>((bottom() - top()) / 45)))) {
    const double y = Y(u / scale);
    g += "<line x1=\"" + Px(right()) + "\" y1=\"" + Px(y) + "\" x2=\"" + Px(right() + 4) +
         "\" y2=\"" + Px(y) + "\" stroke=\"" + kInk + "\"/>";
    g += "<text x=\"" + Px(right() + 6) + "\" y=\"" + Px(y + 4) + "\" fill=\"#555\">" +
         Escape(Label(u)) + "</text>";
  }
  const std::string xc = Px(options_.width - 8);
  const std::string yc = Px((top() + bottom()) / 2);
  g += "<text x=\"" + xc + "\" y=\"" + yc +
       "\" text-anchor=\"middle\" fill=\"#555\" transform=\"rotate(-90 " + xc + " " + yc + ")\">" +
       Escape(label) + "</text></g>";
  body_ += g;
}

void Plot::Bars(const std::vector<double>& edges, const std::vector<double>& heights,
                const std::string& fill) {
  std::string g = "<g fill=\"" + Escape(fill) + "\" stroke=\"#fff\" stroke-width=\"0.5\">";
  const double base = Y(options_.log_y ? ylo_ : std::max(ylo_, 0.0));
  for (std::size_t k = 0; k < heights.size() && k + 1 < edges.size(); ++k) {
    if (!(heights[k] > 0.0)) continue;
    const double x0 = X(edges[k]), x1 = X(edges[k + 1]), y = Y(heights[k]);
    g += "<rect x=\"" + Px(x0) + "\" y=\"" + Px(y) + "\" width=\"" + Px(std::max(x1 - x0, 0.5)) +
         "\" height=\"" + Px(std::max(base - y, 0.0)) + "\"/>";
  }
  body_ += g + "</g>";
}

void Plot::Polyline(const std::vector<double>& xs, const std::vector<double>& ys,
                    const std::string& attributes) {
  std::string points;
  int n = 0;
  auto flush = [&] {
    if (n >= 2) body_ += "<polyline fill=\"none\" " + attributes + " points=\"" + points + "\"/>";
    points.clear();
    n = 0;
  };
  for (std::size_t k = 0; k < xs.size() && k < ys.size(); ++k) {
    if (!Drawable(xs[k], ys[k])) {
      flush();
      continue;
    }
    if (n > 0) points += ' ';
    points += Px(X(xs[k])) + "," + Px(Y(ys[k]));
    ++n;
  }
  flush();
}

void Plot::Steps(const std::vector<double>& xs, const std::vector<double>& ys,
                 const std::string& attributes) {
  std::vector<double> sx, sy;
  for (std::size_t k = 0; k < xs.size() && k < ys.size(); ++k) {
    if (k > 0) {
      sx.push_back(xs[k]);
      sy.push_back(ys[k - 1]);
    }
    sx.push_back(xs[k]);
    sy.push_back(ys[k]);
  }
  Polyline(sx, sy, attributes);
}

void Plot::Points(const std::vector<double>& xs, const std::vector<double>& ys, double r,
                  const std::string& attributes) {
  std::string g = "<g " + attributes + ">";
  const std::string rs = Px(r);
  for (std::size_t k = 0; k < xs.size() && k < ys.size(); ++k) {
    if (!Drawable(xs[k], ys[k])) continue;
    const double x = X(xs[k]), y = Y(ys[k]);
    if (x < left() - 0.5 || x > right() + 0.5 || y < top() - 0.5 || y > bottom() + 0.5) continue;
    g += "<circle cx=\"" + Px(x) + "\" cy=\"" + Px(y) + "\" r=\"" + rs + "\"/>";
  }
  body_ += g + "</g>";
}

void Plot::VLine(double x, const std::string& attributes, const std::string& label) {
  if (!(x >= xlo_ && x <= xhi_)) return;
  const std::string px = Px(X(x));
  body_ += "<line x1=\"" + px + "\" y1=\"" + Px(top()) + "\" x2=\"" + px + "\" y2=\"" +
           Px(bottom()) + "\" " + attributes + "/>";
  if (!label.empty()) {
    const bool near_right = X(x) > right() - 60;
    body_ += "<text x=\"" + Px(X(x) + (near_right ? -3 : 3)) + "\" y=\"" + Px(top() + 12) + "\"" +
             (near_right ? " text-anchor=\"end\"" : "") + " class=\"halo\">" + Escape(label) +
             "</text>";
  }
}

void Plot::HLine(double y, const std::string& attributes, const std::string& label) {
  if (!(y >= ylo_ && y <= yhi_)) return;
  const std::string py = Px(Y(y));
  body_ += "<line x1=\"" + Px(left()) + "\" y1=\"" + py + "\" x2=\"" + Px(right()) + "\" y2=\"" +
           py + "\" " + attributes + "/>";
  if (!label.empty())
    body_ += "<text x=\"" + Px(right() - 3) + "\" y=\"" + Px(Y(y) - 4) +
             "\" text-anchor=\"end\" class=\"halo\">" + Escape(label) + "</text>";
}

void Plot::Text(double x, double y, const std::string& text, const std::string& attributes) {
  body_ += "<text x=\"" + Px(x) + "\" y=\"" + Px(y) + "\"" + (attributes.empty() ? "" : " ") +
           attributes + ">" + Escape(text) + "</text>";
}

void Plot::Raw(const std::string& markup) { body_ += markup; }

void Plot::Legend(const std::vector<LegendEntry>& entries, bool right_side) {
  if (entries.empty()) return;
  std::size_t longest = 0;
  for (const auto& e : entries) longest = std::max(longest, e.label.size());
  const double w = 30.0 + 6.2 * static_cast<double>(longest), h = 6.0 + 15.0 * entries.size();
  const double x0 = right_side ? right() - w - 6 : left() + 6, y0 = top() + 6;
  std::string g = "<g class=\"legend\"><rect x=\"" + Px(x0) + "\" y=\"" + Px(y0) + "\" width=\"" +
                  Px(w) + "\" height=\"" + Px(h) +
                  "\" fill=\"#fff\" fill-opacity=\"0.88\" stroke=\"#bbb\"/>";
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const auto& e = entries[k];
    const double y = y0 + 12.0 + 15.0 * static_cast<double>(k);
    const std::string c = Escape(e.colour);
    if (e.kind == "point") {
      g += "<circle cx=\"" + Px(x0 + 13) + "\" cy=\"" + Px(y - 4) + "\" r=\"3.5\" fill=\"" + c +
           "\"/>";
    } else if (e.kind == "ring") {
      g += "<circle cx=\"" + Px(x0 + 13) + "\" cy=\"" + Px(y - 4) +
           "\" r=\"3.5\" fill=\"none\" stroke=\"" + c + "\" stroke-width=\"1.5\"/>";
    } else if (e.kind == "bar") {
      g += "<rect x=\"" + Px(x0 + 6) + "\" y=\"" + Px(y - 9) +
           "\" width=\"14\" height=\"9\" fill=\"" + c + "\"/>";
    } else if (e.kind == "dash") {
      g += "<line x1=\"" + Px(x0 + 5) + "\" y1=\"" + Px(y - 4) + "\" x2=\"" + Px(x0 + 21) +
           "\" y2=\"" + Px(y - 4) + "\" stroke=\"" + c +
           "\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\"/>";
    } else {
      g += "<line x1=\"" + Px(x0 + 5) + "\" y1=\"" + Px(y - 4) + "\" x2=\"" + Px(x0 + 21) +
           "\" y2=\"" + Px(y - 4) + "\" stroke=\"" + c + "\" stroke-width=\"2\"/>";
    }
    g += "<text x=\"" + Px(x0 + 26) + "\" y=\"" + Px(y) + "\">" + Escape(e.label) + "</text>";
  }
  body_ += g + "</g>";
}

std::string Plot::Svg() const {
  const std::string w = Px(options_.width), h = Px(options_.height);
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h +
                    "\" viewBox=\"0 0 " + w + " " + h +
                    "\" font-family=\"sans-serif\" font-size=\"11\" fill=\"" + kInk +
                    "\" role=\"img\">";
  if (!options_.title.empty()) out += "<title>" + Escape(options_.title) + "</title>";
  return out + body_ + "</svg>";
}

}  // namespace rockcal::reports::svg
