#include "pllvo/camera/board_calibration.h"

#include <cmath>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <Eigen/Core>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"

namespace pllvo::camera {
namespace {

void check_spec(const BoardSpec& b) {
  if (b.type != "chessboard" && b.type != "charuco")
    throw InputError("unknown board '" + b.type + "' (chessboard or charuco)");
  if (b.rows < 3 || b.cols < 3)
    throw InputError("a board needs at least 3 x 3 squares (got " + std::to_string(b.rows) + " x " +
                     std::to_string(b.cols) + ")");
  if (!(b.square_m > 0)) throw InputError("the board's square size must be positive (metres)");
}

cv::Ptr<cv::aruco::CharucoBoard> charuco(const BoardSpec& b) {
  const double marker = b.marker_m > 0 ? b.marker_m : 0.7 * b.square_m;
  return cv::aruco::CharucoBoard::create(b.cols, b.rows, static_cast<float>(b.square_m), static_cast<float>(marker),
                                         cv::aruco::getPredefinedDictionary(b.dictionary));
}

cv::Mat gray_of(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat g;
  cv::cvtColor(image, g, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return g;
}

bool fisheye(const CalibrationOptions& o) {
  if (o.model == "radtan") return false;
  if (o.model == "equidistant") return true;
  throw InputError("unknown camera model '" + o.model + "' (radtan or equidistant)");
}

struct Views {
  std::vector<std::vector<cv::Point3f>> board;
  std::vector<std::vector<cv::Point2f>> image;
  std::vector<size_t> index;  ///< into the images
  cv::Size size;
};

Views detect_all(const std::vector<std::pair<std::string, cv::Mat>>& images, const BoardSpec& board,
                 std::vector<CalibrationView>& report) {
  Views v;
  for (size_t i = 0; i < images.size(); ++i) {
    const cv::Mat& img = images[i].second;
    if (img.empty()) throw InputError(images[i].first, "cannot read this image");
    if (v.size.area() == 0) v.size = img.size();
    if (img.size() != v.size)
      throw InputError(images[i].first, "is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                                            ", the first image " + std::to_string(v.size.width) + "x" +
                                            std::to_string(v.size.height));
    const BoardDetection d = detect_board(gray_of(img), board);
    CalibrationView view{images[i].first, !d.image.empty(), static_cast<int>(d.image.size()), 0};
    report.push_back(view);
    if (d.image.empty()) continue;
    v.board.push_back(d.board);
    v.image.push_back(d.image);
    v.index.push_back(i);
  }
  return v;
}

CameraPtr camera_of(const cv::Mat& K, const cv::Mat& dist, cv::Size size, bool is_fisheye) {
  PinholeIntrinsics k;
  k.fx = K.at<double>(0, 0);
  k.fy = K.at<double>(1, 1);
  k.cx = K.at<double>(0, 2);
  k.cy = K.at<double>(1, 2);
  std::vector<double> d(dist.begin<double>(), dist.end<double>());
  return make_camera(is_fisheye ? "equidistant" : "radtan", size.width, size.height, k, d);
}

double view_rms(const std::vector<cv::Point3f>& board, const std::vector<cv::Point2f>& image, const cv::Mat& rvec,
                const cv::Mat& tvec, const cv::Mat& K, const cv::Mat& dist, bool is_fisheye) {
  std::vector<cv::Point2f> projected;
  if (is_fisheye)
    cv::fisheye::projectPoints(board, projected, rvec, tvec, K, dist);
  else
    cv::projectPoints(board, rvec, tvec, K, dist, projected);
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const cv::Point2f e = projected[i] - image[i];
    sum += e.dot(e);
  }
  return std::sqrt(sum / static_cast<double>(image.size()));
}

}  // namespace

BoardDetection detect_board(const cv::Mat& gray, const BoardSpec& board) {
  check_spec(board);
  BoardDetection d;
  if (board.type == "chessboard") {
    const cv::Size pattern(board.cols - 1, board.rows - 1);
    std::vector<cv::Point2f> corners;
    if (!cv::findChessboardCornersSB(gray, pattern, corners, cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY))
      return d;
    d.image = corners;
    for (int r = 0; r < pattern.height; ++r)
      for (int c = 0; c < pattern.width; ++c) {
        d.board.emplace_back(static_cast<float>((c + 1) * board.square_m), static_cast<float>((r + 1) * board.square_m),
                             0.0f);
        d.ids.push_back(r * pattern.width + c);
      }
    return d;
  }
  const auto b = charuco(board);
  std::vector<std::vector<cv::Point2f>> marker_corners;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(gray, b->dictionary, marker_corners, marker_ids);
  if (marker_ids.size() < 4) return d;
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, gray, b, corners, ids);
  if (ids.size() < 6) return d;
  d.image = corners;
  d.ids = ids;
  for (int id : ids) d.board.push_back(b->chessboardCorners[id]);
  return d;
}

