#include "pllvo/features/lines/polygon_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::lines {

namespace {
struct Shape {
  std::vector<Eigen::Vector2d> vertices;  // image coordinates, convex; an ellipse has none
  Eigen::Vector2d centre;
  double radius = 0.0;
  double ellipse_ratio = 0.0;  // minor/major axis of an ellipse
  double ellipse_angle = 0.0;  // degrees
  double level = 0.0;          // grey level at brightness 1
};

// Everything random about a scene, drawn once so a sequence can re-render it moved.
struct Layout {
  std::vector<Shape> shapes;
  double bg_level = 0.0;
  cv::Mat bg_texture, fg_texture;  // CV_32F, frame-0 coordinates
};

Shape random_shape(std::mt19937_64& rng, const PolygonSceneConfig& c) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Shape p;
  p.radius = 0.5 * (c.min_size_px + (c.max_size_px - c.min_size_px) * u01(rng));
  p.centre = {p.radius + 3 + u01(rng) * (c.width - 2 * p.radius - 6),
              p.radius + 3 + u01(rng) * (c.height - 2 * p.radius - 6)};
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
  for (double a : angles) p.vertices.push_back(p.centre + p.radius * Eigen::Vector2d(std::cos(a + rot), std::sin(a + rot)));
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

Layout make_layout(const PolygonSceneConfig& c) {
  if (c.width < 64 || c.height < 64 || c.supersample < 1)
    throw InputError("polygon scene: image must be at least 64x64 and supersample >= 1");
  std::mt19937_64 rng(c.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Layout layout;
  // Bounding circles keep a margin, so no edge is occluded; ellipses go in the space left.
  auto place = [&](int wanted, bool ellipse) {
    int placed = 0;
    for (int attempt = 0; attempt < 2000 && placed < wanted; ++attempt) {
      Shape p = random_shape(rng, c);
      if (ellipse) {
        p.vertices.clear();
        p.ellipse_ratio = 0.4 + 0.6 * u01(rng);
        p.ellipse_angle = 180.0 * u01(rng);
      }
      bool free = true;
      for (const auto& q : layout.shapes)
        if ((p.centre - q.centre).norm() < p.radius + q.radius + 12.0) free = false;
      if (free) layout.shapes.push_back(std::move(p)), ++placed;
    }
  };
  place(c.num_polygons, false);
  place(c.num_ellipses, true);
  layout.bg_level = 90.0 + 60.0 * u01(rng);
  layout.bg_texture = smooth_texture(rng, c.width, c.height, c.background_texture, 24) +
                      smooth_texture(rng, c.width, c.height, c.fine_texture, 4);
  layout.fg_texture = 0.5 * smooth_texture(rng, c.width, c.height, c.background_texture, 16);
  for (auto& s : layout.shapes) {
    do {
      s.level = 20.0 + 215.0 * u01(rng);
    } while (std::abs(s.level - layout.bg_level) < c.min_contrast);
  }
  return layout;
}

cv::Mat moved_texture(const cv::Mat& texture, const Eigen::Isometry2d& motion) {
  if (motion.isApprox(Eigen::Isometry2d::Identity())) return texture;
  const Eigen::Matrix<double, 2, 3> m = motion.matrix().topRows<2>();
  const cv::Mat M = (cv::Mat_<double>(2, 3) << m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2));
  cv::Mat out;
  cv::warpAffine(texture, out, M, texture.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return out;
}

// Each shape is rendered at S x resolution inside its bounding box and area-averaged down,
// giving its coverage of every pixel. A point x of the final image lies at (x + 0.5) S - 0.5
// in the supersampled box.
PolygonScene render(const Layout& layout, const PolygonSceneConfig& c, const Eigen::Isometry2d& motion,
                    uint64_t noise_seed) {
  const int S = c.supersample;
  constexpr int kShift = 4;
  const cv::Rect frame(0, 0, c.width, c.height);
  const double rot_deg = std::atan2(motion.linear()(1, 0), motion.linear()(0, 0)) * 180.0 / M_PI;
  cv::Mat image = layout.bg_level + moved_texture(layout.bg_texture, motion);
  const cv::Mat fg_texture = moved_texture(layout.fg_texture, motion);
  auto fixed_point = [&](const Eigen::Vector2d& v, const cv::Rect& box) {
    const double hx = (v.x() - box.x + 0.5) * S - 0.5, hy = (v.y() - box.y + 0.5) * S - 0.5;
    return cv::Point(static_cast<int>(std::lround(hx * (1 << kShift))), static_cast<int>(std::lround(hy * (1 << kShift))));
  };
  PolygonScene scene;
  int edge_id = 0;
  for (const auto& shape : layout.shapes) {
    const Eigen::Vector2d centre = motion * shape.centre;
    std::vector<Eigen::Vector2d> verts;
    for (const auto& v : shape.vertices) verts.push_back(motion * v);
    for (size_t k = 0; k < verts.size(); ++k, ++edge_id) {
      LineSegment edge(verts[k], verts[(k + 1) % verts.size()], edge_id);
      if (clip_to_rect(edge, {-0.5, -0.5}, {c.width - 0.5, c.height - 0.5}) && edge.length() > 0.0)
        scene.truth.push_back(edge);
    }
    const cv::Rect box = cv::Rect(cv::Point(static_cast<int>(std::floor(centre.x() - shape.radius)) - 2,
                                            static_cast<int>(std::floor(centre.y() - shape.radius)) - 2),
                                  cv::Point(static_cast<int>(std::ceil(centre.x() + shape.radius)) + 3,
                                            static_cast<int>(std::ceil(centre.y() + shape.radius)) + 3)) &
                         frame;
    if (box.area() == 0) continue;
    cv::Mat hi(box.height * S, box.width * S, CV_8UC1, cv::Scalar(0));
    if (verts.empty()) {
      const int major = static_cast<int>(shape.radius * S * (1 << kShift));
      cv::ellipse(hi, fixed_point(centre, box), cv::Size(major, static_cast<int>(major * shape.ellipse_ratio)),
                  shape.ellipse_angle + rot_deg, 0, 360, cv::Scalar(255), cv::FILLED, cv::LINE_8, kShift);
    } else {
      std::vector<cv::Point> pts;
      for (const auto& v : verts) pts.push_back(fixed_point(v, box));
      cv::fillConvexPoly(hi, pts, cv::Scalar(255), cv::LINE_8, kShift);
    }
    cv::Mat cover;
    hi.convertTo(cover, CV_32F, 1.0 / 255.0);
    cv::resize(cover, cover, box.size(), 0, 0, cv::INTER_AREA);
    const cv::Mat inside = shape.level + fg_texture(box);
    cv::Mat blended = image(box).mul(1.0f - cover) + inside.mul(cover);
    blended.copyTo(image(box));
  }
  image *= c.brightness;
  cv::Mat noise(c.height, c.width, CV_32F);
  cv::RNG(noise_seed).fill(noise, cv::RNG::NORMAL, 0.0, c.noise_sigma);
  image += noise;
  image.convertTo(scene.image, CV_8U);
  return scene;
}
}  // namespace

PolygonScene render_polygon_scene(const PolygonSceneConfig& c) {
  return render(make_layout(c), c, Eigen::Isometry2d::Identity(), c.seed * 7919 + 17);
}

PolygonSequence render_polygon_sequence(const PolygonSceneConfig& c, const std::vector<Eigen::Isometry2d>& motions) {
  const Layout layout = make_layout(c);
  PolygonSequence seq;
  seq.motions = motions;
  for (size_t k = 0; k < motions.size(); ++k)
    seq.frames.push_back(render(layout, c, motions[k], c.seed * 7919 + 17 + k * 104729));
  return seq;
}

PolygonSceneConfig polygon_lighting(const std::string& lighting, int width, int height) {
  PolygonSceneConfig c;
  c.width = width;
  c.height = height;
  if (lighting == "normal") return c;
  if (lighting == "dark") {
    c.brightness = 0.12;
    c.noise_sigma = 1.5;
    return c;
  }
  if (lighting == "noisy") {
    c.noise_sigma = 8.0;
    return c;
  }
  throw InputError("polygon scenes: unknown lighting '" + lighting + "' (expected normal, dark or noisy)");
}

std::vector<PolygonScene> polygon_suite(const std::string& lighting, int frames, int width, int height) {
  PolygonSceneConfig c = polygon_lighting(lighting, width, height);
  std::vector<PolygonScene> scenes;
  for (int i = 0; i < frames; ++i) {
    c.seed = static_cast<uint64_t>(i + 1);
    scenes.push_back(render_polygon_scene(c));
  }
  return scenes;
}

PolygonSequence polygon_tracking_sequence(const std::string& lighting, int frames, double deg_per_frame,
                                          Eigen::Vector2d shift_per_frame, uint64_t seed) {
  PolygonSceneConfig c = polygon_lighting(lighting);
  c.seed = seed;
  const Eigen::Vector2d centre(c.width / 2.0, c.height / 2.0);
  std::vector<Eigen::Isometry2d> motions;
  for (int k = 0; k < frames; ++k) {
    Eigen::Isometry2d m = Eigen::Isometry2d::Identity();
    m.translate(centre + k * shift_per_frame);
    m.rotate(k * deg_per_frame * M_PI / 180.0);
    m.translate(-centre);
    motions.push_back(m);
  }
  return render_polygon_sequence(c, motions);
}

}  // namespace pllvo::lines
