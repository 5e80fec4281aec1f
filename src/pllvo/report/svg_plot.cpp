#include "pllvo/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace pllvo::report {
namespace {

// Line chart margins (SVG units): room for tick labels on the left and below, title above.
constexpr double kLeft = 62, kRight = 14, kTop = 26, kBottom = 40;
constexpr double kFont = 11;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

}  // namespace

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

Range data_range(const std::vector<std::vector<double>>& series) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : series)
    for (double v : s)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) return {0, 1};
  if (hi - lo < 1e-12 * std::max(1.0, std::abs(lo))) {
    const double half = std::max(0.5, 0.05 * std::abs(lo));
    return {lo - half, hi + half};
  }
  return {lo, hi};
}

Range padded(const Range& r, double fraction) {
  const double pad = r.span() * fraction;
  return {r.min - pad, r.max + pad};
}

std::vector<double> nice_ticks(const Range& r, int target) {
  std::vector<double> ticks;
  if (!(r.span() > 0) || target < 1) return ticks;
  const double raw = r.span() / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  // The candidate step whose tick count comes closest to the target.
  double step = magnitude;
  for (double m : {2.0, 5.0, 10.0})
    if (std::abs(r.span() / (m * magnitude) - target) < std::abs(r.span() / step - target)) step = m * magnitude;
  const double first = std::ceil(r.min / step - 1e-9) * step;
  for (double t = first; t <= r.max + 1e-9 * step; t += step) ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

std::string tick_label(double value, double step) {
  char buf[32];
  const double a = std::abs(value);
  if (a != 0 && (a >= 1e5 || a < 1e-4)) {
    std::snprintf(buf, sizeof buf, "%.2g", value);
  } else {
    const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
    std::snprintf(buf, sizeof buf, "%.*f", std::min(decimals, 6), value);
  }
  return buf;
}

AxisMap::AxisMap(Range x, Range y, PixelRect area, bool equal_aspect) : x_(x), y_(y), area_(area) {
  sx_ = area.width / x_.span();
  sy_ = area.height / y_.span();
  if (equal_aspect) {
    // One scale for both axes; the axis with room to spare is widened around its centre.
    const double s = std::min(sx_, sy_);
    const double cx = 0.5 * (x_.min + x_.max), cy = 0.5 * (y_.min + y_.max);
    const double hx = 0.5 * area.width / s, hy = 0.5 * area.height / s;
    x_ = {cx - hx, cx + hx};
    y_ = {cy - hy, cy + hy};
    sx_ = sy_ = s;
  }
}

LineChart::LineChart(std::string title, std::string x_label, std::string y_label)
    : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)) {}

AxisMap LineChart::axis_map(double width, double height) const {
  std::vector<std::vector<double>> xs, ys;
  for (const auto& s : series_) xs.push_back(s.x), ys.push_back(s.y);
  const PixelRect area{kLeft, kTop, std::max(1.0, width - kLeft - kRight), std::max(1.0, height - kTop - kBottom)};
  return AxisMap(padded(data_range(xs), equal_aspect_ ? 0.05 : 0.0), padded(data_range(ys), 0.05), area,
                 equal_aspect_);
}

