#pragma once
// The classical point front ends used as baselines: ORB (ORB-SLAM style) and Shi-Tomasi
// corners (VINS style) described with ORB, so keyframes can be matched either way.
#include <opencv2/features2d.hpp>

#include "pllvo/vo/point_frontend.h"

namespace pllvo::vo {

class OrbFrontend final : public PointFrontend {
 public:
  explicit OrbFrontend(const FrontendConfig& config);
  std::string name() const override { return "orb"; }
  PointFeatures detect(const cv::Mat& image, const std::vector<cv::Point2f>& tracked) override;

 private:
  FrontendConfig config_;
  cv::Ptr<cv::ORB> orb_;
};

class ShiTomasiFrontend final : public PointFrontend {
 public:
  explicit ShiTomasiFrontend(const FrontendConfig& config);
  std::string name() const override { return "shitomasi"; }
  PointFeatures detect(const cv::Mat& image, const std::vector<cv::Point2f>& tracked) override;

 private:
  FrontendConfig config_;
  cv::Ptr<cv::ORB> describer_;
};

}  // namespace pllvo::vo
