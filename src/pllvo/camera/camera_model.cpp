#include "pllvo/camera/camera_model.h"

#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::camera {

namespace {
constexpr double kMinDepth = 1e-9;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_intrinsics(int width, int height, const PinholeIntrinsics& k) {
  if (width <= 0 || height <= 0) throw InputError("camera: image size must be positive");
  for (double v : {k.fx, k.fy, k.cx, k.cy})
    if (!std::isfinite(v)) throw InputError("camera: intrinsics must be finite");
  if (k.fx <= 0 || k.fy <= 0) throw InputError("camera: focal lengths must be positive");
}
}  // namespace

Eigen::Matrix3d PinholeIntrinsics::K() const {
  Eigen::Matrix3d K;
  K << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return K;
}

CameraModel::CameraModel(int width, int height, PinholeIntrinsics intrinsics)
    : width_(width), height_(height), intrinsics_(intrinsics) {
  check_intrinsics(width, height, intrinsics);
}

bool CameraModel::in_image(const Eigen::Vector2d& uv, double border) const {
  return uv.x() >= border - 0.5 && uv.y() >= border - 0.5 && uv.x() <= width_ - 0.5 - border &&
         uv.y() <= height_ - 0.5 - border;
}

std::vector<Eigen::Vector2d> CameraModel::undistort_points(
    const std::vector<Eigen::Vector2d>& pixels, const PinholeIntrinsics* target) const {
  const PinholeIntrinsics& k = target ? *target : intrinsics_;
  std::vector<Eigen::Vector2d> out;
  out.reserve(pixels.size());
  for (const auto& uv : pixels) {
    Eigen::Vector3d b;
    if (!unproject(uv, b) || b.z() <= kMinDepth) {
      out.emplace_back(kNaN, kNaN);
      continue;
    }
    out.emplace_back(k.fx * b.x() / b.z() + k.cx, k.fy * b.y() / b.z() + k.cy);
  }
  return out;
}

void CameraModel::undistort_rectify_map(const PinholeIntrinsics& target, cv::Size size,
                                        const Eigen::Matrix3d& R_target_cam, cv::Mat& map_x,
                                        cv::Mat& map_y) const {
  map_x.create(size, CV_32F);
  map_y.create(size, CV_32F);
  const Eigen::Matrix3d R_cam_target = R_target_cam.transpose();
  for (int v = 0; v < size.height; ++v) {
    auto* mx = map_x.ptr<float>(v);
    auto* my = map_y.ptr<float>(v);
    for (int u = 0; u < size.width; ++u) {
      const Eigen::Vector3d ray((u - target.cx) / target.fx, (v - target.cy) / target.fy, 1.0);
      Eigen::Vector2d uv;
      if (project(R_cam_target * ray, uv)) {
        mx[u] = static_cast<float>(uv.x());
        my[u] = static_cast<float>(uv.y());
      } else {
        mx[u] = my[u] = -1.f;
      }
    }
  }
}

cv::Mat CameraModel::undistort_image(const cv::Mat& image, const PinholeIntrinsics* target) const {
  if (image.cols != width_ || image.rows != height_)
    throw InputError("undistort_image: image is " + std::to_string(image.cols) + "x" +
                     std::to_string(image.rows) + ", camera is " + std::to_string(width_) + "x" +
                     std::to_string(height_));
  cv::Mat mx, my, out;
  undistort_rectify_map(target ? *target : intrinsics_, image.size(), Eigen::Matrix3d::Identity(),
                        mx, my);
  cv::remap(image, out, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  return out;
}

// ---------------------------------------------------------------- PinholeRadtan

PinholeRadtan::PinholeRadtan(int width, int height, PinholeIntrinsics intrinsics,
                             std::vector<double> d)
    : CameraModel(width, height, intrinsics) {
  if (!(d.empty() || d.size() == 4 || d.size() == 5))
    throw InputError("radtan distortion needs 4 or 5 coefficients (k1 k2 p1 p2 [k3]), got " +
                     std::to_string(d.size()));
  for (double v : d)
    if (!std::isfinite(v)) throw InputError("radtan distortion coefficients must be finite");
  d.resize(5, 0.0);
  k1_ = d[0], k2_ = d[1], p1_ = d[2], p2_ = d[3], k3_ = d[4];
}

std::vector<double> PinholeRadtan::distortion() const { return {k1_, k2_, p1_, p2_, k3_}; }

Eigen::Vector2d PinholeRadtan::distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
  const Eigen::Vector2d d(x * radial + 2 * p1_ * x * y + p2_ * (r2 + 2 * x * x),
                          y * radial + p1_ * (r2 + 2 * y * y) + 2 * p2_ * x * y);
  if (J) {
    const double dradial_dr2 = k1_ + r2 * (2 * k2_ + 3 * k3_ * r2);
    const double drdx = 2 * x * dradial_dr2, drdy = 2 * y * dradial_dr2;
    (*J)(0, 0) = radial + x * drdx + 2 * p1_ * y + 6 * p2_ * x;
    (*J)(0, 1) = x * drdy + 2 * p1_ * x + 2 * p2_ * y;
    (*J)(1, 0) = y * drdx + 2 * p1_ * x + 2 * p2_ * y;
    (*J)(1, 1) = radial + y * drdy + 6 * p1_ * y + 2 * p2_ * x;
  }
  return d;
}

