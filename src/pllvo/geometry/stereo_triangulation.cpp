#include "pllvo/geometry/stereo_triangulation.h"

#include <algorithm>
#include <cmath>

namespace pllvo::geometry {

const char* to_string(StereoStatus status) {
  switch (status) {
    case StereoStatus::kOk: return "ok";
    case StereoStatus::kEpipolar: return "off the epipolar line";
    case StereoStatus::kSmallDisparity: return "small disparity";
    case StereoStatus::kLargeDisparity: return "large disparity";
    case StereoStatus::kTooClose: return "too close";
    case StereoStatus::kTooFar: return "too far";
  }
  return "?";
}

void StereoTriangulationConfig::load(const ConfigNode& node) {
  node.get("max_epipolar_error_px", max_epipolar_error_px);
  node.get("min_disparity_px", min_disparity_px);
  node.get("max_disparity_px", max_disparity_px);
  node.get("min_depth", min_depth);
  node.get("max_depth", max_depth);
  node.reject_unknown_keys();
}

StereoPoint triangulate_stereo(const Eigen::Vector2d& uv_left, const Eigen::Vector2d& uv_right,
                               const camera::PinholeIntrinsics& K, double baseline,
                               const StereoTriangulationConfig& config) {
  StereoPoint out;
  out.disparity_px = uv_left.x() - uv_right.x();
  if (!(std::abs(uv_left.y() - uv_right.y()) <= config.max_epipolar_error_px)) {
    out.status = StereoStatus::kEpipolar;
    return out;
  }
  if (!(out.disparity_px >= config.min_disparity_px) || !(out.disparity_px > 0)) {
    out.status = StereoStatus::kSmallDisparity;
    return out;
  }
  if (config.max_disparity_px > 0 && out.disparity_px > config.max_disparity_px) {
    out.status = StereoStatus::kLargeDisparity;
    return out;
  }
  const double z = K.fx * baseline / out.disparity_px;
  if (z < config.min_depth) {
    out.status = StereoStatus::kTooClose;
    return out;
  }
  if (config.max_depth > 0 && z > config.max_depth) {
    out.status = StereoStatus::kTooFar;
    return out;
  }
  // The row is measured in both images; their mean halves its noise.
  const double v = 0.5 * (uv_left.y() + uv_right.y());
  out.p_left << (uv_left.x() - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z;
  out.status = StereoStatus::kOk;
  return out;
}

std::vector<StereoPoint> triangulate_stereo(std::span<const Eigen::Vector2d> uv_left,
                                            std::span<const Eigen::Vector2d> uv_right,
                                            const camera::PinholeIntrinsics& K, double baseline,
                                            const StereoTriangulationConfig& config) {
  std::vector<StereoPoint> out(std::min(uv_left.size(), uv_right.size()));
  for (size_t i = 0; i < out.size(); ++i) out[i] = triangulate_stereo(uv_left[i], uv_right[i], K, baseline, config);
  return out;
}

}  // namespace pllvo::geometry
