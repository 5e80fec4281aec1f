// Geometric truth of the rendering: ground-truth 3-D points projected with the ground-truth
// pose through the distorted camera land on the rendered features; stereo pairs are
// rectified; depth agrees with an independent ray cast.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "pllvo/synth/random.h"
#include "synth_fixtures.h"

using namespace pllvo::synth;
using namespace pllvo::synth::testing;

namespace {

constexpr double kSquare = 0.1;

struct CornerError {
  double max = 0, mean = 0;
  int count = 0;
};

/// Refines every projected checker corner with cornerSubPix, starting up to 1.5 px away,
/// and measures the distance between the refined corner and the projection.
CornerError corner_error(const cv::Mat& image, const pllvo::camera::CameraModel& cam,
                         const Eigen::Isometry3d& T_world_cam, const std::vector<Eigen::Vector3d>& corners,
                         uint64_t seed, std::vector<cv::Point2f>* refined_out = nullptr,
                         std::vector<Eigen::Vector2d>* projected_out = nullptr) {
  Random rng(seed);
  std::vector<cv::Point2f> pts;
  std::vector<Eigen::Vector2d> projected;
  for (const auto& X : corners) {
    Eigen::Vector2d uv;
    if (!cam.project(T_world_cam.inverse() * X, uv) || !cam.in_image(uv, 15)) continue;
    projected.push_back(uv);
    pts.emplace_back(static_cast<float>(uv.x() + rng.uniform(-1.5, 1.5)),
                     static_cast<float>(uv.y() + rng.uniform(-1.5, 1.5)));
  }
  cv::cornerSubPix(image, pts, cv::Size(5, 5), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
  CornerError e;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double d = (Eigen::Vector2d(pts[i].x, pts[i].y) - projected[i]).norm();
    e.max = std::max(e.max, d);
    e.mean += d;
  }
  e.count = static_cast<int>(pts.size());
  if (e.count) e.mean /= e.count;
  if (refined_out) *refined_out = pts;
  if (projected_out) *projected_out = projected;
  return e;
}

}  // namespace

TEST(SynthGeometry, ProjectedCornersHitRenderedCornersSubPixel) {
  const Scene scene = checker_scene(kSquare);
  const Quad wall = scene.quads[0];
  const auto corners = checker_corners(wall, kSquare);
  // Several poses: tilted, rolled, off-centre; corners reach the distorted image borders.
  const Eigen::Isometry3d poses[] = {camera_facing_wall(0, 0, 0, 0), camera_facing_wall(0.3, 0.15, 0.1, 0.2),
                                     camera_facing_wall(-0.4, -0.25, -0.12, -0.35)};
  for (const auto& pose : poses) {
    Generator gen(quiet_spec(), scene, std::make_shared<StaticPath>(pose));
    RenderOptions opt;
    opt.noise = false;
    const RenderedFrame f = gen.render(0, opt);
    const CornerError e = corner_error(f.cameras[0].image, *gen.camera(0), f.cameras[0].T_world_cam, corners, 7);
    std::printf("checker corners: %d, error mean %.3f px, max %.3f px\n", e.count, e.mean, e.max);
    EXPECT_GT(e.count, 150);
    EXPECT_LT(e.max, 0.35) << "mean " << e.mean;
    EXPECT_LT(e.mean, 0.12);
  }
}

