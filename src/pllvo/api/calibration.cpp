#include "pllvo/api/calibration.h"

#include <cmath>


#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/io/calibration_file.h"
#include "pllvo/io/sequence.h"

namespace pllvo {
namespace {

camera::CameraPtr make_checked_camera(const CameraIntrinsics& c, const char* which) {
  const std::string name = std::string("calibration, ") + which + " camera";
  if (c.width <= 0 || c.height <= 0)
    throw InputError(name + ": width and height must be positive (got " + std::to_string(c.width) + "x" +
                     std::to_string(c.height) + ")");
  for (double v : {c.fx, c.fy, c.cx, c.cy})
    if (!std::isfinite(v)) throw InputError(name + ": fx, fy, cx, cy must be finite numbers");
  if (!(c.fx > 0) || !(c.fy > 0)) throw InputError(name + ": fx and fy must be positive");
  for (double v : c.distortion)
    if (!std::isfinite(v)) throw InputError(name + ": the distortion coefficients must be finite numbers");
  camera::PinholeIntrinsics k;
  k.fx = c.fx;
  k.fy = c.fy;
  k.cx = c.cx;
  k.cy = c.cy;
  return camera::make_camera(c.distortion_model, c.width, c.height, k, c.distortion);
}

}  // namespace

Calibration::Calibration(std::shared_ptr<const io::Calibration> calibration) : calibration_(std::move(calibration)) {
  if (!calibration_ || !calibration_->cam0) throw InputError("calibration: no camera");
}

Calibration Calibration::load(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "calibration: no such file or folder");
  auto c = std::make_shared<io::Calibration>();
  if (std::filesystem::is_directory(path)) {
    *c = io::open_sequence(path)->calibration();
  } else {
    *c = io::load_calibration_file(path);
  }
  return Calibration(std::move(c));
}

Calibration Calibration::mono(const CameraIntrinsics& camera) {
  auto c = std::make_shared<io::Calibration>();
  c->cam0 = make_checked_camera(camera, "left");
  return Calibration(std::move(c));
}

Calibration Calibration::stereo_pair(const CameraIntrinsics& left, const CameraIntrinsics& right,
                                     const Eigen::Isometry3d& T_left_right) {
  if (!T_left_right.matrix().allFinite()) throw InputError("calibration: T_left_right must be finite");
  auto c = std::make_shared<io::Calibration>();
  c->cam0 = make_checked_camera(left, "left");
  c->cam1 = make_checked_camera(right, "right");
  c->T_body_cam1 = T_left_right;
  if (!(c->baseline() > 0)) throw InputError("calibration: the two cameras of a stereo pair must not coincide");
  return Calibration(std::move(c));
}

bool Calibration::stereo() const { return calibration_->stereo(); }
int Calibration::width() const { return calibration_->cam0->width(); }
int Calibration::height() const { return calibration_->cam0->height(); }
double Calibration::baseline() const { return calibration_->baseline(); }

Calibration Calibration::left_only() const {
  auto c = std::make_shared<io::Calibration>(*calibration_);
  c->cam1.reset();
  return Calibration(std::move(c));
}

Calibration Calibration::with_depth(double units_per_metre) const {
  if (!std::isfinite(units_per_metre) || units_per_metre <= 0)
    throw InputError("Calibration::with_depth: units_per_metre must be positive and finite, got " +
                     std::to_string(units_per_metre));
  auto c = std::make_shared<io::Calibration>(*calibration_);
  c->depth_factor = units_per_metre;
  return Calibration(std::move(c));
}

bool Calibration::depth() const { return calibration_->has_depth(); }
double Calibration::depth_units_per_metre() const { return calibration_->depth_factor; }

}  // namespace pllvo