BoardCalibration calibrate_camera(const std::vector<std::pair<std::string, cv::Mat>>& images, const BoardSpec& board,
                                  const CalibrationOptions& options) {
  check_spec(board);
  const bool is_fisheye = fisheye(options);
  BoardCalibration result;
  const Views v = detect_all(images, board, result.views);
  if (v.board.size() < options.min_views)
    throw InputError("the board was found in " + std::to_string(v.board.size()) + " of " +
                     std::to_string(images.size()) + " images; calibration needs at least " +
                     std::to_string(options.min_views) + " (check --board, --rows, --cols: squares, not inner corners)");
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  if (is_fisheye) {
    std::vector<std::vector<cv::Point3d>> board3;
    std::vector<std::vector<cv::Point2d>> image2;
    for (size_t i = 0; i < v.board.size(); ++i) {
      board3.emplace_back(v.board[i].begin(), v.board[i].end());
      image2.emplace_back(v.image[i].begin(), v.image[i].end());
    }
    result.rms_px = cv::fisheye::calibrate(board3, image2, v.size, K, dist, rvecs, tvecs,
                                           cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
                                           cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  } else {
    result.rms_px = cv::calibrateCamera(v.board, v.image, v.size, K, dist, rvecs, tvecs);
  }
  K.convertTo(K, CV_64F);
  dist.convertTo(dist, CV_64F);
  result.camera = camera_of(K, dist.reshape(1, 1), v.size, is_fisheye);
  for (size_t i = 0; i < v.index.size(); ++i)
    result.views[v.index[i]].rms_px = view_rms(v.board[i], v.image[i], rvecs[i], tvecs[i], K, dist, is_fisheye);
  return result;
}

StereoBoardCalibration calibrate_stereo(const std::vector<std::pair<std::string, cv::Mat>>& left,
                                        const std::vector<std::pair<std::string, cv::Mat>>& right,
                                        const BoardSpec& board, const CalibrationOptions& options) {
  if (left.size() != right.size())
    throw InputError("stereo calibration needs as many right images as left ones (" + std::to_string(left.size()) +
                     " left, " + std::to_string(right.size()) + " right)");
  if (fisheye(options)) throw InputError("stereo calibration supports the radtan model only");
  StereoBoardCalibration s;
  s.left = calibrate_camera(left, board, options);
  s.right = calibrate_camera(right, board, options);
  std::vector<std::vector<cv::Point3f>> board3;
  std::vector<std::vector<cv::Point2f>> l2, r2;
  for (size_t i = 0; i < left.size(); ++i) {
    const BoardDetection a = detect_board(gray_of(left[i].second), board);
    const BoardDetection b = detect_board(gray_of(right[i].second), board);
    if (a.ids.empty() || b.ids.empty()) continue;
    std::vector<cv::Point3f> o;
    std::vector<cv::Point2f> pl, pr;
    for (size_t j = 0; j < a.ids.size(); ++j)
      for (size_t k = 0; k < b.ids.size(); ++k)
        if (a.ids[j] == b.ids[k]) {
          o.push_back(a.board[j]);
          pl.push_back(a.image[j]);
          pr.push_back(b.image[k]);
        }
    if (o.size() < 6) continue;
    board3.push_back(o);
    l2.push_back(pl);
    r2.push_back(pr);
  }
  s.pairs = board3.size();
  if (s.pairs < options.min_views)
    throw InputError("the board was found in both images of " + std::to_string(s.pairs) + " pairs; at least " +
                     std::to_string(options.min_views) + " are needed");
  const auto K_of = [](const CameraModel& c) { cv::Mat K; cv::eigen2cv(c.intrinsics().K(), K); return K; };
  cv::Mat K0 = K_of(*s.left.camera), K1 = K_of(*s.right.camera);
  const std::vector<double> dist0 = s.left.camera->distortion(), dist1 = s.right.camera->distortion();
  cv::Mat d0 = cv::Mat(dist0).clone().reshape(1, 1), d1 = cv::Mat(dist1).clone().reshape(1, 1);
  cv::Mat R, T, E, F;
  s.rms_px = cv::stereoCalibrate(board3, l2, r2, K0, d0, K1, d1, left.front().second.size(), R, T, E, F,
                                 cv::CALIB_FIX_INTRINSIC);
  // OpenCV's R, T map left-camera points into the right camera: T_right_left.
  Eigen::Matrix3d Re;
  Eigen::Vector3d Te;
  cv::cv2eigen(R, Re);
  cv::cv2eigen(T, Te);
  Eigen::Isometry3d T_right_left = Eigen::Isometry3d::Identity();
  T_right_left.linear() = Re;
  T_right_left.translation() = Te;
  s.T_left_right = T_right_left.inverse();
  return s;
}

cv::Mat draw_board(const BoardSpec& board, int pixels_per_square) {
  check_spec(board);
  const cv::Size size((board.cols + 2) * pixels_per_square, (board.rows + 2) * pixels_per_square);
  cv::Mat img(size, CV_8UC1, cv::Scalar(255));
  if (board.type == "chessboard") {
    for (int r = 0; r < board.rows; ++r)
      for (int c = 0; c < board.cols; ++c)
        if ((r + c) % 2 == 0)
          img(cv::Rect((c + 1) * pixels_per_square, (r + 1) * pixels_per_square, pixels_per_square, pixels_per_square))
              .setTo(0);
    return img;
  }
  cv::Mat inner;
  charuco(board)->draw(cv::Size(board.cols * pixels_per_square, board.rows * pixels_per_square), inner, 0, 1);
  inner.copyTo(img(cv::Rect(pixels_per_square, pixels_per_square, inner.cols, inner.rows)));
  return img;
}

}  // namespace pllvo::camera
