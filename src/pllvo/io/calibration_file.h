#pragma once
// Calibration files a user brings: pllvo's camera YAML (camera/camera_yaml.h), a EuRoC
// sensor.yaml, OpenCV's calibration output (cv::FileStorage: image_width, image_height,
// camera_matrix, distortion_coefficients), or a Kalibr camchain (cam0 and optionally cam1 with
// T_cn_cnm1: a stereo pair). `pllvo calibrate` writes pllvo's YAML for one camera and a Kalibr
// camchain for a pair.
#include <filesystem>

#include <Eigen/Geometry>

#include "pllvo/camera/camera_model.h"
#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// Reads any of the formats above, told apart by their keys. InputError naming the file and key.
Calibration load_calibration_file(const std::filesystem::path& file);

/// A Kalibr camchain for cam0 alone or a pair (cam1 with T_cn_cnm1 = T_right_left).
void save_kalibr_camchain(const camera::CameraModel& cam0, const camera::CameraModel* cam1,
                          const Eigen::Isometry3d& T_left_right, const std::filesystem::path& file);

}  // namespace pllvo::io
