#pragma once
// Point detection and description on keyframes, behind one interface so that SuperPoint
// and the classical baselines (ORB, Shi-Tomasi) share the rest of the pipeline.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/vo/vo_config.h"

namespace pllvo::vo {

/// Points of one image with one descriptor row each (CV_8U binary or CV_32F float).
struct PointFeatures {
  std::vector<cv::Point2f> points;  ///< pixels of the input image
  std::vector<float> scores;        ///< detector response, larger is better
  cv::Mat descriptors;              ///< rows == points.size()
  /// Per point: its index in the `tracked` list given to detect() when it is a tracked point
  /// described where it is, -1 for a new detection.
  std::vector<int> source;

  size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool binary() const { return descriptors.type() == CV_8U; }
  /// Appends `other` (same descriptor type and width, or this one empty).
  void append(const PointFeatures& other);
  /// The features at `rows`, in that order.
  PointFeatures select(const std::vector<int>& rows) const;
};

class PointFrontend {
 public:
  virtual ~PointFrontend() = default;
  virtual std::string name() const = 0;
  /// Keyframe features on `image` (CV_8UC1): the `tracked` points described where they are
  /// (those that can be described: a descriptor needs a patch inside the image), then new
  /// detections spread over a grid, none closer than the configured distance to a tracked
  /// point, up to the configured total. Any image, also a black or flat one, is fine: it just
  /// yields few or no points.
  virtual PointFeatures detect(const cv::Mat& image, const std::vector<cv::Point2f>& tracked = {}) = 0;
  /// Feedback after the keyframe was matched with the previous one: `matched` of its
  /// `keypoints` found a partner. Detectors that adapt to it (SuperPoint's threshold) use it.
  virtual void report_matches(int /*matched*/, int /*keypoints*/) {}
};

/// The front end named by `config.type` ("auto": see resolve_frontend_type); InputError when
/// it cannot be built (e.g. SuperPoint asked for by name and no weights found).
std::unique_ptr<PointFrontend> make_point_frontend(const FrontendConfig& config);

/// The front end `config.type` stands for: "auto" is superpoint when SuperPoint weights are
/// found (frontend.superpoint_weights, then the nn lookup), else orb, with `notice` saying why
/// (also logged); any other type is itself.
std::string resolve_frontend_type(const FrontendConfig& config, std::string* notice = nullptr);

/// Keeps the strongest keypoints per grid cell (an even share of `max_points` each, the
/// leftover filled by the strongest of the rest), so points cover the whole image.
std::vector<size_t> select_on_grid(const std::vector<cv::Point2f>& points, const std::vector<float>& scores,
                                   cv::Size image_size, int grid_cols, int grid_rows, int max_points);

/// 255 everywhere except discs of `radius` around `occupied` and a border of `border` pixels.
cv::Mat free_space_mask(cv::Size size, const std::vector<cv::Point2f>& occupied, double radius, int border);

/// Contrast-limited histogram equalisation, so that dim frames still give corners.
cv::Mat equalize_for_detection(const cv::Mat& image);

}  // namespace pllvo::vo
