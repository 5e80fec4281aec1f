// `pllvo run --source`: a video file gives the image folder's trajectory; a source that stalls,
// a corrupt frame, a size change, a truncated file and SIGTERM each end the run with their
// message and the outputs of the frames before.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <unistd.h>

#include "../support/cli_runner.h"
#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/io/video_source.h"
#include "pllvo/vo/run_sequence.h"
#include "pllvo/vo/run_source.h"
#include "synthetic_sequence.h"

namespace pllvo::vo {
namespace {

namespace fs = std::filesystem;

struct Recording {
  fs::path folder;  ///< image folder: images/*.png + camera.yaml (fps 20)
  fs::path video;   ///< the same frames, FFV1 (lossless) in Matroska
  std::vector<cv::Mat> frames;
};

/// A 4 s monocular synthetic sequence as an image folder and as a lossless video of the same frames.
const Recording& recording() {
  static const Recording r = [] {
    Recording rec;
    const auto euroc = testing::rendered(testing::small_spec("easy_normal", 4.0, false), "source_mono");
    const auto sequence = io::open_sequence(euroc);
    rec.folder = fs::temp_directory_path() / ("pllvo_source_folder_" + std::to_string(::getpid()));
    fs::remove_all(rec.folder);
    fs::create_directories(rec.folder / "images");
    camera::save_camera_yaml(*sequence->calibration().cam0, rec.folder / "camera.yaml");
    std::ofstream(rec.folder / "camera.yaml", std::ios::app) << "fps: 20\n";
    rec.video = rec.folder / "video.mkv";
    const cv::Size size(sequence->calibration().cam0->width(), sequence->calibration().cam0->height());
    cv::VideoWriter writer(rec.video.string(), cv::VideoWriter::fourcc('F', 'F', 'V', '1'), 20.0, size, false);
    EXPECT_TRUE(writer.isOpened());
    for (size_t i = 0; i < sequence->size(); ++i) {
      const cv::Mat image = sequence->frame(i).left;
      char name[32];
      std::snprintf(name, sizeof name, "%06zu.png", i);
      cv::imwrite((rec.folder / "images" / name).string(), image);
      writer.write(image);
      rec.frames.push_back(image);
    }
    return rec;
  }();
  return r;
}

fs::path fresh(const std::string& name) {
  const auto d = fs::temp_directory_path() / ("pllvo_source_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

io::Calibration calibration() { return io::open_sequence(recording().folder)->calibration(); }

void expect_outputs(const fs::path& out) {
  for (const char* f : {"trajectory.tum", "keyframes.tum", "stats.json", "map.ply"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
}

/// A source double: the recording's frames from a grabber that misbehaves at frame `at`.
std::unique_ptr<io::VideoSource> double_source(std::function<bool(size_t, io::GrabbedFrame&)> at_frame,
                                               double stall_timeout_s = 5.0) {
  auto i = std::make_shared<size_t>(0);
  io::VideoSourceOptions options;
  options.stall_timeout_s = stall_timeout_s;
  return std::make_unique<io::VideoSource>(
      "double",
      [i, at_frame](io::GrabbedFrame& f) {
        const size_t k = (*i)++;
        if (k >= recording().frames.size()) return false;
        f.image = recording().frames[k];
        f.timestamp_s = k / 20.0;
        return at_frame(k, f);
      },
      false, options);
}

TEST(RunSource, LosslessVideoGivesTheImageFolderTrajectory) {
  const VoConfig config = testing::deterministic();
  RunOptions folder_options;
  const RunSummary folder = run_sequence(*io::open_sequence(recording().folder), config, folder_options);
  ASSERT_GT(folder.tracked_frames, 60u);

  const auto source = io::VideoSource::open(recording().video.string());
  EXPECT_FALSE(source->live());
  SourceRunOptions options;
  options.out_dir = fresh("video");
  const SourceRunResult video = run_source(*source, calibration(), config, options);
  EXPECT_EQ(video.ended_by, "end_of_stream");
  EXPECT_FALSE(video.failed());
  ASSERT_EQ(video.summary.trajectory.size(), folder.trajectory.size());
  for (size_t i = 0; i < folder.trajectory.size(); ++i) {
    EXPECT_EQ(video.summary.trajectory.stamps[i], folder.trajectory.stamps[i]);
    EXPECT_EQ(video.summary.trajectory.poses[i].matrix(), folder.trajectory.poses[i].matrix()) << "frame " << i;
  }
  expect_outputs(options.out_dir);
}

TEST(RunSource, AStalledSourceEndsTheRunWithItsMessageAndKeepsTheOutputs) {
  const auto source = double_source(
      [](size_t k, io::GrabbedFrame&) {
        if (k == 60) std::this_thread::sleep_for(std::chrono::seconds(10));  // the camera stops
        return true;
      },
      0.5);
  SourceRunOptions options;
  options.out_dir = fresh("stall");
  const auto t0 = std::chrono::steady_clock::now();
  const SourceRunResult r = run_source(*source, calibration(), testing::deterministic(), options);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 8.0);  // did not wait it out
  EXPECT_EQ(r.ended_by, "stalled");
  EXPECT_TRUE(r.failed());
  EXPECT_NE(r.message.find("no frame for 0.5 s after 60 frames"), std::string::npos) << r.message;
  EXPECT_EQ(r.summary.frames, 60u);
  EXPECT_GT(r.summary.tracked_frames, 10u);  // the monocular map starts after ~1 s of parallax
  expect_outputs(options.out_dir);
}

TEST(RunSource, ACorruptFrameEndsTheRunNamingTheFrame) {
  const auto source = double_source([](size_t k, io::GrabbedFrame& f) {
    if (k == 25) f.image = cv::Mat();
    return true;
  });
  SourceRunOptions options;
  options.out_dir = fresh("corrupt");
  const SourceRunResult r = run_source(*source, calibration(), testing::deterministic(), options);
  EXPECT_EQ(r.ended_by, "bad_frame");
  EXPECT_NE(r.message.find("frame 25 is empty"), std::string::npos) << r.message;
  EXPECT_EQ(r.summary.frames, 25u);
  expect_outputs(options.out_dir);
}

TEST(RunSource, ASizeChangeEndsTheRunNamingBothSizes) {
  const auto source = double_source([](size_t k, io::GrabbedFrame& f) {
    if (k == 25) cv::resize(f.image, f.image, cv::Size(320, 200));
    return true;
  });
  SourceRunOptions options;
  options.out_dir = fresh("resize");
  const SourceRunResult r = run_source(*source, calibration(), testing::deterministic(), options);
  EXPECT_EQ(r.ended_by, "bad_frame");
  EXPECT_NE(r.message.find("320x200"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("376x240"), std::string::npos) << r.message;
  EXPECT_EQ(r.summary.frames, 25u);
  expect_outputs(options.out_dir);
}

TEST(RunSource, ATruncatedFileIsReportedAndWhatWasReadIsKept) {
  const fs::path cut = fresh("truncated_video");
  fs::create_directories(cut);
  const fs::path video = cut / "cut.mkv";
  fs::copy_file(recording().video, video);
  fs::resize_file(video, fs::file_size(video) / 2);
  const auto source = io::VideoSource::open(video.string());
  ASSERT_EQ(source->expected_frames(), recording().frames.size());  // Matroska states its length
  SourceRunOptions options;
  options.out_dir = cut / "out";
  const SourceRunResult r = run_source(*source, calibration(), testing::deterministic(), options);
  EXPECT_EQ(r.ended_by, "truncated");
  EXPECT_NE(r.message.find("of the " + std::to_string(recording().frames.size()) + " frames"), std::string::npos)
      << r.message;
  EXPECT_GT(r.summary.frames, 10u);
  EXPECT_LT(r.summary.frames, recording().frames.size());
  expect_outputs(options.out_dir);
}

TEST(RunSource, SigtermEndsACliRunCleanlyWithEveryOutput) {
  const fs::path out = fresh("sigterm");
  // --realtime: the 4 s recording plays at its rate, so the signal after 1.5 s comes mid-run.
  const auto r = test::run_cli("run --source " + recording().video.string() + " --camera " +
                                   (recording().folder / "camera.yaml").string() + " --frontend orb --realtime --out " +
                                   out.string(),
                               "timeout --preserve-status -s TERM 1.5");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ended by: stopped"), std::string::npos) << r.output;
  expect_outputs(out);
  std::ifstream stats(out / "stats.json");
  const auto j = nlohmann::json::parse(stats);
  EXPECT_EQ(j["ended_by"], "stopped");
  EXPECT_LT(j["frames"].get<size_t>(), recording().frames.size());
  EXPECT_GT(j["frames"].get<size_t>(), 5u);
}

TEST(RunSource, CliSourceErrorsAreClear) {
  const fs::path out = fresh("cli_errors");
  auto r = test::run_cli("run --source /no/such/video.mkv --camera " + (recording().folder / "camera.yaml").string() +
                         " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot open this video source"), std::string::npos) << r.output;
  r = test::run_cli("run --source " + recording().video.string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--source needs --camera"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace pllvo::vo
