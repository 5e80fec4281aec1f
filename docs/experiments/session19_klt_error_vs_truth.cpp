// Session 19 experiment (docs/vo.md, "Session 19"): KLT track error against rendered truth,
// split along / across the true image motion, to tell whether motion blur biases tracks.
// Shi-Tomasi corners of frame k (quality QUALITY) are tracked into frame k+1 with the VO's KLT
// settings (21 px window, 3 levels, seeded 5.8 px off the truth), on frames scaled to mean 110 and
// smoothed with sigma 1.5 as the VO does in low light. Truth: the corner's rendered depth moved
// with the ground-truth poses. Errors over 3 px count as gross and stay out of the statistics.
//
// Build (from the repo, after the library is built):
//   g++ -O2 -std=c++20 -Wno-deprecated-enum-enum-conversion -DFMT_SHARED -DSPDLOG_COMPILED_LIB -DSPDLOG_FMT_EXTERNAL -DSPDLOG_SHARED_LIB \
//     -Isrc -I/usr/include/eigen3 -I/usr/include/opencv4 docs/experiments/session19_klt_error_vs_truth.cpp \
//     build/src/libpllvo.a -o /tmp/klt_error -lopencv_imgcodecs -lopencv_imgproc -lopencv_video \
//     -lopencv_core -lopencv_calib3d -lopencv_features2d -lyaml-cpp -lspdlog -lfmt
// Run: /tmp/klt_error SEQ FIRST LAST QUALITY  (SEQ rendered by `pllvo synth ... --depth`)
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include "pllvo/io/sequence.h"
using namespace pllvo;
int main(int argc, char** argv) {
  const std::filesystem::path root = argv[1];
  const int first = std::atoi(argv[2]), last = std::atoi(argv[3]);
  auto seq = io::open_sequence(root, {});
  const auto& cam = *seq->calibration().cam0;
  const auto& gt = *seq->ground_truth();
  auto pose_at = [&](double t) {
    size_t best = 0;
    for (size_t i = 0; i < gt.stamps.size(); ++i) if (std::abs(gt.stamps[i] - t) < std::abs(gt.stamps[best] - t)) best = i;
    return gt.poses[best];
  };
  auto prep = [](const cv::Mat& im) {
    cv::Mat f; const double m = cv::mean(im)[0]; im.convertTo(f, CV_8U, 110.0 / std::max(m, 1.0));
    cv::Mat g; cv::GaussianBlur(f, g, cv::Size(), 1.5); return g; };
  double sum_a = 0, sum_c = 0, sq_a = 0, sq_c = 0; long n_all = 0, n_bad = 0;
  for (int k = first; k < last; ++k) {
    const auto f0 = seq->frame(k), f1 = seq->frame(k + 1);
    const auto ip = seq->image_path(k, 0);
    const std::string name = (ip.parent_path().parent_path() / "depth" / ip.filename()).string();
    const cv::Mat depth = cv::imread(name, cv::IMREAD_UNCHANGED);
    if (depth.empty()) { std::fprintf(stderr, "no depth %s\n", name.c_str()); return 1; }
    const cv::Mat a = prep(f0.left), b = prep(f1.left);
    std::vector<cv::Point2f> pts; cv::goodFeaturesToTrack(a, pts, 300, std::atof(argv[4]), 12, cv::noArray(), 3);
    const Eigen::Isometry3d T01 = pose_at(f0.timestamp).inverse() * pose_at(f1.timestamp);  // T_c0_c1
    const Eigen::Isometry3d T10 = T01.inverse();
    std::vector<cv::Point2f> truth, seed; std::vector<int> keep;
    for (size_t i = 0; i < pts.size(); ++i) {
      const int u = std::lround(pts[i].x), v = std::lround(pts[i].y);
      const double z = depth.at<uint16_t>(v, u) * 1e-3; if (z <= 0) continue;
      Eigen::Vector3d bear; if (!cam.unproject({pts[i].x, pts[i].y}, bear)) continue;
      Eigen::Vector2d uv; if (!cam.project(T10 * (bear / bear.z() * z), uv)) continue;
      truth.emplace_back(uv.x(), uv.y()); seed.push_back(truth.back()); keep.push_back(i);
    }
    std::vector<cv::Point2f> from; for (int i : keep) from.push_back(pts[i]);
    std::vector<unsigned char> st; std::vector<float> err;
    std::vector<cv::Point2f> out = seed;
    // seed with the truth plus a 5 px offset, as a motion prior would be off
    for (auto& p : out) p += cv::Point2f(5, -3);
    cv::calcOpticalFlowPyrLK(a, b, from, out, st, err, cv::Size(21, 21), 3,
                             cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01), cv::OPTFLOW_USE_INITIAL_FLOW, 1e-4);
    double fa = 0, fc = 0, fa2 = 0, fc2 = 0; int m = 0; double flow = 0;
    for (size_t j = 0; j < from.size(); ++j) {
      if (!st[j]) continue;
      cv::Point2f d = truth[j] - from[j]; const double L = cv::norm(d); flow += L;
      cv::Point2f e = out[j] - truth[j];
      if (cv::norm(e) > 3) { ++n_bad; continue; }
      if (L < 3) continue;
      const double ea = (e.x * d.x + e.y * d.y) / L, ec = (-e.x * d.y + e.y * d.x) / L;
      fa += ea; fc += ec; fa2 += ea * ea; fc2 += ec * ec; ++m;
    }
    n_all += m; sum_a += fa; sum_c += fc; sq_a += fa2; sq_c += fc2;
    if (m) std::printf("frame %d: flow %.1f px, %d good, along mean %+.3f rms %.3f, across mean %+.3f rms %.3f\n", k, flow / from.size(), m,
                       fa / m, std::sqrt(fa2 / m), fc / m, std::sqrt(fc2 / m));
  }
  std::printf("ALL: %ld good, %ld off by >3 px; along mean %+.3f rms %.3f; across mean %+.3f rms %.3f\n", n_all, n_bad,
              sum_a / n_all, std::sqrt(sq_a / n_all), sum_c / n_all, std::sqrt(sq_c / n_all));
}
