#include "pllvo/synth/radiance.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pllvo::synth {

namespace {

constexpr int kLightCell = 8;  // irradiance is smooth: evaluate every 8 texels, interpolate

/// Irradiance image of a quad at its texture's size.
cv::Mat irradiance_map(const Scene& scene, int state, const Quad& q, cv::Size size) {
  const int gw = std::max(2, size.width / kLightCell + 1), gh = std::max(2, size.height / kLightCell + 1);
  cv::Mat grid(gh, gw, CV_32F);
  const Eigen::Vector3d n = q.normal();
  for (int r = 0; r < gh; ++r)
    for (int c = 0; c < gw; ++c) {
      const Eigen::Vector3d x = q.point(static_cast<double>(c) / (gw - 1), static_cast<double>(r) / (gh - 1));
      grid.at<float>(r, c) = static_cast<float>(irradiance(scene, state, x, n));
    }
  cv::Mat out;
  cv::resize(grid, out, size, 0, 0, cv::INTER_LINEAR);
  return out;
}

cv::Mat quad_radiance(const Scene& scene, int state, size_t qi, double light_scale) {
  const Quad& q = scene.quads[qi];
  const Texture& tex = scene.textures[q.texture];
  if (tex.emissive && tex.emission[state] >= 0) return tex.image * tex.emission[state];
  cv::Mat E = irradiance_map(scene, state, q, tex.image.size());
  return tex.image.mul(E, light_scale);
}

MipTexture make_mips(const cv::Mat& radiance) {
  MipTexture m;
  double max_value = 0;
  cv::minMaxLoc(radiance, nullptr, &max_value);
  m.scale = static_cast<float>(std::max(max_value, 1e-6) / 65535.0);
  std::vector<cv::Mat> levels(1);
  radiance.convertTo(levels[0], CV_16U, 1.0 / m.scale);
  while (levels.back().cols > 1 || levels.back().rows > 1) {
    cv::Mat next;
    const cv::Mat& prev = levels.back();
    cv::resize(prev, next, cv::Size(std::max(1, prev.cols / 2), std::max(1, prev.rows / 2)), 0, 0, cv::INTER_AREA);
    levels.push_back(next);
  }
  int64_t total = 0;
  for (const auto& l : levels) total += static_cast<int64_t>(l.rows + 1) * (l.cols + 1);
  m.data.resize(total + 2);  // +2: a 32-bit read of the last texel pair stays inside
  int64_t offset = 0;
  for (const auto& l : levels) {
    MipLevel d{l.cols, l.rows, l.cols + 1, offset};
    cv::Mat padded(l.rows + 1, l.cols + 1, CV_16U, m.data.data() + offset);
    cv::copyMakeBorder(l, padded, 0, 1, 0, 1, cv::BORDER_REPLICATE);
    m.levels.push_back(d);
    offset += static_cast<int64_t>(l.rows + 1) * (l.cols + 1);
  }
  return m;
}

}  // namespace

cv::Mat MipTexture::level(size_t l) const {
  const MipLevel& d = levels.at(l);
  return cv::Mat(d.rows, d.cols, CV_16U, const_cast<uint16_t*>(data.data() + d.offset), d.step * sizeof(uint16_t))
      .clone();
}

double irradiance(const Scene& scene, int state, const Eigen::Vector3d& x, const Eigen::Vector3d& n) {
  double e = scene.ambient[state];
  for (const auto& light : scene.lights) {
    if (!light.on[state]) continue;
    const Eigen::Vector3d d = light.position - x;
    const double r2 = std::max(d.squaredNorm(), 0.05);
    const Eigen::Vector3d dn = d / std::sqrt(r2);
    double g = std::max(0.0, n.dot(dn));
    if (light.direction.squaredNorm() > 0) g *= std::max(0.0, -light.direction.dot(dn));
    e += light.power * g / r2;
  }
  return e;
}

double light_normalisation(const Scene& scene, double target) {
  double sum = 0, area = 0;
  for (const auto& q : scene.quads) {
    const Texture& tex = scene.textures[q.texture];
    if (tex.emissive) continue;
    // A coarse 8x8 sample of reflectance times irradiance is plenty for a mean.
    cv::Mat small;
    cv::resize(tex.image, small, cv::Size(8, 8), 0, 0, cv::INTER_AREA);
    double s = 0;
    for (int r = 0; r < 8; ++r)
      for (int c = 0; c < 8; ++c)
        s += small.at<float>(r, c) * irradiance(scene, 0, q.point((c + 0.5) / 8, (r + 0.5) / 8), q.normal());
    sum += s / 64 * q.area();
    area += q.area();
  }
  return sum > 0 ? target * area / sum : 1.0;
}

RadianceState bake_radiance(const Scene& scene, int state, double light_scale) {
  RadianceState out;
  out.quads.reserve(scene.quads.size());
  double sum = 0, area = 0;
  for (size_t qi = 0; qi < scene.quads.size(); ++qi) {
    const cv::Mat radiance = quad_radiance(scene, state, qi, light_scale);
    if (!scene.textures[scene.quads[qi].texture].emissive) {
      sum += cv::mean(radiance)[0] * scene.quads[qi].area();
      area += scene.quads[qi].area();
    }
    out.quads.push_back(make_mips(radiance));
  }
  out.mean_radiance = area > 0 ? sum / area : 0;
  return out;
}

}  // namespace pllvo::synth
