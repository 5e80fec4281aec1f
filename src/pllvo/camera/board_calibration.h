#pragma once
// Camera calibration from views of a planar board (OpenCV's calibration): a chessboard or a
// ChArUco board, pinhole with radial-tangential distortion or Kannala-Brandt (fisheye), one
// camera or a stereo pair (the pair's extrinsics with each camera's intrinsics held).
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"

namespace pllvo::camera {

struct BoardSpec {
  std::string type = "chessboard";  ///< chessboard | charuco
  int rows = 0, cols = 0;           ///< squares per column and per row (inner corners: rows-1 x cols-1)
  double square_m = 0;              ///< side of a square, metres
  double marker_m = 0;              ///< ChArUco: side of a marker; 0: 0.7 x square_m
  int dictionary = 0;               ///< ChArUco: OpenCV's predefined dictionary (0: DICT_4X4_50)
};

struct CalibrationOptions {
  std::string model = "radtan";  ///< radtan (k1 k2 p1 p2 k3) | equidistant (Kannala-Brandt k1..k4)
  size_t min_views = 6;          ///< fewer views with a board found is refused
};

/// One image: whether the board was found, how many corners, its reprojection RMS after calibration.
struct CalibrationView {
  std::string name;
  bool found = false;
  int corners = 0;
  double rms_px = 0;
};

struct BoardCalibration {
  CameraPtr camera;
  double rms_px = 0;  ///< over every corner of every used view
  std::vector<CalibrationView> views;
};

struct StereoBoardCalibration {
  BoardCalibration left, right;
  Eigen::Isometry3d T_left_right = Eigen::Isometry3d::Identity();  ///< right camera in the left's frame
  double rms_px = 0;  ///< of the stereo fit
  size_t pairs = 0;   ///< pairs with the board found in both images
};

/// Corners of the board found in `gray` (image pixels) and the same corners on the board (metres,
/// z = 0); `ids` the corner numbers (row-major over the inner corners). Empty when not found.
struct BoardDetection {
  std::vector<cv::Point2f> image;
  std::vector<cv::Point3f> board;
  std::vector<int> ids;
};
BoardDetection detect_board(const cv::Mat& gray, const BoardSpec& board);

/// InputError when the spec is not a board (too few squares, no square size) or when fewer than
/// options.min_views images show it (the message lists how many did).
BoardCalibration calibrate_camera(const std::vector<std::pair<std::string, cv::Mat>>& images, const BoardSpec& board,
                                  const CalibrationOptions& options = {});
/// Left and right images in pairs (same order, same size per side).
StereoBoardCalibration calibrate_stereo(const std::vector<std::pair<std::string, cv::Mat>>& left,
                                        const std::vector<std::pair<std::string, cv::Mat>>& right,
                                        const BoardSpec& board, const CalibrationOptions& options = {});

/// An image of the board as printed: `pixels_per_square` pixels a square, with a white margin of one square.
cv::Mat draw_board(const BoardSpec& board, int pixels_per_square);

}  // namespace pllvo::camera
