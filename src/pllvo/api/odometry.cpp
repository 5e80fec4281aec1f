#include "pllvo/api/odometry.h"

#include <cstdlib>
#include <mutex>
#include <optional>

#include <yaml-cpp/yaml.h>

#include "pllvo/common/yaml_config.h"
#include "pllvo/report/config_overrides.h"
#include "pllvo/vo/odometry_session.h"
#include "pllvo/vo/vo_config.h"

namespace pllvo {
namespace {

vo::VoConfig config_from(const OdometryOptions& options) {
  // Without overrides, exactly `VoConfig::load`: its errors name the file and line.
  if (options.overrides.empty()) return options.config_yaml.empty() ? vo::VoConfig() : vo::VoConfig::load(options.config_yaml);
  YAML::Node base;  // null: the defaults
  std::string source = "odometry options";
  if (!options.config_yaml.empty()) {
    base = ConfigNode::load_file(options.config_yaml).raw();  // missing or malformed: InputError with the line
    source = options.config_yaml.string();
  }
  std::vector<report::ConfigOverride> overrides;
  for (const auto& [key, value] : options.overrides) overrides.push_back(report::parse_override(key + "=" + value));
  return report::make_vo_config(base, overrides, source + " with overrides");
}

/// single_thread and models_dir applied to `config`, validated.
vo::VoConfig with_options(vo::VoConfig config, const OdometryOptions& options) {
  if (options.single_thread) config.run.threaded = false;
  const char* env = std::getenv("PLLVO_MODELS");
  if (!options.models_dir.empty() && !(env && *env) && std::filesystem::is_directory(options.models_dir)) {
    if (config.frontend.superpoint_weights.empty()) config.frontend.superpoint_weights = options.models_dir.string();
    if (config.mapping.lightglue_weights.empty()) config.mapping.lightglue_weights = options.models_dir.string();
  }
  config.validate(options.config_yaml);
  return config;
}

Eigen::Matrix4d matrix_of(const geometry::Pose& pose) { return pose.matrix(); }

std::vector<StampedPose> stamped(const io::Trajectory& trajectory) {
  std::vector<StampedPose> out(trajectory.size());
  for (size_t i = 0; i < trajectory.size(); ++i) {
    out[i].timestamp = trajectory.stamps[i];
    out[i].T_world_cam0 = trajectory.poses[i].matrix();
  }
  return out;
}

}  // namespace

const char* to_string(TrackingState state) {
  switch (state) {
    case TrackingState::kInitializing:
      return "initializing";
    case TrackingState::kTracking:
      return "tracking";
    case TrackingState::kLost:
      return "lost";
  }
  return "?";
}

struct Odometry::Impl {
  std::unique_ptr<vo::OdometrySession> session;
  std::mutex track_mutex;  ///< serialises track(): its result is read back from `latest`
  std::mutex input_mutex;  ///< next_index
  size_t next_index = 0;
  mutable std::mutex result_mutex;
  TrackResult latest;
  bool tracked_before = false;
  long long keyframe_marks = 0;  ///< keyframe requests + initialisations counted so far
  std::function<void(const TrackResult&)> callback;
  std::optional<vo::RunSummary> summary;
  double units_per_metre = 0;  ///< of 16-bit depth images (the calibration's)

  Impl(const Calibration& calibration, const vo::VoConfig& config, const OdometryOptions& options) {
    vo::SessionOptions session_options;
    session_options.stereo = options.stereo;
    session_options.depth = options.depth;
    session_options.live = options.live;
    session = std::make_unique<vo::OdometrySession>(config, calibration.internal(), session_options);
    units_per_metre = calibration.depth_units_per_metre();
    session->set_on_frame([this](const vo::FrameRecord& record, const vo::TrackingView& view) { on_frame(record, view); });
  }

  long long keyframes_marked() const {
    const auto& stats = session->stats();
    return stats.count("keyframe_requests") + stats.count("keyframes.initialization");
  }

  void on_frame(const vo::FrameRecord& record, const vo::TrackingView& view) {
    TrackResult r;
    r.frame_index = record.index;
    r.timestamp = record.timestamp;
    r.tracked = record.tracked;
    if (record.tracked) r.T_world_cam0 = matrix_of(record.T_world_cam);
    r.tracked_points = record.tracked_points;
    r.tracked_lines = record.tracked_lines;
    r.map_segment = record.segment;
    const long long marks = keyframes_marked();
    r.keyframe = marks > keyframe_marks;
    keyframe_marks = marks;
    tracked_before = tracked_before || record.tracked;
    r.state = record.tracked ? TrackingState::kTracking
                             : (tracked_before ? TrackingState::kLost : TrackingState::kInitializing);
    r.points.reserve(view.points.size());
    for (const auto& p : view.points) {
      r.points.emplace_back(p.px.x, p.px.y);
      r.point_in_map.push_back(p.point != vo::kNoId);
    }
    for (const auto& l : view.lines)
      r.lines.emplace_back(l.segment.start.x(), l.segment.start.y(), l.segment.end.x(), l.segment.end.y());
    {
      std::lock_guard<std::mutex> lock(result_mutex);
      latest = r;
    }
    if (callback) callback(r);
  }

  // Copies of the caller's images: the odometry keeps them past the call (the last image; a
  // keyframe's, on the worker), and the caller may reuse its buffers at once (a camera driver's, a
  // numpy array): OdometryApi.ACallersReusedBuffersGiveTheSameTrajectory.
  io::Frame frame(double timestamp, const cv::Mat& left, const cv::Mat& right, const cv::Mat& depth) {
    std::lock_guard<std::mutex> lock(input_mutex);
    io::Frame f;
    f.index = next_index;
    f.timestamp = timestamp;
    f.left = left.clone();
    f.right = right.empty() ? right : right.clone();
    f.depth = metres(depth, f.index);
    return f;
  }

