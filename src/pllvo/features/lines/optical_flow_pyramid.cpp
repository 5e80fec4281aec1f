#include "pllvo/features/lines/optical_flow_pyramid.h"

#include <algorithm>
#include <cmath>

#include <opencv2/video/tracking.hpp>

#include "pllvo/common/error.h"

namespace pllvo::lines {

OpticalFlowPyramid::OpticalFlowPyramid(const cv::Mat& gray, cv::Size window, int max_level, double normalized_mean)
    : window_(window), size_(gray.size()) {
  if (gray.empty() || gray.type() != CV_8UC1) throw InputError("optical-flow pyramid: expected an 8-bit gray image");
  cv::Mat image = gray;
  if (normalized_mean > 0.0) {
    gain_ = normalized_mean / std::max(cv::mean(gray)[0], 1.0);
    if (std::abs(gain_ - 1.0) > 1e-3) {
      cv::Mat scaled;  // a new buffer: convertTo into `image` would overwrite the caller's pixels
      gray.convertTo(scaled, CV_8U, gain_);
      image = scaled;
    }
  }
  max_level_ = cv::buildOpticalFlowPyramid(image, levels_, window, max_level, /*withDerivatives=*/true);
}

}  // namespace pllvo::lines
