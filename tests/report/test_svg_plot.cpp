// SVG charts: the data -> pixel map (corners, flipped y, equal aspect), ticks, and that the
// rendered polylines and bars sit exactly where the map says.
#include <cmath>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "pllvo/report/svg_plot.h"

namespace pllvo::report {
namespace {

std::vector<std::pair<double, double>> polyline_points(const std::string& svg, size_t which = 0) {
  const std::regex poly("<polyline[^>]*points=\"([^\"]*)\"");
  auto it = std::sregex_iterator(svg.begin(), svg.end(), poly);
  for (size_t i = 0; i < which; ++i) ++it;
  EXPECT_NE(it, std::sregex_iterator());
  std::vector<std::pair<double, double>> out;
  const std::string pts = (*it)[1];
  const std::regex pair("([-0-9.]+),([-0-9.]+)");
  for (auto p = std::sregex_iterator(pts.begin(), pts.end(), pair); p != std::sregex_iterator(); ++p)
    out.push_back({std::stod((*p)[1]), std::stod((*p)[2])});
  return out;
}

TEST(AxisMap, MapsRangeCornersToAreaCornersWithYUp) {
  const AxisMap m({-1, 3}, {10, 20}, {50, 30, 400, 200});
  EXPECT_DOUBLE_EQ(m.px(-1), 50);
  EXPECT_DOUBLE_EQ(m.px(3), 450);
  EXPECT_DOUBLE_EQ(m.px(1), 250);
  EXPECT_DOUBLE_EQ(m.py(10), 230);  // bottom of the area
  EXPECT_DOUBLE_EQ(m.py(20), 30);   // top
  EXPECT_DOUBLE_EQ(m.py(12.5), 180);
}

TEST(AxisMap, EqualAspectUsesOneScaleAndCentresTheShorterAxis) {
  // 4 x 1 data units into a 400 x 400 area: 100 px per unit on both axes, y centred.
  const AxisMap m({0, 4}, {0, 1}, {0, 0, 400, 400}, true);
  EXPECT_DOUBLE_EQ(m.px(1) - m.px(0), 100);
  EXPECT_DOUBLE_EQ(m.py(0) - m.py(1), 100);
  EXPECT_DOUBLE_EQ(m.px(0), 0);
  EXPECT_DOUBLE_EQ(m.px(4), 400);
  EXPECT_DOUBLE_EQ(m.py(0.5), 200);  // data centre at the area centre
}

TEST(Ticks, NiceStepsInsideTheRange) {
  const auto t = nice_ticks({0.03, 0.97}, 5);
  ASSERT_EQ(t.size(), 4u);  // step 0.2: 0.2 0.4 0.6 0.8
  EXPECT_NEAR(t[0], 0.2, 1e-12);
  EXPECT_NEAR(t[1] - t[0], 0.2, 1e-12);
  const auto u = nice_ticks({-130, 470}, 6);
  EXPECT_NEAR(u[1] - u[0], 100, 1e-9);
  EXPECT_NEAR(u[0], -100, 1e-9);
  EXPECT_EQ(tick_label(0.4, 0.2), "0.4");
  EXPECT_EQ(tick_label(300, 100), "300");
}

TEST(DataRange, IgnoresNaNAndWidensDegenerateRanges) {
  const Range r = data_range({{1, NAN, 3}, {2, -2}});
  EXPECT_DOUBLE_EQ(r.min, -2);
  EXPECT_DOUBLE_EQ(r.max, 3);
  const Range d = data_range({{5, 5}});
  EXPECT_LT(d.min, 5);
  EXPECT_GT(d.max, 5);
  const Range e = data_range({});
  EXPECT_GT(e.span(), 0);
}

TEST(LineChart, PolylinePointsAreTheMappedData) {
  LineChart chart("t", "x", "y");
  chart.add({"a", "#ff0000", {0, 1, 2}, {0, 4, 2}});
  const std::string svg = chart.render(600, 300);
  const AxisMap m = chart.axis_map(600, 300);
  const auto pts = polyline_points(svg);
  ASSERT_EQ(pts.size(), 3u);
  const double xs[] = {0, 1, 2}, ys[] = {0, 4, 2};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(pts[i].first, m.px(xs[i]), 0.006);
    EXPECT_NEAR(pts[i].second, m.py(ys[i]), 0.006);
  }
  // Every point inside the plot area, the highest value highest on the page.
  for (const auto& p : pts) {
    EXPECT_GE(p.first, m.area().left - 1e-9);
    EXPECT_LE(p.first, m.area().right() + 1e-9);
    EXPECT_GE(p.second, m.area().top - 1e-9);
    EXPECT_LE(p.second, m.area().bottom() + 1e-9);
  }
  EXPECT_LT(pts[1].second, pts[2].second);
  EXPECT_LT(pts[2].second, pts[0].second);
}

TEST(LineChart, NaNBreaksTheLine) {
  LineChart chart("t", "x", "y");
  chart.add({"a", "red", {0, 1, 2, 3, 4}, {0, 1, NAN, 3, 4}});
  const std::string svg = chart.render(400, 300);
  EXPECT_EQ(polyline_points(svg, 0).size(), 2u);
  EXPECT_EQ(polyline_points(svg, 1).size(), 2u);
}

TEST(LineChart, EqualAspectTrajectoryKeepsACircleRound) {
  LineChart chart("top", "x", "y");
  chart.set_equal_aspect(true);
  std::vector<double> x, y;
  for (int i = 0; i <= 64; ++i) x.push_back(3 * std::cos(i * M_PI / 32)), y.push_back(3 * std::sin(i * M_PI / 32));
  chart.add({"c", "red", x, y});
  const auto pts = polyline_points(chart.render(600, 300));
  double minx = 1e9, maxx = -1e9, miny = 1e9, maxy = -1e9;
  for (const auto& p : pts)
    minx = std::min(minx, p.first), maxx = std::max(maxx, p.first), miny = std::min(miny, p.second),
    maxy = std::max(maxy, p.second);
  EXPECT_NEAR(maxx - minx, maxy - miny, 0.05);  // as wide as high on the page
  EXPECT_GT(maxx - minx, 100);
}

TEST(BarChart, BarLengthsAreProportional) {
  BarChart chart("timing", "ms");
  chart.add("a", 10, 20);
  chart.add("b", 5);
  const double full = chart.bar_length(20, 800);
  EXPECT_NEAR(chart.bar_length(10, 800), full / 2, 1e-9);
  EXPECT_NEAR(chart.bar_length(5, 800), full / 4, 1e-9);
  const std::string svg = chart.render(800);
  const std::regex bar("class=\"bar\" x=\"[-0-9.]+\" y=\"[-0-9.]+\" width=\"([-0-9.]+)\"");
  std::vector<double> widths;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator(); ++it)
    widths.push_back(std::stod((*it)[1]));
  ASSERT_EQ(widths.size(), 2u);
  EXPECT_NEAR(widths[0], full / 2, 0.006);
  EXPECT_NEAR(widths[1], full / 4, 0.006);
}

TEST(Svg, EscapesText) {
  EXPECT_EQ(xml_escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
  LineChart chart("x < y", "", "");
  EXPECT_NE(chart.render(200, 200).find("x &lt; y"), std::string::npos);
}

}  // namespace
}  // namespace pllvo::report
