#pragma once
// Camera projection models. Points are in the camera frame (x right, y down, z forward);
// pixels follow OpenCV's convention (centre of the top-left pixel at (0, 0)).
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>
#include <opencv2/core.hpp>

namespace pllvo::camera {

/// Pinhole intrinsics of an ideal (distortion-free) camera.
struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix3d K() const;
};

class CameraModel {
 public:
  CameraModel(int width, int height, PinholeIntrinsics intrinsics);
  virtual ~CameraModel() = default;

  int width() const { return width_; }
  int height() const { return height_; }
  const PinholeIntrinsics& intrinsics() const { return intrinsics_; }

  /// "pinhole-radtan" or "kannala-brandt".
  virtual std::string name() const = 0;
  /// Distortion coefficients in the model's published order.
  virtual std::vector<double> distortion() const = 0;

  /// Projects a 3-D point; false when it cannot be imaged (behind the camera, or
  /// outside the model's valid domain). `J` (2x3, d pixel / d point) is filled on success.
  virtual bool project(const Eigen::Vector3d& p, Eigen::Vector2d& uv,
                       Eigen::Matrix<double, 2, 3>* J = nullptr) const = 0;

  /// Unit-norm bearing of a pixel; false when the iterative inversion does not converge.
  virtual bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const = 0;

  bool in_image(const Eigen::Vector2d& uv, double border = 0.0) const;

  /// Distortion-free pixel coordinates under `target` (default: this camera's own K).
  /// Points that cannot be undistorted come back as NaN.
  std::vector<Eigen::Vector2d> undistort_points(const std::vector<Eigen::Vector2d>& pixels,
                                                const PinholeIntrinsics* target = nullptr) const;

  /// remap() tables that turn an image of this camera into an ideal pinhole image
  /// (size and intrinsics `target`, optional rotation R_target_cam of the new view).
  void undistort_rectify_map(const PinholeIntrinsics& target, cv::Size size,
                             const Eigen::Matrix3d& R_target_cam, cv::Mat& map_x,
                             cv::Mat& map_y) const;

  cv::Mat undistort_image(const cv::Mat& image, const PinholeIntrinsics* target = nullptr) const;

 protected:
  int width_, height_;
  PinholeIntrinsics intrinsics_;
};

using CameraPtr = std::shared_ptr<const CameraModel>;

/// Pinhole with radial-tangential distortion (OpenCV / Kalibr "radtan": k1 k2 p1 p2 [k3]).
class PinholeRadtan final : public CameraModel {
 public:
  PinholeRadtan(int width, int height, PinholeIntrinsics intrinsics,
                std::vector<double> distortion = {});
  std::string name() const override { return "pinhole-radtan"; }
  std::vector<double> distortion() const override;
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d& uv,
               Eigen::Matrix<double, 2, 3>* J = nullptr) const override;
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const override;

  /// Distorts normalised coordinates; `J` = d distorted / d undistorted.
  Eigen::Vector2d distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J = nullptr) const;

 private:
  double k1_ = 0, k2_ = 0, p1_ = 0, p2_ = 0, k3_ = 0;
};

/// Equidistant / Kannala-Brandt fisheye (OpenCV fisheye, Kalibr "equidistant": k1..k4).
class KannalaBrandt final : public CameraModel {
 public:
  KannalaBrandt(int width, int height, PinholeIntrinsics intrinsics, std::vector<double> k);
  std::string name() const override { return "kannala-brandt"; }
  std::vector<double> distortion() const override { return {k_[0], k_[1], k_[2], k_[3]}; }
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d& uv,
               Eigen::Matrix<double, 2, 3>* J = nullptr) const override;
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const override;

 private:
  double theta_d(double theta, double* dtheta_d = nullptr) const;
  double k_[4];
};

}  // namespace pllvo::camera