TEST(SynthGeometry, CornersStaySubPixelWithNoiseAndWrongPoseIsDetected) {
  const Scene scene = checker_scene(kSquare);
  const auto corners = checker_corners(scene.quads[0], kSquare);
  const Eigen::Isometry3d pose = camera_facing_wall(0.2, 0.1, -0.05, 0.1);
  Generator gen(quiet_spec(), scene, std::make_shared<StaticPath>(pose));
  const RenderedFrame f = gen.render(0);  // with photon and read noise
  const CornerError e = corner_error(f.cameras[0].image, *gen.camera(0), f.cameras[0].T_world_cam, corners, 3);
  EXPECT_LT(e.max, 0.5);
  // The same check with a pose off by 0.2 degrees fails: the test can tell.
  Eigen::Isometry3d wrong = f.cameras[0].T_world_cam;
  wrong.linear() = wrong.linear() * Eigen::AngleAxisd(0.2 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const CornerError bad = corner_error(f.cameras[0].image, *gen.camera(0), wrong, corners, 3);
  EXPECT_GT(bad.mean, 1.0);
}

TEST(SynthGeometry, StereoPairIsRectifiedWithTheRightDisparity) {
  const Scene scene = checker_scene(kSquare);
  const Quad wall = scene.quads[0];
  const auto corners = checker_corners(wall, kSquare);
  SequenceSpec spec = quiet_spec();
  spec.camera.stereo = true;
  spec.camera.baseline_m = 0.11;
  Generator gen(spec, scene, std::make_shared<StaticPath>(camera_facing_wall(-0.05, 0.05, 0.03, 0.08)));
  RenderOptions opt;
  opt.noise = false;
  const RenderedFrame f = gen.render(0, opt);
  ASSERT_EQ(f.cameras.size(), 2u);
  // cam1 sits 0.11 m along cam0's x axis.
  const Eigen::Isometry3d T_c0_c1 = f.cameras[0].T_world_cam.inverse() * f.cameras[1].T_world_cam;
  EXPECT_LT((T_c0_c1.translation() - Eigen::Vector3d(0.11, 0, 0)).norm(), 1e-12);
  EXPECT_LT((T_c0_c1.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);

  std::vector<cv::Point2f> left, right;
  std::vector<Eigen::Vector2d> proj_left, proj_right;
  const auto& cam = *gen.camera(0);
  const CornerError el = corner_error(f.cameras[0].image, cam, f.cameras[0].T_world_cam, corners, 1, &left, &proj_left);
  const CornerError er = corner_error(f.cameras[1].image, cam, f.cameras[1].T_world_cam, corners, 2, &right, &proj_right);
  EXPECT_LT(el.max, 0.5);
  EXPECT_LT(er.max, 0.5);

  // Match corners by their 3-D point and check the epipolar constraint on undistorted points.
  const auto& k = cam.intrinsics();
  int checked = 0;
  double max_dy = 0;
  for (const auto& X : corners) {
    Eigen::Vector2d ul, ur;
    if (!cam.project(f.cameras[0].T_world_cam.inverse() * X, ul) || !cam.in_image(ul, 15)) continue;
    if (!cam.project(f.cameras[1].T_world_cam.inverse() * X, ur) || !cam.in_image(ur, 15)) continue;
    auto find = [](const std::vector<Eigen::Vector2d>& proj, const std::vector<cv::Point2f>& refined,
                   const Eigen::Vector2d& uv) {
      for (size_t i = 0; i < proj.size(); ++i)
        if ((proj[i] - uv).norm() < 1e-9) return Eigen::Vector2d(refined[i].x, refined[i].y);
      return Eigen::Vector2d(-1, -1);
    };
    const auto rl = find(proj_left, left, ul), rr = find(proj_right, right, ur);
    ASSERT_GE(rl.x(), 0);
    ASSERT_GE(rr.x(), 0);
    Eigen::Vector3d bl, br;
    ASSERT_TRUE(cam.unproject(rl, bl));
    ASSERT_TRUE(cam.unproject(rr, br));
    const double yl = k.fy * bl.y() / bl.z(), yr = k.fy * br.y() / br.z();
    max_dy = std::max(max_dy, std::abs(yl - yr));
    const double depth = (f.cameras[0].T_world_cam.inverse() * X).z();
    const double disparity = k.fx * (bl.x() / bl.z() - br.x() / br.z());
    EXPECT_NEAR(disparity, k.fx * 0.11 / depth, 0.5);
    ++checked;
  }
  EXPECT_GT(checked, 100);
  EXPECT_LT(max_dy, 0.5);
  std::printf("stereo: %d corner pairs, max row difference %.3f px\n", checked, max_dy);
}

namespace {
/// Nearest surface along a ray by brute force over all quads (front faces only).
double ray_cast_depth(const Scene& scene, const Eigen::Isometry3d& T_world_cam, const Eigen::Vector3d& bearing) {
  const Eigen::Vector3d o = T_world_cam.translation(), d = T_world_cam.linear() * bearing;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& q : scene.quads) {
    if (!q.faces(o)) continue;
    const Eigen::Vector3d n = q.normal();
    const double denom = n.dot(d);
    if (std::abs(denom) < 1e-12) continue;
    const double lambda = n.dot(q.origin - o) / denom;
    if (lambda <= 0 || lambda >= best) continue;
    const Eigen::Vector3d p = o + lambda * d - q.origin;
    const double s = p.dot(q.u) / q.u.squaredNorm(), t = p.dot(q.v) / q.v.squaredNorm();
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) best = lambda;
  }
  return best * bearing.z();
}
}  // namespace

TEST(SynthGeometry, DepthMatchesBruteForceRayCastInTheRoom) {
  SequenceSpec spec = preset("medium_normal");
  spec.duration_s = 2;
  Generator gen(spec);
  RenderOptions opt;
  opt.depth = true;
  const RenderedFrame f = gen.render(17, opt);
  const cv::Mat& depth = f.cameras[0].depth;
  ASSERT_EQ(depth.type(), CV_32F);
  Random rng(5);
  int agree = 0, total = 0;
  for (int k = 0; k < 2000; ++k) {
    const int u = rng.integer(0, depth.cols - 1), v = rng.integer(0, depth.rows - 1);
    Eigen::Vector3d b;
    ASSERT_TRUE(gen.camera(0)->unproject(Eigen::Vector2d(u, v), b));
    const double truth = ray_cast_depth(gen.scene(), f.cameras[0].T_world_cam, b);
    ++total;
    if (std::abs(depth.at<float>(v, u) - truth) < 1e-3 * truth) ++agree;
  }
  // Disagreement only where a pixel straddles an occlusion boundary.
  EXPECT_GT(agree, 0.98 * total);
}

TEST(SynthGeometry, SimdAndScalarRasterizersAgreeExactly) {
  SequenceSpec spec = preset("medium_normal");
  Generator gen(spec);
  const RadianceState state = bake_radiance(gen.scene(), 0, 1.0);
  Rasterizer fast(gen.lens().ideal_view(), 0.05, true), plain(gen.lens().ideal_view(), 0.05, false);
  for (double t : {0.0, 3.3, 11.7}) {
    const Eigen::Isometry3d T = gen.T_world_cam(0, t).inverse();
    fast.render(gen.scene(), state, T, 1.0f);
    plain.render(gen.scene(), state, T, 1.0f);
    EXPECT_EQ(cv::norm(fast.radiance(), plain.radiance(), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(fast.inverse_depth(), plain.inverse_depth(), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::countNonZero(fast.quad_ids() != plain.quad_ids()), 0);
    EXPECT_GT(cv::countNonZero(plain.quad_ids() >= 0), 0.95 * gen.lens().ideal_view().drawn.pixels());
  }
}