std::string LineChart::render(double width, double height) const {
  const AxisMap map = axis_map(width, height);
  const PixelRect& a = map.area();
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"" << num(width) << "\" height=\""
    << num(height) << "\" viewBox=\"0 0 " << num(width) << ' ' << num(height) << "\" font-family=\"sans-serif\" font-size=\""
    << kFont << "\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << num(width / 2) << "\" y=\"16\" text-anchor=\"middle\" font-weight=\"bold\">"
    << xml_escape(title_) << "</text>\n";
  // Grid and ticks.
  const auto xt = nice_ticks(map.x_range(), std::max(2, static_cast<int>(a.width / 80)));
  const auto yt = nice_ticks(map.y_range(), std::max(2, static_cast<int>(a.height / 45)));
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1, ystep = yt.size() > 1 ? yt[1] - yt[0] : 1;
  for (double t : xt) {
    const double x = map.px(t);
    o << "<line x1=\"" << num(x) << "\" y1=\"" << num(a.top) << "\" x2=\"" << num(x) << "\" y2=\"" << num(a.bottom())
      << "\" stroke=\"#e4e4e4\"/>\n<text x=\"" << num(x) << "\" y=\"" << num(a.bottom() + 14)
      << "\" text-anchor=\"middle\">" << tick_label(t, xstep) << "</text>\n";
  }
  for (double t : yt) {
    const double y = map.py(t);
    o << "<line x1=\"" << num(a.left) << "\" y1=\"" << num(y) << "\" x2=\"" << num(a.right()) << "\" y2=\"" << num(y)
      << "\" stroke=\"#e4e4e4\"/>\n<text x=\"" << num(a.left - 5) << "\" y=\"" << num(y + 4)
      << "\" text-anchor=\"end\">" << tick_label(t, ystep) << "</text>\n";
  }
  o << "<rect x=\"" << num(a.left) << "\" y=\"" << num(a.top) << "\" width=\"" << num(a.width) << "\" height=\""
    << num(a.height) << "\" fill=\"none\" stroke=\"#444\"/>\n";
  o << "<text x=\"" << num(a.left + a.width / 2) << "\" y=\"" << num(height - 6) << "\" text-anchor=\"middle\">"
    << xml_escape(x_label_) << "</text>\n";
  o << "<text transform=\"translate(14," << num(a.top + a.height / 2) << ") rotate(-90)\" text-anchor=\"middle\">"
    << xml_escape(y_label_) << "</text>\n";
  // Data, clipped to the plot area.
  const std::string clip = "clip-" + id_;
  o << "<clipPath id=\"" << clip << "\"><rect x=\"" << num(a.left) << "\" y=\"" << num(a.top) << "\" width=\""
    << num(a.width) << "\" height=\"" << num(a.height) << "\"/></clipPath>\n<g clip-path=\"url(#" << clip << ")\">\n";
  for (const auto& s : series_) {
    std::string points;
    auto flush = [&] {
      if (!points.empty())
        o << "<polyline class=\"series\" fill=\"none\" stroke=\"" << s.color << "\" stroke-width=\"" << num(s.width)
          << "\"" << (s.dashed ? " stroke-dasharray=\"5,3\"" : "") << " points=\"" << points << "\"/>\n";
      points.clear();
    };
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        flush();
        continue;
      }
      points += num(map.px(s.x[i])) + "," + num(map.py(s.y[i])) + " ";
    }
    flush();
  }
  o << "</g>\n";
  // Legend.
  double ly = a.top + 14;
  for (const auto& s : series_) {
    if (s.label.empty()) continue;
    const double lx = a.right() - 120;
    o << "<line x1=\"" << num(lx) << "\" y1=\"" << num(ly - 4) << "\" x2=\"" << num(lx + 18) << "\" y2=\"" << num(ly - 4)
      << "\" stroke=\"" << s.color << "\" stroke-width=\"2\"" << (s.dashed ? " stroke-dasharray=\"5,3\"" : "")
      << "/><text x=\"" << num(lx + 22) << "\" y=\"" << num(ly) << "\">" << xml_escape(s.label) << "</text>\n";
    ly += 14;
  }
  o << "</svg>\n";
  return o.str();
}

// ---------------------------------------------------------------- bars

namespace {
constexpr double kBarLabel = 150, kBarRight = 90, kBarHeight = 18, kBarGap = 6, kBarTop = 26;
}

BarChart::BarChart(std::string title, std::string value_label)
    : title_(std::move(title)), value_label_(std::move(value_label)) {}

void BarChart::add(std::string label, double value, double behind) {
  bars_.push_back({std::move(label), value, behind});
}

double BarChart::max_value() const {
  double m = 0;
  for (const auto& b : bars_) m = std::max({m, b.value, b.behind});
  return m > 0 ? m : 1;
}

double BarChart::bar_length(double value, double width) const {
  return std::max(0.0, value) / max_value() * std::max(1.0, width - kBarLabel - kBarRight);
}

std::string BarChart::render(double width) const {
  const double height = kBarTop + bars_.size() * (kBarHeight + kBarGap) + 24;
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"" << num(width) << "\" height=\""
    << num(height) << "\" viewBox=\"0 0 " << num(width) << ' ' << num(height)
    << "\" font-family=\"sans-serif\" font-size=\"" << kFont << "\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << num(width / 2) << "\" y=\"16\" text-anchor=\"middle\" font-weight=\"bold\">"
    << xml_escape(title_) << "</text>\n";
  double y = kBarTop;
  for (const auto& b : bars_) {
    o << "<text x=\"" << num(kBarLabel - 6) << "\" y=\"" << num(y + kBarHeight - 5) << "\" text-anchor=\"end\">"
      << xml_escape(b.label) << "</text>\n";
    if (b.behind > 0)
      o << "<rect class=\"bar-behind\" x=\"" << num(kBarLabel) << "\" y=\"" << num(y) << "\" width=\""
        << num(bar_length(b.behind, width)) << "\" height=\"" << num(kBarHeight) << "\" fill=\"#c6dbef\"/>\n";
    const double len = bar_length(b.value, width);
    o << "<rect class=\"bar\" x=\"" << num(kBarLabel) << "\" y=\"" << num(y + 3) << "\" width=\"" << num(len)
      << "\" height=\"" << num(kBarHeight - 6) << "\" fill=\"#2171b5\"/>\n";
    char value[48];
    std::snprintf(value, sizeof value, "%.2f", b.value);
    o << "<text x=\"" << num(kBarLabel + std::max(len, bar_length(b.behind, width)) + 4) << "\" y=\""
      << num(y + kBarHeight - 5) << "\">" << value << "</text>\n";
    y += kBarHeight + kBarGap;
  }
  o << "<text x=\"" << num(kBarLabel) << "\" y=\"" << num(height - 6) << "\">" << xml_escape(value_label_)
    << "</text>\n</svg>\n";
  return o.str();
}

}  // namespace pllvo::report
