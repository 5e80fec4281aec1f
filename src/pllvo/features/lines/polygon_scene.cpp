#include "pllvo/features/lines/polygon_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::lines {

namespace {
struct Polygon {
  std::vector<Eigen::Vector2d> vertices;  // image coordinates, convex; an ellipse has none
  Eigen::Vector2d centre;
  double radius;
  double ellipse_ratio = 0.0;  // minor/major axis of an ellipse
  double ellipse_angle = 0.0;
};

Polygon random_polygon(std::mt19937_64& rng, const PolygonSceneConfig& c) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double radius = 0.5 * (c.min_size_px + (c.max_size_px - c.min_size_px) * u01(rng));
  Polygon p;
  p.radius = radius;
  p.centre = {radius + 3 + u01(rng) * (c.width - 2 * radius - 6), radius + 3 + u01(rng) * (c.height - 2 * radius - 6)};
  const double rot = u01(rng) * 2 * M_PI;
  const int kind = static_cast<int>(u01(rng) * 3);
  std::vector<double> angles;
  if (kind == 0) {  // rectangle with a random aspect: vertices on the circle, symmetric
    const double half = 0.25 * M_PI + (u01(rng) - 0.5) * 0.6;
    angles = {half, M_PI - half, M_PI + half, 2 * M_PI - half};
  } else {  // triangle or quadrilateral with well-separated vertices (no sliver edges)
    const int n = kind == 1 ? 3 : 4;
    for (int i = 0; i < n; ++i) angles.push_back((i + 0.25 + 0.5 * u01(rng)) * 2 * M_PI / n);
  }
  for (double a : angles)
    p.vertices.push_back(p.centre + radius * Eigen::Vector2d(std::cos(a + rot), std::sin(a + rot)));
  return p;
}

// Smooth random field with the given amplitude (bicubic upsampling of coarse noise).
cv::Mat smooth_texture(std::mt19937_64& rng, int width, int height, double amplitude, int cell) {
  cv::Mat coarse(height / cell + 3, width / cell + 3, CV_32F);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int y = 0; y < coarse.rows; ++y)
    for (int x = 0; x < coarse.cols; ++x) coarse.at<float>(y, x) = u(rng) * static_cast<float>(amplitude);
  cv::Mat fine;
  cv::resize(coarse, fine, cv::Size(coarse.cols * cell, coarse.rows * cell), 0, 0, cv::INTER_CUBIC);
  return fine(cv::Rect(cell, cell, width, height)).clone();
}
}  // namespace

