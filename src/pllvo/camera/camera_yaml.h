#pragma once
// pllvo's camera calibration YAML (used for TUM, image folders and synthetic data):
//   model: pinhole                 # the only projection so far
//   width: 752
//   height: 480
//   fx: 458.654  fy: 457.296  cx: 367.215  cy: 248.375
//   distortion_model: radtan       # radtan | equidistant | none
//   distortion: [k1, k2, p1, p2, k3]   # radtan: 4 or 5 values; equidistant: k1..k4
// Extra keys (fps, depth_factor, ...) are allowed and ignored here.
#include <filesystem>

#include "pllvo/camera/camera_model.h"
#include "pllvo/common/yaml_config.h"

namespace pllvo::camera {

CameraPtr load_camera_yaml(const std::filesystem::path& file);
CameraPtr camera_from_yaml(const ConfigNode& node);
/// Builds a model from its distortion name ("radtan"/"radial-tangential", "equidistant"/
/// "kannala-brandt"/"fisheye", "none"); InputError for an unknown name.
CameraPtr make_camera(const std::string& distortion_model, int width, int height,
                      const PinholeIntrinsics& k, const std::vector<double>& distortion);
void save_camera_yaml(const CameraModel& camera, const std::filesystem::path& file);

}  // namespace pllvo::camera
