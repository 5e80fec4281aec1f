// The library API (pllvo/api): the same trajectory as `pllvo run --single-thread`, bad input as
// typed errors that leave the odometry working, live input that drops instead of blocking.
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <unistd.h>

#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "../vo/synthetic_sequence.h"
#include "pllvo/api/dataset.h"
#include "pllvo/api/odometry.h"
#include "pllvo/common/fixtures.h"
#include "pllvo/vo/run_sequence.h"

namespace pllvo {
namespace {

namespace fs = std::filesystem;

fs::path stereo_sequence() { return vo::testing::rendered(vo::testing::small_spec("easy_normal", 3.0, true), "api_stereo"); }

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path temp_dir(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("pllvo_api_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

/// `pllvo run --single-thread` on the same folder and config, written to `out`.
vo::RunSummary reference_run(const fs::path& dataset, const vo::VoConfig& config, const fs::path& out) {
  const auto sequence = io::open_sequence(dataset);
  vo::RunOptions options;
  options.out_dir = out;
  return vo::run_sequence(*sequence, config, options);
}

void expect_same_poses(const std::vector<StampedPose>& api, const io::Trajectory& reference) {
  ASSERT_EQ(api.size(), reference.size());
  for (size_t i = 0; i < api.size(); ++i) {
    EXPECT_EQ(api[i].timestamp, reference.stamps[i]);
    EXPECT_EQ(api[i].T_world_cam0, reference.poses[i].matrix()) << "pose " << i;  // bitwise
  }
}

TEST(OdometryApi, TracksToTheSameTrajectoryAsRunSingleThread) {
  const vo::VoConfig config = vo::testing::deterministic();
  const auto ref_dir = temp_dir("ref");
  const vo::RunSummary ref = reference_run(stereo_sequence(), config, ref_dir);
  ASSERT_GT(ref.tracked_frames, 50u);

  const Dataset dataset(stereo_sequence());
  Odometry odometry(dataset.calibration(), config);
  ASSERT_TRUE(odometry.stereo());
  size_t keyframes = 0;
  for (size_t i = 0; i < dataset.size(); ++i) {
    const DatasetFrame f = dataset.frame(i);
    const TrackResult r = odometry.track(f.timestamp, f.left, f.right);
    EXPECT_EQ(r.frame_index, i);
    keyframes += r.keyframe ? 1 : 0;
    if (r.tracked) {
      EXPECT_EQ(r.state, TrackingState::kTracking);
      EXPECT_GT(r.tracked_points, 0);
      EXPECT_EQ(r.points.size(), r.point_in_map.size());
    }
  }
  odometry.finish();
  expect_same_poses(odometry.trajectory(), ref.trajectory);
  expect_same_poses(odometry.keyframes(), ref.keyframe_trajectory);
  EXPECT_EQ(keyframes, ref.keyframes);  // every keyframe was flagged on its frame
  EXPECT_EQ(odometry.map_points().size(), ref.map.points.size());

  const auto out = temp_dir("save");
  odometry.save(out);
  EXPECT_EQ(read_file(out / "trajectory.tum"), read_file(ref_dir / "trajectory.tum"));
  EXPECT_EQ(read_file(out / "keyframes.tum"), read_file(ref_dir / "keyframes.tum"));
  EXPECT_EQ(read_file(out / "map.ply"), read_file(ref_dir / "map.ply"));
  EXPECT_EQ(odometry.report().tracked_frames, ref.tracked_frames);
}

// A camera driver fills the same buffers for every frame; the odometry keeps images past the call
// (a keyframe's depth, the previous image for the contrast fallback), so it must not keep the
// caller's buffers.
TEST(OdometryApi, ACallersReusedBuffersGiveTheSameTrajectory) {
  const vo::VoConfig config = vo::testing::default_single_thread();
  const Dataset dataset(shared_path("data/tum_fr3_office_snippet"));
  Odometry fresh(dataset.calibration(), config), reused(dataset.calibration(), config);
  cv::Mat image, depth;
  for (size_t i = 0; i < dataset.size(); ++i) {
    const DatasetFrame f = dataset.frame(i);
    fresh.track_rgbd(f.timestamp, f.left, f.depth);
    f.left.copyTo(image);  // same size and type: the same memory every frame
    f.depth.copyTo(depth);
    reused.track_rgbd(f.timestamp, image, depth);
    image.setTo(0);  // the driver writes into them while the odometry goes on
    depth.setTo(0);
  }
  fresh.finish();
  reused.finish();
  const auto a = fresh.trajectory(), b = reused.trajectory();
  ASSERT_EQ(a.size(), 16u);
  ASSERT_EQ(b.size(), a.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].T_world_cam0, b[i].T_world_cam0) << "pose " << i;
}

// RGB-D through the API: TUM fr3 office's depth images as the dataset gives them (float metres)
// and as a camera driver would (16-bit, 5000 per metre) give `pllvo run --single-thread`'s
// trajectory (which test_rgbd checks against the ground truth: 3.0 mm over 16/16 frames).
TEST(OdometryApi, RgbdFramesTrackToTheSameTrajectoryAsRun) {
  const fs::path tum = shared_path("data/tum_fr3_office_snippet");
  const vo::VoConfig config = vo::testing::default_single_thread();
  const vo::RunSummary ref = reference_run(tum, config, temp_dir("rgbd_ref"));
  ASSERT_TRUE(ref.depth);
  ASSERT_EQ(ref.tracked_frames, 16u);

  const Dataset dataset(tum);
  ASSERT_TRUE(dataset.calibration().depth());
  EXPECT_EQ(dataset.calibration().depth_units_per_metre(), 5000.0);
  for (const bool sixteen_bit : {false, true}) {
    SCOPED_TRACE(sixteen_bit ? "CV_16UC1 depth" : "CV_32FC1 depth");
    Odometry odometry(dataset.calibration(), config);
    ASSERT_TRUE(odometry.rgbd());
    ASSERT_FALSE(odometry.stereo());
    for (size_t i = 0; i < dataset.size(); ++i) {
      const DatasetFrame f = dataset.frame(i);
      ASSERT_EQ(f.depth.type(), CV_32FC1);
      cv::Mat depth = f.depth;
      if (sixteen_bit) f.depth.convertTo(depth, CV_16U, 5000.0);  // back to the sensor's units
      EXPECT_TRUE(odometry.track_rgbd(f.timestamp, f.left, depth).tracked) << "frame " << i;
    }
    odometry.finish();
    expect_same_poses(odometry.trajectory(), ref.trajectory);
  }

  // A calibration without depth gives a monocular odometry that refuses depth frames; depth of
  // another type or size is an InputError naming the frame; the next good frame still tracks.
  const Calibration mono = Calibration::mono(CameraIntrinsics{640, 480, 535.4, 539.2, 320.1, 247.6});
  EXPECT_FALSE(mono.depth());
  Odometry mono_odometry(mono, config);
  EXPECT_FALSE(mono_odometry.rgbd());
  const DatasetFrame f0 = dataset.frame(0);
  EXPECT_THROW(mono_odometry.track_rgbd(f0.timestamp, f0.left, f0.depth), InputError);
  EXPECT_THROW(mono.with_depth(0), InputError);
  EXPECT_THROW(mono.with_depth(std::numeric_limits<double>::quiet_NaN()), InputError);
  Odometry rgbd(mono.with_depth(5000), config);
  EXPECT_TRUE(rgbd.rgbd());
  cv::Mat bytes;
  f0.depth.convertTo(bytes, CV_8U);
  try {
    rgbd.track_rgbd(f0.timestamp, f0.left, bytes);
    ADD_FAILURE() << "8-bit depth accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("CV_16UC1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(rgbd.track_rgbd(f0.timestamp, f0.left, f0.depth(cv::Rect(0, 0, 320, 240)).clone()), InputError);
  EXPECT_NO_THROW(rgbd.track_rgbd(f0.timestamp, f0.left, f0.depth));
}

TEST(OdometryApi, BadFramesAreInputErrorsAndTheNextGoodFrameTracksAsUsual) {
  const vo::VoConfig config = vo::testing::deterministic();
  const vo::RunSummary ref = reference_run(stereo_sequence(), config, {});
  const Dataset dataset(stereo_sequence());
  Odometry odometry(dataset.calibration(), config);
  for (size_t i = 0; i < dataset.size(); ++i) {
    const DatasetFrame f = dataset.frame(i);
    if (i == 10) {
      cv::Mat small;
      cv::resize(f.left, small, cv::Size(f.left.cols / 2, f.left.rows / 2));
      EXPECT_THROW(odometry.track(f.timestamp, small, f.right), InputError);
      EXPECT_THROW(odometry.track(f.timestamp, cv::Mat(), f.right), InputError);
      EXPECT_THROW(odometry.track(f.timestamp, f.left), InputError);  // stereo needs the right image
      cv::Mat wide;
      f.left.convertTo(wide, CV_16U, 256.0);
      EXPECT_THROW(odometry.track(f.timestamp, wide, f.right), InputError);
      EXPECT_THROW(odometry.track(std::numeric_limits<double>::quiet_NaN(), f.left, f.right), InputError);
      EXPECT_THROW(odometry.track(dataset.frame(i - 1).timestamp, f.left, f.right), InputError);  // not later
      try {
        odometry.track(f.timestamp, small, f.right);
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("188x120"), std::string::npos) << e.what();
      }
    }
    if (i == 20) {  // a BGR frame is converted, as OpenCV reads it
      cv::Mat left_bgr, right_bgr;
      cv::cvtColor(f.left, left_bgr, cv::COLOR_GRAY2BGR);
      cv::cvtColor(f.right, right_bgr, cv::COLOR_GRAY2BGR);
      odometry.track(f.timestamp, left_bgr, right_bgr);
      continue;
    }
    odometry.track(f.timestamp, f.left, f.right);
  }
  odometry.finish();
  // Frame indices count accepted frames only, so the trajectory is the clean run's.
  expect_same_poses(odometry.trajectory(), ref.trajectory);
  EXPECT_THROW(odometry.track(100.0, dataset.frame(0).left, dataset.frame(0).right), InputError);  // finished
}

TEST(OdometryApi, CalibrationsFromEveryFormatAndBadStructs) {
  const Calibration euroc = Calibration::load(shared_path("data/euroc_V1_01_easy_micro"));
  EXPECT_TRUE(euroc.stereo());
  EXPECT_EQ(euroc.width(), 752);
  EXPECT_NEAR(euroc.baseline(), 0.110, 0.002);  // EuRoC's stereo rig: 11.0 cm
  const Calibration sensor =
      Calibration::load(shared_path("data/euroc_V1_01_easy_micro") / "mav0" / "cam0" / "sensor.yaml");
  EXPECT_FALSE(sensor.stereo());
  EXPECT_EQ(sensor.height(), 480);
  const Calibration kitti = Calibration::load(shared_path("data/kitti_06_stereo51") / "sequences" / "06");
  EXPECT_NEAR(kitti.baseline(), 0.537, 0.002);  // KITTI's gray pair: 53.7 cm
  EXPECT_EQ(kitti.width(), 1226);
  EXPECT_FALSE(kitti.left_only().stereo());
  EXPECT_THROW(Calibration::load("/no/such/camera.yaml"), InputError);

  CameraIntrinsics c{640, 480, 500, 500, 320, 240, "none", {}};
  EXPECT_FALSE(Calibration::mono(c).stereo());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.1, 0, 0);
  EXPECT_NEAR(Calibration::stereo_pair(c, c, T).baseline(), 0.1, 1e-12);
  EXPECT_THROW(Calibration::stereo_pair(c, c, Eigen::Isometry3d::Identity()), InputError);  // no baseline
  CameraIntrinsics nan = c;
  nan.fx = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Calibration::mono(nan), InputError);
  CameraIntrinsics empty = c;
  empty.width = 0;
  EXPECT_THROW(Calibration::mono(empty), InputError);
  CameraIntrinsics bad_distortion = c;
  bad_distortion.distortion_model = "radtan";
  bad_distortion.distortion = {0.1, std::numeric_limits<double>::infinity(), 0, 0};
  EXPECT_THROW(Calibration::mono(bad_distortion), InputError);
}

TEST(OdometryApi, ConfigFromYamlAndOverridesWithErrorsNamingTheKey) {
  OdometryOptions o;
  o.overrides = {{"frontend.type", "orb"}, {"keyframes.max_interval_s", "0.5"}};
  o.single_thread = true;
  const vo::VoConfig c = vo_config_of(o);
  EXPECT_EQ(c.frontend.type, "orb");
  EXPECT_FALSE(c.run.threaded);
  o.overrides = {{"keyframes.no_such_key", "1"}};
  try {
    vo_config_of(o);
    ADD_FAILURE() << "an unknown key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_key"), std::string::npos) << e.what();
  }
  o.overrides.clear();
  o.config_yaml = "/no/such/vo.yaml";
  EXPECT_THROW(vo_config_of(o), InputError);
}

