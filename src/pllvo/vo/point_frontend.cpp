#include "pllvo/vo/point_frontend.h"

#include <algorithm>
#include <numeric>

#include <spdlog/spdlog.h>

#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/vo/classical_frontends.h"
#include "pllvo/vo/superpoint_frontend.h"

namespace pllvo::vo {

void PointFeatures::append(const PointFeatures& other) {
  if (other.empty()) return;
  if (!descriptors.empty() && (descriptors.type() != other.descriptors.type() ||
                               descriptors.cols != other.descriptors.cols))
    throw InternalError("PointFeatures::append: descriptor layouts differ");
  points.insert(points.end(), other.points.begin(), other.points.end());
  scores.insert(scores.end(), other.scores.begin(), other.scores.end());
  source.insert(source.end(), other.source.begin(), other.source.end());
  if (descriptors.empty())
    descriptors = other.descriptors.clone();
  else
    cv::vconcat(descriptors, other.descriptors, descriptors);
}

PointFeatures PointFeatures::select(const std::vector<int>& rows) const {
  PointFeatures out;
  out.descriptors.create(static_cast<int>(rows.size()), descriptors.cols, descriptors.type());
  for (size_t k = 0; k < rows.size(); ++k) {
    const int i = rows[k];
    out.points.push_back(points.at(static_cast<size_t>(i)));
    if (!scores.empty()) out.scores.push_back(scores.at(static_cast<size_t>(i)));
    if (!source.empty()) out.source.push_back(source.at(static_cast<size_t>(i)));
    descriptors.row(i).copyTo(out.descriptors.row(static_cast<int>(k)));
  }
  return out;
}

std::vector<size_t> select_on_grid(const std::vector<cv::Point2f>& points, const std::vector<float>& scores,
                                   cv::Size image_size, int grid_cols, int grid_rows, int max_points) {
  std::vector<size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return scores[a] > scores[b]; });
  if (static_cast<int>(points.size()) <= max_points) return order;

  const int cells = grid_cols * grid_rows;
  const int quota = std::max(1, max_points / cells);
  std::vector<int> used(cells, 0);
  std::vector<char> taken(points.size(), 0);
  std::vector<size_t> selected;
  for (size_t i : order) {
    const int cx = std::clamp(static_cast<int>(points[i].x * grid_cols / image_size.width), 0, grid_cols - 1);
    const int cy = std::clamp(static_cast<int>(points[i].y * grid_rows / image_size.height), 0, grid_rows - 1);
    int& n = used[cy * grid_cols + cx];
    if (n >= quota) continue;
    ++n;
    taken[i] = 1;
    selected.push_back(i);
    if (static_cast<int>(selected.size()) >= max_points) return selected;
  }
  for (size_t i : order) {
    if (static_cast<int>(selected.size()) >= max_points) break;
    if (!taken[i]) selected.push_back(i);
  }
  return selected;
}

cv::Mat free_space_mask(cv::Size size, const std::vector<cv::Point2f>& occupied, double radius, int border) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  if (size.width > 2 * border && size.height > 2 * border)
    mask(cv::Rect(border, border, size.width - 2 * border, size.height - 2 * border)).setTo(255);
  const int r = std::max(1, static_cast<int>(std::lround(radius)));
  for (const auto& p : occupied) cv::circle(mask, cv::Point(cvRound(p.x), cvRound(p.y)), r, cv::Scalar(0), -1);
  return mask;
}

cv::Mat equalize_for_detection(const cv::Mat& image) {
  // Tiles of ~100 px adapt to light that changes across the frame (HDR scenes).
  const int tiles_x = std::max(2, image.cols / 100), tiles_y = std::max(2, image.rows / 100);
  auto clahe = cv::createCLAHE(3.0, cv::Size(tiles_x, tiles_y));
  cv::Mat out;
  clahe->apply(image, out);
  return out;
}

std::string resolve_frontend_type(const FrontendConfig& config, std::string* notice) {
  if (notice) notice->clear();
  if (config.type != "auto") return config.type;
  if (find_superpoint_weights(config)) return "superpoint";
  const std::string message =
      "no SuperPoint weights found (frontend.superpoint_weights, $PLLVO_MODELS, models/): running the ORB front end "
      "instead";
  spdlog::warn("{}", message);
  if (notice) *notice = message;
  return "orb";
}

std::unique_ptr<PointFrontend> make_point_frontend(const FrontendConfig& requested) {
  FrontendConfig config = requested;
  config.type = resolve_frontend_type(requested);
  if (config.type == "orb") return std::make_unique<OrbFrontend>(config);
  if (config.type == "shitomasi") return std::make_unique<ShiTomasiFrontend>(config);
  if (config.type == "superpoint") return std::make_unique<SuperPointFrontend>(config);
  throw InputError("unknown point front end '" + config.type + "' (superpoint, orb, shitomasi)");
}

}  // namespace pllvo::vo