bool PinholeRadtan::project(const Eigen::Vector3d& p, Eigen::Vector2d& uv,
                            Eigen::Matrix<double, 2, 3>* J) const {
  if (!(p.z() > kMinDepth)) return false;
  const double iz = 1.0 / p.z();
  const Eigen::Vector2d xy(p.x() * iz, p.y() * iz);
  Eigen::Matrix2d Jd;
  const Eigen::Vector2d d = distort(xy, J ? &Jd : nullptr);
  uv << intrinsics_.fx * d.x() + intrinsics_.cx, intrinsics_.fy * d.y() + intrinsics_.cy;
  if (J) {
    Eigen::Matrix<double, 2, 3> Jn;
    Jn << iz, 0, -xy.x() * iz, 0, iz, -xy.y() * iz;
    *J = Eigen::DiagonalMatrix<double, 2>(intrinsics_.fx, intrinsics_.fy) * Jd * Jn;
  }
  return true;
}

bool PinholeRadtan::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const {
  const Eigen::Vector2d target((uv.x() - intrinsics_.cx) / intrinsics_.fx,
                               (uv.y() - intrinsics_.cy) / intrinsics_.fy);
  // Newton on distort(xy) = target, started at the distorted point itself.
  Eigen::Vector2d xy = target;
  bool converged = false;
  for (int it = 0; it < 30; ++it) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d r = distort(xy, &J) - target;
    if (r.squaredNorm() < 1e-24) {
      converged = true;
      break;
    }
    const Eigen::Vector2d step = J.inverse() * r;
    if (!step.allFinite()) return false;
    xy -= step;
  }
  if (!converged && (distort(xy) - target).norm() > 1e-9) return false;
  bearing = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  return true;
}

// ---------------------------------------------------------------- KannalaBrandt

KannalaBrandt::KannalaBrandt(int width, int height, PinholeIntrinsics intrinsics,
                             std::vector<double> k)
    : CameraModel(width, height, intrinsics) {
  if (k.size() != 4)
    throw InputError("equidistant distortion needs 4 coefficients (k1..k4), got " +
                     std::to_string(k.size()));
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(k[i])) throw InputError("equidistant coefficients must be finite");
    k_[i] = k[i];
  }
}

double KannalaBrandt::theta_d(double t, double* dtheta_d) const {
  const double t2 = t * t;
  if (dtheta_d)
    *dtheta_d = 1 + t2 * (3 * k_[0] + t2 * (5 * k_[1] + t2 * (7 * k_[2] + t2 * 9 * k_[3])));
  return t * (1 + t2 * (k_[0] + t2 * (k_[1] + t2 * (k_[2] + t2 * k_[3]))));
}

bool KannalaBrandt::project(const Eigen::Vector3d& p, Eigen::Vector2d& uv,
                            Eigen::Matrix<double, 2, 3>* J) const {
  const double X = p.x(), Y = p.y(), Z = p.z();
  const double r2 = X * X + Y * Y, r = std::sqrt(r2);
  const double fx = intrinsics_.fx, fy = intrinsics_.fy;
  if (r < 1e-9 * std::abs(Z) || r < 1e-300) {
    // On the optical axis the model is a pinhole to first order.
    if (!(Z > kMinDepth)) return false;
    uv << fx * X / Z + intrinsics_.cx, fy * Y / Z + intrinsics_.cy;
    if (J) *J << fx / Z, 0, -fx * X / (Z * Z), 0, fy / Z, -fy * Y / (Z * Z);
    return true;
  }
  const double theta = std::atan2(r, Z);
  double dtd = 0;
  const double td = theta_d(theta, &dtd);
  const double s = td / r;
  uv << fx * X * s + intrinsics_.cx, fy * Y * s + intrinsics_.cy;
  if (J) {
    const double n2 = r2 + Z * Z;
    const Eigen::Vector3d dtheta(Z * X / (r * n2), Z * Y / (r * n2), -r / n2);
    const Eigen::Vector3d dr(X / r, Y / r, 0.0);
    const Eigen::Vector3d ds = (dtd * dtheta * r - td * dr) / r2;
    Eigen::Matrix<double, 2, 3> dm;
    dm.row(0) = X * ds.transpose();
    dm.row(1) = Y * ds.transpose();
    dm(0, 0) += s;
    dm(1, 1) += s;
    *J = Eigen::DiagonalMatrix<double, 2>(fx, fy) * dm;
  }
  return true;
}

bool KannalaBrandt::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const {
  const Eigen::Vector2d m((uv.x() - intrinsics_.cx) / intrinsics_.fx,
                          (uv.y() - intrinsics_.cy) / intrinsics_.fy);
  const double td = m.norm();
  if (td < 1e-12) {
    bearing = Eigen::Vector3d::UnitZ();
    return true;
  }
  double theta = td;
  for (int it = 0; it < 30; ++it) {
    double d = 0;
    const double f = theta_d(theta, &d) - td;
    if (std::abs(f) < 1e-14) break;
    if (!(std::abs(d) > 1e-12)) return false;
    theta -= f / d;
  }
  if (!(std::abs(theta_d(theta) - td) < 1e-9) || theta < 0 || theta > M_PI) return false;
  const double st = std::sin(theta);
  bearing << st * m.x() / td, st * m.y() / td, std::cos(theta);
  return true;
}

}  // namespace pllvo::camera