TEST(OdometryApi, LiveInputDropsFramesInsteadOfBlockingTheCamera) {
  vo::VoConfig config = vo::testing::deterministic();
  config.run.threaded = true;
  const Dataset dataset(stereo_sequence());
  std::vector<DatasetFrame> frames;
  for (size_t i = 0; i < dataset.size(); ++i) frames.push_back(dataset.frame(i));
  OdometryOptions options;
  options.live = true;
  Odometry odometry(dataset.calibration(), config, options);
  std::atomic<size_t> results{0};
  std::atomic<size_t> last_index{0};
  odometry.on_result([&](const TrackResult& r) {
    ++results;
    last_index = r.frame_index;
  });
  // A camera far faster than tracking: every frame at once, as from a burst.
  size_t replaced = 0;
  double slowest_push_s = 0;
  for (const auto& f : frames) {
    const auto t0 = std::chrono::steady_clock::now();
    replaced += odometry.push(f.timestamp, f.left, f.right) ? 1 : 0;
    slowest_push_s = std::max(slowest_push_s, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  odometry.finish();
  const RunReport report = odometry.report();
  EXPECT_GT(replaced, frames.size() / 2);  // the tracker took only some frames
  EXPECT_EQ(report.frames_dropped, replaced);
  EXPECT_EQ(results + replaced, frames.size());  // every frame tracked or dropped, once
  EXPECT_EQ(last_index, frames.size() - 1);      // the newest frame is never left behind
  EXPECT_EQ(report.frames, frames.size());
  // push() copies the image and returns: far below one frame's tracking time, measured here.
  EXPECT_LT(slowest_push_s, report.wall_seconds / static_cast<double>(results.load()));
  EXPECT_THROW(odometry.push(1e9, frames[0].left, frames[0].right), InputError);  // after finish
}

}  // namespace
}  // namespace pllvo
