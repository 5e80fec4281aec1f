#pragma once
// pllvo's library API: the camera calibration an odometry is built from.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace pllvo {

namespace io {
struct Calibration;
}

/// One camera: pinhole intrinsics and lens distortion, for images of width x height pixels.
struct CameraIntrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  /// "none", "radtan" (k1 k2 p1 p2 [k3]) or "equidistant" (Kannala-Brandt k1..k4).
  std::string distortion_model = "none";
  std::vector<double> distortion;
};

/// A mono camera or a stereo pair. Cheap to copy (shared, immutable).
class Calibration {
 public:
  /// Reads any calibration pllvo reads: a dataset folder (EuRoC ASL, KITTI odometry, TUM RGB-D
  /// or image folder with its camera.yaml; stereo when the dataset has two cameras), pllvo's
  /// camera YAML (docs/datasets.md), a EuRoC sensor.yaml, OpenCV's calibration output
  /// (camera_matrix, distortion_coefficients) or a Kalibr camchain (a stereo pair with cam1).
  /// InputError naming the file and key.
  static Calibration load(const std::filesystem::path& path);
  /// InputError for a size or focal length that is not positive or any value that is not finite.
  static Calibration mono(const CameraIntrinsics& camera);
  /// `T_left_right`: the right camera's pose in the left camera's frame (KITTI-style rectified
  /// pair: identity rotation, translation (baseline, 0, 0)).
  static Calibration stereo_pair(const CameraIntrinsics& left, const CameraIntrinsics& right,
                                 const Eigen::Isometry3d& T_left_right);

  bool stereo() const;
  int width() const;
  int height() const;
  double baseline() const;  ///< metres between the optical centres; 0 for mono
  /// The same calibration with the second camera left out.
  Calibration left_only() const;
  /// RGB-D: the same calibration with depth images registered to the (left) camera; their 16-bit
  /// values hold `units_per_metre` per metre (TUM 5000, millimetres 1000), float images are metres.
  /// load() of a dataset with depth images already has it. InputError unless positive and finite.
  Calibration with_depth(double units_per_metre) const;
  bool depth() const;
  double depth_units_per_metre() const;  ///< 0 without depth

  const io::Calibration& internal() const { return *calibration_; }
  explicit Calibration(std::shared_ptr<const io::Calibration> calibration);

 private:
  std::shared_ptr<const io::Calibration> calibration_;
};

}  // namespace pllvo
