#pragma once
// The synthetic camera: renders any frame of a sequence, with its exact ground truth.
//
//   synth::Generator gen(synth::preset("medium_normal"));
//   synth::RenderOptions opt;  opt.lines = true;
//   synth::RenderedFrame f = gen.render(42, opt);
//   f.cameras[0].image           // CV_8UC1 752x480, what cam0 recorded
//   f.cameras[0].T_world_cam     // its pose at the timestamp (mid-exposure)
//   f.cameras[0].segments        // visible 3-D edges as 2-D segments in that image
//
// Frames are independent: render(i) needs no earlier frame, and the same spec and seed
// give the same bytes.
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pllvo/camera/camera_model.h"
#include "pllvo/synth/camera_path.h"
#include "pllvo/synth/exposure.h"
#include "pllvo/synth/flow_blur.h"
#include "pllvo/synth/lens.h"
#include "pllvo/synth/radiance.h"
#include "pllvo/synth/rasterizer.h"
#include "pllvo/synth/scene.h"
#include "pllvo/synth/sensor.h"
#include "pllvo/synth/spec.h"
#include "pllvo/synth/truth.h"

namespace pllvo::synth {

struct RenderOptions {
  bool lines = false;  ///< fill CameraFrame::segments
  bool depth = false;  ///< fill CameraFrame::depth
  bool clean = false;  ///< fill CameraFrame::clean (noise-free digital numbers)
  bool noise = true;   ///< photon and read noise in the recorded image
};

struct CameraFrame {
  cv::Mat image;  ///< CV_8UC1: the recorded frame
  cv::Mat clean;  ///< CV_32F: expected digital numbers without noise or quantisation
  cv::Mat depth;  ///< CV_32F: z in metres along the optical axis, 0 where nothing
  std::vector<TruthSegment> segments;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
};

struct RenderedFrame {
  size_t index = 0;
  int64_t stamp_ns = 0;
  double time_s = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();  ///< of the body origin
  FrameExposure exposure;
  int subframes = 1;  ///< renders averaged for motion blur
  std::vector<CameraFrame> cameras;  ///< cam0 [, cam1]
};

class Generator {
 public:
  /// Builds the scene and the flight of `spec` (validated; InputError when invalid).
  explicit Generator(SequenceSpec spec);
  /// A given scene and camera path (tests, custom setups); `path` gives T_world_cam0(t).
  Generator(SequenceSpec spec, Scene scene, std::shared_ptr<const CameraPath> path);

  const SequenceSpec& spec() const { return spec_; }
  const Scene& scene() const { return scene_; }
  const CameraPath& path() const { return *path_; }
  const ExposureSchedule& exposure() const { return *exposure_; }
  const LensModel& lens() const { return *lens_; }
  const SensorModel& sensor() const { return *sensor_; }

  size_t num_frames() const { return spec_.num_frames(); }
  double time(size_t i) const { return spec_.frame_time(i); }
  int64_t stamp_ns(size_t i) const;
  /// Timestamp of time t (seconds from the first frame).
  int64_t stamp_ns(double t) const;

  size_t num_cameras() const { return cameras_.size(); }
  const camera::CameraPtr& camera(size_t c) const { return cameras_.at(c); }
  const Eigen::Isometry3d& T_body_cam(size_t c) const { return T_body_cam_.at(c); }
  Eigen::Isometry3d T_world_cam(size_t c, double t) const;
  Eigen::Isometry3d T_world_body(double t) const;
  Eigen::Vector3d body_velocity(double t) const;

  /// Renders frame i (not thread-safe: buffers are reused between calls).
  RenderedFrame render(size_t i, const RenderOptions& options = {});

 private:
  void init();
  CameraFrame render_camera(size_t c, size_t frame, double t, const FrameExposure& exposure,
                            const RenderOptions& options, int& subframes);
  /// Largest image motion (px) over the exposure among a grid of pixels, from main_'s depth.
  double image_motion(size_t c, double t, double exposure_s) const;
  /// Odd number of renders so that each covers at most step_px of motion (max_subframes at most).
  int num_renders(double motion, double step_px) const;
  /// distorted_ = mean of n full renders over the exposure; returns the light factor still to apply.
  double expose_by_renders(size_t c, double t, double exposure_s, int state, int n);
  /// distorted_ = n renders, each blurred along the image motion of its part of the exposure.
  void expose_by_flow(size_t c, double t, double exposure_s, int state, int n, double motion);

  SequenceSpec spec_;
  Scene scene_;
  std::shared_ptr<const CameraPath> path_;
  std::vector<camera::CameraPtr> cameras_;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> T_body_cam_;
  std::unique_ptr<LensModel> lens_;
  std::unique_ptr<SensorModel> sensor_;
  std::unique_ptr<ExposureSchedule> exposure_;
  std::vector<RadianceState> radiance_;  ///< per lighting state
  std::unique_ptr<Rasterizer> main_, scratch_;
  std::unique_ptr<FlowBlur> flow_blur_;
  cv::Mat accumulated_, distorted_, electrons_;
};

}  // namespace pllvo::synth
