#include "pllvo/features/lines/optical_flow_pyramid.h"

#include <opencv2/video/tracking.hpp>

#include "pllvo/common/error.h"

namespace pllvo::lines {

OpticalFlowPyramid::OpticalFlowPyramid(const cv::Mat& gray, cv::Size window, int max_level)
    : window_(window), size_(gray.size()) {
  if (gray.empty() || gray.type() != CV_8UC1) throw InputError("optical-flow pyramid: expected an 8-bit gray image");
  max_level_ = cv::buildOpticalFlowPyramid(gray, levels_, window, max_level, /*withDerivatives=*/true);
}

}  // namespace pllvo::lines
