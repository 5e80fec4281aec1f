#pragma once
// Line and bar charts as standalone SVG text, drawn by pllvo itself so a report page needs no
// scripts and no network. A chart maps data coordinates into a plot area inside the SVG canvas;
// that mapping is public (and tested) because everything drawn goes through it.
#include <string>
#include <vector>

namespace pllvo::report {

/// Closed interval of data values on one axis.
struct Range {
  double min = 0, max = 1;
  double span() const { return max - min; }
};

/// The smallest range holding every finite value of every series; a degenerate range (one
/// value, or none) is widened so that it still maps to a finite scale.
Range data_range(const std::vector<std::vector<double>>& series);
/// `r` widened by `fraction` of its span on both sides.
Range padded(const Range& r, double fraction);

/// "Nice" tick values (steps of 1, 2 or 5 times a power of ten) inside `r`, about `target` of them.
std::vector<double> nice_ticks(const Range& r, int target = 5);
/// Tick label: as few digits as the step needs ("0.5", "10", "1e+03").
std::string tick_label(double value, double step);

/// Pixel rectangle of the plot area (SVG user units, y down).
struct PixelRect {
  double left = 0, top = 0, width = 0, height = 0;
  double right() const { return left + width; }
  double bottom() const { return top + height; }
};

/// Linear map data -> pixels: x grows to the right, y grows upwards in data and downwards in
/// pixels. With `equal_aspect` one data unit has the same length on both axes (trajectory
/// views); the larger of the two ranges decides and the other is centred.
class AxisMap {
 public:
  AxisMap(Range x, Range y, PixelRect area, bool equal_aspect = false);
  double px(double x) const { return area_.left + (x - x_.min) * sx_; }
  double py(double y) const { return area_.bottom() - (y - y_.min) * sy_; }
  const Range& x_range() const { return x_; }
  const Range& y_range() const { return y_; }
  const PixelRect& area() const { return area_; }

 private:
  Range x_, y_;
  PixelRect area_;
  double sx_ = 1, sy_ = 1;
};

struct Series {
  std::string label;
  std::string color;  ///< any SVG colour
  std::vector<double> x, y;
  bool dashed = false;
  double width = 1.5;
};

/// An x-y line chart: axes with ticks and labels, one polyline per series (NaN breaks a line),
/// legend in the top-right corner.
class LineChart {
 public:
  LineChart(std::string title, std::string x_label, std::string y_label);
  void add(Series s) { series_.push_back(std::move(s)); }
  void set_equal_aspect(bool on) { equal_aspect_ = on; }
  /// Names the chart's clip path; charts on one page need different ids.
  void set_id(std::string id) { id_ = std::move(id); }
  /// The map that render() uses for this canvas size (padding and margins included).
  AxisMap axis_map(double width, double height) const;
  std::string render(double width, double height) const;

 private:
  std::string title_, x_label_, y_label_;
  std::vector<Series> series_;
  bool equal_aspect_ = false;
  std::string id_ = "plot";
};

/// Horizontal bars, one per labelled value, with an optional second (lighter) value per bar
/// drawn behind it (e.g. p95 behind the mean).
class BarChart {
 public:
  BarChart(std::string title, std::string value_label);
  void add(std::string label, double value, double behind = 0);
  /// Pixel length of a bar of `value` for this canvas width.
  double bar_length(double value, double width) const;
  std::string render(double width) const;  ///< height follows from the number of bars

 private:
  struct Bar {
    std::string label;
    double value = 0, behind = 0;
  };
  double max_value() const;
  std::string title_, value_label_;
  std::vector<Bar> bars_;
};

/// `text` with &, <, >, " escaped for XML / HTML.
std::string xml_escape(const std::string& text);

}  // namespace pllvo::report
