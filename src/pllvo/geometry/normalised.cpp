#include "pllvo/geometry/normalised.h"

#include <limits>

namespace pllvo::geometry {

double pixel_scale(const camera::CameraModel& camera) {
  return 0.5 * (camera.intrinsics().fx + camera.intrinsics().fy);
}

bool pixel_to_normalised(const camera::CameraModel& camera, const Eigen::Vector2d& uv,
                         Eigen::Vector2d& xy) {
  Eigen::Vector3d bearing;
  if (!camera.unproject(uv, bearing) || !(bearing.z() > 1e-9)) return false;
  xy = bearing.head<2>() / bearing.z();
  return true;
}

std::vector<Eigen::Vector2d> pixels_to_normalised(const camera::CameraModel& camera,
                                                  const std::vector<Eigen::Vector2d>& uv) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Eigen::Vector2d> out(uv.size(), Eigen::Vector2d(nan, nan));
  for (size_t i = 0; i < uv.size(); ++i) pixel_to_normalised(camera, uv[i], out[i]);
  return out;
}

}  // namespace pllvo::geometry