  TrackResult track(double timestamp, const cv::Mat& left, const cv::Mat& right, const cv::Mat& depth) {
    std::lock_guard<std::mutex> lock(track_mutex);
    session->process(frame(timestamp, left, right, depth));
    accepted();
    std::lock_guard<std::mutex> result_lock(result_mutex);
    return latest;
  }

  bool push(double timestamp, const cv::Mat& left, const cv::Mat& right, const cv::Mat& depth) {
    const auto replaced = session->push(frame(timestamp, left, right, depth));
    accepted();
    return replaced.has_value();
  }

  void require_rgbd(const char* call) const {
    if (!session->depth())
      throw InputError(std::string("Odometry::") + call +
                       ": this odometry is not RGB-D (its calibration has no depth, see Calibration::with_depth)");
  }

  // The odometry takes depth in metres (CV_32FC1); a 16-bit image is converted with the
  // calibration's units per metre. A new buffer either way, as for the images.
  cv::Mat metres(const cv::Mat& depth, size_t index) const {
    if (depth.empty()) return depth;
    if (depth.type() == CV_32FC1) return depth.clone();
    if (depth.type() != CV_16UC1)
      throw InputError("frame " + std::to_string(index) + ": the depth image must be CV_16UC1 (units per metre: " +
                       std::to_string(units_per_metre) + ") or CV_32FC1 metres; got type " + std::to_string(depth.type()));
    cv::Mat m;
    depth.convertTo(m, CV_32F, 1.0 / units_per_metre);
    return m;
  }
  void accepted() {
    std::lock_guard<std::mutex> lock(input_mutex);
    ++next_index;
  }
};

vo::VoConfig vo_config_of(const OdometryOptions& options) { return with_options(config_from(options), options); }

Odometry::Odometry(const Calibration& calibration, const OdometryOptions& options)
    : impl_(std::make_unique<Impl>(calibration, vo_config_of(options), options)) {}

Odometry::Odometry(const Calibration& calibration, const vo::VoConfig& config, const OdometryOptions& options)
    : impl_(std::make_unique<Impl>(calibration, with_options(config, options), options)) {}

Odometry::~Odometry() = default;
Odometry::Odometry(Odometry&&) noexcept = default;
Odometry& Odometry::operator=(Odometry&&) noexcept = default;

TrackResult Odometry::track(double timestamp, const cv::Mat& left, const cv::Mat& right) {
  return impl_->track(timestamp, left, right, cv::Mat());
}

bool Odometry::push(double timestamp, const cv::Mat& left, const cv::Mat& right) {
  return impl_->push(timestamp, left, right, cv::Mat());
}

TrackResult Odometry::track_rgbd(double timestamp, const cv::Mat& image, const cv::Mat& depth) {
  impl_->require_rgbd("track_rgbd");
  return impl_->track(timestamp, image, cv::Mat(), depth);
}

bool Odometry::push_rgbd(double timestamp, const cv::Mat& image, const cv::Mat& depth) {
  impl_->require_rgbd("push_rgbd");
  return impl_->push(timestamp, image, cv::Mat(), depth);
}

void Odometry::on_result(std::function<void(const TrackResult&)> callback) {
  std::lock_guard<std::mutex> lock(impl_->track_mutex);
  impl_->callback = std::move(callback);
}

TrackResult Odometry::latest() const {
  std::lock_guard<std::mutex> lock(impl_->result_mutex);
  return impl_->latest;
}

void Odometry::finish() {
  impl_->session->finish();
  if (!impl_->summary) impl_->summary = impl_->session->summary(vo::SessionSource{});
}

std::vector<StampedPose> Odometry::trajectory() const {
  if (impl_->summary) return stamped(impl_->summary->trajectory);
  return stamped(vo::tracked_trajectory(impl_->session->odometry().records()));
}

std::vector<StampedPose> Odometry::anchored_trajectory() const {
  if (impl_->summary) return stamped(impl_->summary->anchored_trajectory);
  const vo::Odometry& odometry = impl_->session->odometry();
  return stamped(vo::keyframe_anchored_trajectory(odometry.records(), odometry.keyframe_poses()));
}

std::vector<StampedPose> Odometry::keyframes() const {
  if (impl_->summary) return stamped(impl_->summary->keyframe_trajectory);
  return stamped(impl_->session->odometry().keyframe_trajectory());
}

std::vector<Eigen::Vector3d> Odometry::map_points() const {
  const vo::MapData map = impl_->summary ? impl_->summary->map : impl_->session->odometry().map_snapshot();
  std::vector<Eigen::Vector3d> out;
  out.reserve(map.points.size());
  for (const auto& [id, p] : map.points) out.push_back(p.position);
  return out;
}

bool Odometry::stereo() const { return impl_->session->stereo(); }
bool Odometry::rgbd() const { return impl_->session->depth(); }

RunReport Odometry::report() const {
  if (!impl_->summary) throw InputError("Odometry::report(): call finish() first");
  const vo::RunSummary& s = *impl_->summary;
  RunReport r;
  r.frames = s.frames;
  r.tracked_frames = s.tracked_frames;
  r.keyframes = s.keyframes;
  r.frames_dropped = s.live ? s.live->dropped_frames.size() : 0;
  r.resets = s.resets;
  r.wall_seconds = s.wall_seconds;
  r.frames_per_second = s.frames_per_second;
  r.stats_json = s.stats.dump(2);
  return r;
}

void Odometry::save(const std::filesystem::path& dir) const {
  if (!impl_->summary) throw InputError(dir, "Odometry::save(): call finish() first");
  vo::OdometrySession::save(*impl_->summary, dir);
}

}  // namespace pllvo
