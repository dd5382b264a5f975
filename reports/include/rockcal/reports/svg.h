// A tiny SVG plotting helper for the HTML report: axes with nice ticks (linear
// or log, on either axis), a secondary axis in other units, bars, polylines, points, lines and
// text. Output is XML (every element closed, attributes quoted, text escaped).
#ifndef ROCKCAL_REPORTS_SVG_H_
#define ROCKCAL_REPORTS_SVG_H_

#include <string>
#include <utility>
#include <vector>

namespace rockcal::reports::svg {

// Escapes &, <, >, " and ' for XML text and attribute values.
std::string Escape(const std::string& text);
// A coordinate in pixels with one decimal ("12.3", "-4", never "1e+03").
std::string Px(double v);
// A number for tick labels and captions: up to `digits` significant digits,
// no exponent between 1e-4 and 1e6, trailing zeros dropped.
std::string Label(double v, int digits = 4);

// About `count` tick positions covering [lo, hi]: multiples of 1, 2 or 5 x 10^k
// inside the range. lo < hi.
std::vector<double> Ticks(double lo, double hi, int count = 5);
// Log-scale ticks inside [lo, hi] (0 < lo < hi): powers of ten, with 2 and 5
// multiples when fewer than three powers fall inside.
std::vector<double> LogTicks(double lo, double hi);
// The step Ticks would use: a 1, 2 or 5 x 10^k close to (hi - lo) / count.
double NiceStep(double span, int count);

// Colour-blind-safe qualitative colours (Okabe and Ito), cycled by index.
const char* Colour(int index);

class Plot final {
 public:
  struct Options {
    double width = 380.0, height = 250.0;                         // px, the whole picture
    double left = 58.0, right = 16.0, top = 16.0, bottom = 44.0;  // margins, px
    bool log_x = false;  // log scale on x: data x <= 0 is not drawn
    bool log_y = false;  // log scale on y: data y <= 0 is not drawn
    std::string title;   // read by screen readers (<title>), not drawn
    // When not empty: the x ticks (data x, label) instead of nice numbers,
    // e.g. categories of a bar chart. Not used on a log x axis.
    std::vector<std::pair<double, std::string>> x_ticks;
  };
  // A plot of [xlo, xhi] x [ylo, yhi]; empty ranges are widened. With log_x
  // (log_y), a bad xlo (ylo) <= 0 is replaced by xhi / 1000 (yhi / 1000).
  Plot(double xlo, double xhi, double ylo, double yhi, const Options& options);

  double X(double x) const;  // data -> px
  double Y(double y) const;
  double xlo() const { return xlo_; }
  double xhi() const { return xhi_; }
  double ylo() const { return ylo_; }
  double yhi() const { return yhi_; }
  // Left, right, top and bottom of the plot area in px.
  double left() const { return options_.left; }
  double right() const { return options_.width - options_.right; }
  double top() const { return options_.top; }
  double bottom() const { return options_.height - options_.bottom; }

  // Frame, grid lines, ticks and axis labels (bottom and left).
  void Axes(const std::string& x_label, const std::string& y_label);
  // A secondary axis on top showing x * scale (e.g. feet beside metres);
  // needs a top margin of about 36 px. Not drawn on a log x axis.
  void TopAxis(double scale, const std::string& label);
  // A secondary axis on the right showing y * scale; needs a right margin of
  // about 50 px. Not drawn on a log y axis.
  void RightAxis(double scale, const std::string& label);
  // Bars between consecutive `edges` (size heights + 1), from y = ylo.
  void Bars(const std::vector<double>& edges, const std::vector<double>& heights,
            const std::string& fill);
  // A polyline through (xs[k], ys[k]); non-finite points (and points <= 0 on
  // a log axis) break the line.
  // `attributes` is added verbatim (e.g. stroke="#000" stroke-width="1").
  void Polyline(const std::vector<double>& xs, const std::vector<double>& ys,
                const std::string& attributes);
  // A step line (best so far): horizontal then vertical between points.
  void Steps(const std::vector<double>& xs, const std::vector<double>& ys,
             const std::string& attributes);
  // Circles of radius r px at the points inside the plot (finite, and > 0 on
  // a log axis).
  void Points(const std::vector<double>& xs, const std::vector<double>& ys, double r,
              const std::string& attributes);
  // A vertical line at data x (clipped to the plot) with a label at its top.
  void VLine(double x, const std::string& attributes, const std::string& label = "");
  // A horizontal line at data y with a label at its right end.
  void HLine(double y, const std::string& attributes, const std::string& label = "");
  // Text at px (x, y); `attributes` e.g. text-anchor="end".
  void Text(double x, double y, const std::string& text, const std::string& attributes = "");
  // Raw SVG markup (px coordinates), e.g. a clipped group of paths.
  void Raw(const std::string& markup);
  // A legend box in the top-left (or top-right) corner of the plot area:
  // one (colour, label, kind) per entry, kind "line", "point" or "bar".
  struct LegendEntry {
    std::string colour, label, kind = "line";
  };
  void Legend(const std::vector<LegendEntry>& entries, bool right = false);

  // The whole <svg> element.
  std::string Svg() const;

 private:
  // A finite point that a log axis can show (> 0 there).
  bool Drawable(double x, double y) const;

  double xlo_, xhi_, ylo_, yhi_;
  Options options_;
  std::string body_;
};

}  // namespace rockcal::reports::svg

#endif  // ROCKCAL_REPORTS_SVG_H_
