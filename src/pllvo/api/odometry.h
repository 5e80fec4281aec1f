#pragma once
// pllvo's library API: the visual odometry as a user embeds it. The only header a user needs
// (it brings calibration.h and the error types):
//
//   auto odometry = pllvo::Odometry(pllvo::Calibration::load("camera.yaml"));
//   pllvo::TrackResult r = odometry.track(timestamp, image);     // or push() from a camera thread
//   odometry.finish(); odometry.save("out");                      // what `pllvo run --out` writes
//
// Frames are 8-bit gray, BGR or BGRA cv::Mats of the calibration's size. A bad frame (wrong
// size or type, empty, a timestamp that does not increase, NaN) is an InputError and leaves the
// odometry as it was: the next good frame is tracked as usual.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pllvo/api/calibration.h"
#include "pllvo/common/error.h"

// find_package(pllvo) defines it as the installed package's models folder.
#ifndef PLLVO_INSTALLED_MODELS_DIR
#define PLLVO_INSTALLED_MODELS_DIR ""
#endif

namespace pllvo {

namespace vo {
struct VoConfig;
}

/// How the odometry is set up. The VO's own parameters are the VO config (config/vo.yaml, every
/// key in docs/config.md): a YAML file and/or dotted `key=value` overrides, defaults otherwise.
struct OdometryOptions {
  std::filesystem::path config_yaml;  ///< empty: the defaults
  /// Applied after the YAML, in order: {"keyframes.max_interval_s", "0.5"}; values are YAML.
  std::vector<std::pair<std::string, std::string>> overrides;
  bool stereo = true;  ///< use the second camera when the calibration has one
  /// Without a second camera in use: the frames' depth images when the calibration has depth
  /// (RGB-D: track_rgbd, push_rgbd); false: monocular.
  bool depth = true;
  /// Keyframes processed inline on the tracking thread: repeatable results (bitwise the same
  /// as `pllvo run --single-thread`), slower. Same as the override run.threaded=false.
  bool single_thread = false;
  /// A live camera: the tracker never waits for the keyframe worker, also with track().
  /// push() implies it.
  bool live = false;
  /// Folder of the network weights, used when the VO config names none and $PLLVO_MODELS is
  /// unset. Default: the models of the installed package this header came from; empty (the
  /// build tree): pllvo's own lookup (docs/nn.md).
  std::filesystem::path models_dir = PLLVO_INSTALLED_MODELS_DIR;
};

/// The VO config that `options` describe: the YAML, the overrides, single_thread and models_dir
/// applied, validated. InputError naming the file or key at fault.
vo::VoConfig vo_config_of(const OdometryOptions& options);

enum class TrackingState {
  kInitializing,  ///< no map yet (monocular: waiting for parallax)
  kTracking,      ///< this frame has a pose
  kLost,          ///< the map was lost on this frame or before; a new one starts when it can
};
const char* to_string(TrackingState state);

/// What the odometry knows about one frame once it is processed.
struct TrackResult {
  size_t frame_index = 0;  ///< 0, 1, 2... in the order the frames were given
  double timestamp = 0;
  TrackingState state = TrackingState::kInitializing;
  bool tracked = false;                                     ///< T_world_cam0 is valid
  Eigen::Matrix4d T_world_cam0 = Eigen::Matrix4d::Identity();  ///< the left camera's pose
  int tracked_points = 0;
  int tracked_lines = 0;
  bool keyframe = false;  ///< this frame was made a keyframe
  int map_segment = 0;    ///< increases with every new map after a loss
  /// For display, in the working image (undistorted / rectified left): the points and line
  /// segments the tracker follows; `point_in_map[i]`: point i is a map point (else a candidate).
  std::vector<Eigen::Vector2f> points;
  std::vector<bool> point_in_map;
  std::vector<Eigen::Vector4f> lines;  ///< x1 y1 x2 y2
};

struct StampedPose {
  double timestamp = 0;
  Eigen::Matrix4d T_world_cam0 = Eigen::Matrix4d::Identity();
};

/// What a finished run reports (also in stats.json).
struct RunReport {
  size_t frames = 0, tracked_frames = 0, keyframes = 0, frames_dropped = 0;
  int resets = 0;
  double wall_seconds = 0, frames_per_second = 0;
  std::string stats_json;  ///< the whole of stats.json
};

class Odometry {
 public:
  explicit Odometry(const Calibration& calibration, const OdometryOptions& options = {});
  /// The same with a config struct in place of the YAML and overrides.
  Odometry(const Calibration& calibration, const vo::VoConfig& config, const OdometryOptions& options = {});
  ~Odometry();
  Odometry(Odometry&&) noexcept;
  Odometry& operator=(Odometry&&) noexcept;

  /// Tracks one frame on the caller's thread and returns its result. Calls from several threads
  /// are serialised. `right` only for a stereo odometry.
  TrackResult track(double timestamp, const cv::Mat& left, const cv::Mat& right = cv::Mat());
  /// From a camera callback: checks the frame, hands it to the odometry's tracking thread and
  /// returns at once. When the tracker is still busy, the frame waiting for it is replaced by
  /// this one and counted as dropped (returns true then). Results go to the callback.
  bool push(double timestamp, const cv::Mat& left, const cv::Mat& right = cv::Mat());
  /// RGB-D (the calibration has depth, see Calibration::with_depth): one image and its depth
  /// image of the same size, CV_16UC1 in the calibration's units per metre or CV_32FC1 metres;
  /// 0 or NaN where the sensor has no depth. An empty depth image tracks the frame without.
  TrackResult track_rgbd(double timestamp, const cv::Mat& image, const cv::Mat& depth);
  bool push_rgbd(double timestamp, const cv::Mat& image, const cv::Mat& depth);
  /// Called after every tracked frame on the thread that tracked it; keep it short.
  void on_result(std::function<void(const TrackResult&)> callback);
  /// The latest result (any thread); frame_index 0 and kInitializing before the first frame.
  TrackResult latest() const;

  /// Ends input: waits for frames in flight and keyframes being processed. Rethrows an error
  /// that stopped the tracking thread of push(). Further frames are refused.
  void finish();
  /// Poses of the tracked frames (T_world_cam0), as trajectory.tum has them.
  std::vector<StampedPose> trajectory() const;
  /// The same frames, each on its keyframe's current (bundle-adjusted) pose at its tracked pose
  /// relative to it, as trajectory_anchored.tum has them: the better estimate after the fact.
  std::vector<StampedPose> anchored_trajectory() const;
  /// Keyframe poses after bundle adjustment; poll them to follow map updates.
  std::vector<StampedPose> keyframes() const;
  /// The map's 3-D points in the world frame.
  std::vector<Eigen::Vector3d> map_points() const;
  bool stereo() const;
  bool rgbd() const;  ///< depth images are the metric source
  /// After finish(): counts and stats.json.
  RunReport report() const;
  /// After finish(): trajectory.tum, trajectory_anchored.tum, keyframes.tum, map.ply, stats.json in `dir` (created),
  /// exactly as `pllvo run --out dir` writes them.
  void save(const std::filesystem::path& dir) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pllvo
