#pragma once
// Conversion between a camera's pixels and the undistorted normalised image coordinates
// that geometry/ and backend/ work in (distortion is removed once, per feature, so every
// solver sees a distortion-free pinhole and 3-D lines project to straight lines).
#include <vector>

#include <Eigen/Core>

#include "pllvo/camera/camera_model.h"

namespace pllvo::geometry {

/// Pixels per normalised unit, (fx + fy) / 2: converts pixel thresholds to normalised units.
double pixel_scale(const camera::CameraModel& camera);

/// Normalised coordinates (X/Z, Y/Z) of a pixel; false when the camera cannot unproject it or
/// its ray points backwards.
bool pixel_to_normalised(const camera::CameraModel& camera, const Eigen::Vector2d& uv,
                         Eigen::Vector2d& xy);

/// Normalised coordinates of many pixels; failures come back as NaN.
std::vector<Eigen::Vector2d> pixels_to_normalised(const camera::CameraModel& camera,
                                                  const std::vector<Eigen::Vector2d>& uv);

}  // namespace pllvo::geometry