PolygonScene render_polygon_scene(const PolygonSceneConfig& c) {
  if (c.width < 64 || c.height < 64 || c.supersample < 1)
    throw InputError("polygon scene: image must be at least 64x64 and supersample >= 1");
  std::mt19937_64 rng(c.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);

  // Place polygons whose bounding circles keep a margin, so no edge is occluded.
  std::vector<Polygon> polys;
  for (int attempt = 0; attempt < 2000 && static_cast<int>(polys.size()) < c.num_polygons; ++attempt) {
    Polygon p = random_polygon(rng, c);
    bool free = true;
    for (const auto& q : polys)
      if ((p.centre - q.centre).norm() < p.radius + q.radius + 12.0) free = false;
    if (free) polys.push_back(std::move(p));
  }
  // Ellipses in the remaining free space.
  const size_t num_true = polys.size();
  for (int attempt = 0; attempt < 2000 && static_cast<int>(polys.size() - num_true) < c.num_ellipses; ++attempt) {
    Polygon e = random_polygon(rng, c);
    e.vertices.clear();
    e.ellipse_ratio = 0.4 + 0.6 * u01(rng);
    e.ellipse_angle = 180.0 * u01(rng);
    bool free = true;
    for (const auto& q : polys)
      if ((e.centre - q.centre).norm() < e.radius + q.radius + 12.0) free = false;
    if (free) polys.push_back(std::move(e));
  }

  // Each polygon is rendered at S x resolution inside its bounding box and area-averaged down,
  // giving its coverage of every pixel. A point x of the final image lies at (x + 0.5) S - 0.5
  // in the supersampled box.
  const int S = c.supersample;
  constexpr int kShift = 4;
  const double bg_level = 90.0 + 60.0 * u01(rng);
  cv::Mat image = bg_level + smooth_texture(rng, c.width, c.height, c.background_texture, 24) +
                  smooth_texture(rng, c.width, c.height, c.fine_texture, 4);
  const cv::Mat fg_texture = 0.5 * smooth_texture(rng, c.width, c.height, c.background_texture, 16);
  for (const auto& poly : polys) {
    double level;
    do {
      level = 20.0 + 215.0 * u01(rng);
    } while (std::abs(level - bg_level) < c.min_contrast);
    double xmin = poly.centre.x() - poly.radius, ymin = poly.centre.y() - poly.radius;
    double xmax = poly.centre.x() + poly.radius, ymax = poly.centre.y() + poly.radius;
    for (const auto& v : poly.vertices) {
      xmin = std::min(xmin, v.x()), ymin = std::min(ymin, v.y());
      xmax = std::max(xmax, v.x()), ymax = std::max(ymax, v.y());
    }
    const cv::Rect box = cv::Rect(cv::Point(static_cast<int>(std::floor(xmin)) - 2, static_cast<int>(std::floor(ymin)) - 2),
                                  cv::Point(static_cast<int>(std::ceil(xmax)) + 3, static_cast<int>(std::ceil(ymax)) + 3)) &
                         cv::Rect(0, 0, c.width, c.height);
    cv::Mat hi(box.height * S, box.width * S, CV_8UC1, cv::Scalar(0));
    std::vector<cv::Point> pts;
    for (const auto& v : poly.vertices) {
      const double hx = (v.x() - box.x + 0.5) * S - 0.5, hy = (v.y() - box.y + 0.5) * S - 0.5;
      pts.emplace_back(static_cast<int>(std::lround(hx * (1 << kShift))),
                       static_cast<int>(std::lround(hy * (1 << kShift))));
    }
    if (poly.vertices.empty()) {
      const cv::Point centre(static_cast<int>(std::lround(((poly.centre.x() - box.x + 0.5) * S - 0.5) * (1 << kShift))),
                             static_cast<int>(std::lround(((poly.centre.y() - box.y + 0.5) * S - 0.5) * (1 << kShift))));
      const int major = static_cast<int>(poly.radius * S * (1 << kShift));
      cv::ellipse(hi, centre, cv::Size(major, static_cast<int>(major * poly.ellipse_ratio)), poly.ellipse_angle, 0, 360,
                  cv::Scalar(255), cv::FILLED, cv::LINE_8, kShift);
    } else {
      cv::fillConvexPoly(hi, pts, cv::Scalar(255), cv::LINE_8, kShift);
    }
    cv::Mat cover;
    hi.convertTo(cover, CV_32F, 1.0 / 255.0);
    cv::resize(cover, cover, box.size(), 0, 0, cv::INTER_AREA);
    cv::Mat roi = image(box);
    const cv::Mat inside = level + fg_texture(box);
    roi = roi.mul(1.0f - cover) + inside.mul(cover);
    roi.copyTo(image(box));
  }
  image *= c.brightness;
  cv::Mat noise(c.height, c.width, CV_32F);
  cv::RNG cvrng(static_cast<uint64>(c.seed * 7919 + 17));
  cvrng.fill(noise, cv::RNG::NORMAL, 0.0, c.noise_sigma);
  image += noise;

  PolygonScene scene;
  image.convertTo(scene.image, CV_8U);
  for (const auto& p : polys)
    for (size_t k = 0; k < p.vertices.size(); ++k)
      scene.truth.emplace_back(p.vertices[k], p.vertices[(k + 1) % p.vertices.size()],
                               static_cast<int>(scene.truth.size()));
  return scene;
}

std::vector<PolygonScene> polygon_suite(const std::string& lighting, int frames, int width, int height) {
  PolygonSceneConfig c;
  c.width = width;
  c.height = height;
  if (lighting == "normal") {
  } else if (lighting == "dark") {
    c.brightness = 0.12;
    c.noise_sigma = 1.5;
  } else if (lighting == "noisy") {
    c.noise_sigma = 8.0;
  } else {
    throw InputError("polygon suite: unknown lighting '" + lighting + "' (expected normal, dark or noisy)");
  }
  std::vector<PolygonScene> scenes;
  for (int i = 0; i < frames; ++i) {
    c.seed = static_cast<uint64_t>(i + 1);
    scenes.push_back(render_polygon_scene(c));
  }
  return scenes;
}

}  // namespace pllvo::lines
