// Motion blur: the smear follows the motion, its length is angular speed x exposure x focal
// length, the fast flow blur agrees with the reference (one full render per sub-exposure),
// and its AVX2 and scalar paths give the same image.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "synth_fixtures.h"

using namespace pllvo::synth;
using namespace pllvo::synth::testing;

namespace {

constexpr double kSquare = 0.1;

/// Checker wall seen head-on while the camera pans about its y axis at `omega` rad/s.
SequenceSpec pan_spec(const std::string& method, double exposure_ms) {
  SequenceSpec spec = quiet_spec();
  spec.sensor.motion_blur = true;
  spec.sensor.blur_method = method;
  spec.sensor.blur_step_px = 1.0;
  spec.sensor.exposure_ms = exposure_ms;
  spec.sensor.max_exposure_ms = exposure_ms;
  spec.sensor.sensitivity = 1200 * 10 / exposure_ms;  // the same brightness, no saturation
  spec.sensor.psf_sigma_px = 0;
  spec.sensor.vignetting = 0;
  return spec;
}

RenderedFrame render_pan(const SequenceSpec& spec, double omega) {
  const Eigen::Isometry3d pose = camera_facing_wall();
  Generator gen(spec, checker_scene(kSquare),
                std::make_shared<ConstantVelocityPath>(pose, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, omega, 0)));
  RenderOptions opt;
  opt.noise = false;
  opt.clean = true;
  return gen.render(0, opt);
}

/// Length (px) of the ramp that the checker's edges make along x (dx = 1) or y in the
/// central 241 x 161 pixels: for a step of height h blurred into a ramp of length L, the
/// differences sum to h and their squares to h^2 / L.
double edge_length(const cv::Mat& clean, int dx, int dy) {
  const cv::Mat roi = clean(cv::Rect(376 - 120, 240 - 80, 241, 161));
  double lo = 1e9, hi = -1e9, sum_abs = 0, sum_sq = 0;
  for (int r = 0; r + dy < roi.rows; ++r)
    for (int c = 0; c + dx < roi.cols; ++c) {
      const double v = roi.at<float>(r, c), g = roi.at<float>(r + dy, c + dx) - v;
      lo = std::min(lo, v), hi = std::max(hi, v);
      sum_abs += std::abs(g), sum_sq += g * g;
    }
  return (hi - lo) * sum_abs / sum_sq;
}

}  // namespace

TEST(SynthMotionBlur, SmearsAlongTheMotionOnly) {
  for (const std::string method : {"flow", "renders"}) {
    SCOPED_TRACE(method);
    SequenceSpec spec = pan_spec(method, 10);
    // Panning at 1 rad/s: ~4.6 px of horizontal motion in 10 ms.
    const RenderedFrame moving = render_pan(spec, 1.0), still = render_pan(spec, 0.0);
    EXPECT_EQ(still.subframes, 1);
    if (method == "flow") EXPECT_EQ(moving.subframes, 1);  // one render covers up to 64 px
    else EXPECT_GE(moving.subframes, 5);
    const double gx = edge_length(moving.cameras[0].clean, 1, 0) / edge_length(still.cameras[0].clean, 1, 0);
    const double gy = edge_length(moving.cameras[0].clean, 0, 1) / edge_length(still.cameras[0].clean, 0, 1);
    EXPECT_GT(gx, 2.0);
    EXPECT_NEAR(gy, 1.0, 0.1);
  }
}

TEST(SynthMotionBlur, LengthIsAngularSpeedTimesExposureTimesFocalLength) {
  const double fx = quiet_spec().camera.fx;
  for (const std::string method : {"flow", "renders"}) {
    SCOPED_TRACE(method);
    const double still = edge_length(render_pan(pan_spec(method, 10), 0.0).cameras[0].clean, 1, 0);
    // (rad/s, ms): motion 4.6, 9.2, 9.2 and 18.3 px.
    for (const auto& [omega, exposure_ms] : {std::pair{1.0, 10.0}, {2.0, 10.0}, {1.0, 20.0}, {2.0, 20.0}}) {
      const double expected = omega * exposure_ms * 1e-3 * fx;
      const double length = edge_length(render_pan(pan_spec(method, exposure_ms), omega).cameras[0].clean, 1, 0);
      std::printf("%s: %.0f rad/s x %.0f ms: edge ramp %.2f px (still %.2f), motion %.2f px\n", method.c_str(), omega,
                  exposure_ms, length, still, expected);
      // A box of length L on a ramp of length L0 makes a ramp of about L + L0 / 2.
      EXPECT_NEAR(length - still / 2, expected, 0.1 * expected + 0.5);
    }
  }
}

TEST(SynthMotionBlur, FlowBlurAgreesWithRenderedSubExposures) {
  // Fast motion and a long exposure: the hardest case for the flow blur (depth steps in the
  // room); brightness as in normal light, so that differences show.
  SequenceSpec spec = preset("difficult_normal");
  spec.duration_s = 12;
  spec.sensor.exposure_ms = spec.sensor.max_exposure_ms = 15;
  spec.sensor.sensitivity = 660;
  spec.sensor.blur_step_px = 1.0;
  spec.sensor.max_subframes = 41;
  SequenceSpec reference_spec = spec, sharp_spec = spec;
  reference_spec.sensor.blur_method = "renders";
  sharp_spec.sensor.motion_blur = false;
  Generator flow(spec), reference(reference_spec), sharp(sharp_spec);
  RenderOptions opt;
  opt.noise = false;
  opt.clean = true;
  // Mean absolute differences to the reference over the whole frame and over the pixels the
  // blur changes by more than 5 DN (edges and texture, where the approximation shows).
  double err_flow = 0, err_sharp = 0, edge_flow = 0, edge_sharp = 0;
  int frames = 0;
  for (size_t i = 20; i < flow.num_frames(); i += 40) {
    const RenderedFrame ff = flow.render(i, opt), fr = reference.render(i, opt), fs = sharp.render(i, opt);
    if (fr.subframes < 9) continue;  // little motion: nothing to compare
    cv::Mat df, ds;
    cv::absdiff(ff.cameras[0].clean, fr.cameras[0].clean, df);
    cv::absdiff(fs.cameras[0].clean, fr.cameras[0].clean, ds);
    const cv::Mat changed = ds > 5;
    const double ef = cv::mean(df)[0], es = cv::mean(ds)[0];
    const double cf = cv::mean(df, changed)[0], cs = cv::mean(ds, changed)[0];
    std::printf("frame %zu: %d reference renders, flow %d; mean |flow - reference| %.2f DN (%.2f where the blur "
                "changes > 5 DN), |sharp - reference| %.2f DN (%.2f)\n",
                i, fr.subframes, ff.subframes, ef, cf, es, cs);
    err_flow += ef, err_sharp += es, edge_flow += cf, edge_sharp += cs, ++frames;
  }
  ASSERT_GE(frames, 3);
  EXPECT_LT(err_flow, 0.25 * err_sharp);
  EXPECT_LT(edge_flow, 0.25 * edge_sharp);
  EXPECT_LT(err_flow / frames, 0.5);
}

TEST(SynthMotionBlur, SimdAndScalarFlowBlurAgreeExactly) {
  Generator gen(preset("difficult_normal"));
  const RadianceState state = bake_radiance(gen.scene(), 0, 1.0);
  const BlurRegion& region = gen.lens().blur_region(10);
  Rasterizer r(gen.lens().ideal_view(), 0.05);
  FlowBlur fast(gen.lens(), 1.0, 64, true), plain(gen.lens(), 1.0, 64, false);
  for (double t : {1.0, 7.3, 20.1}) {
    const Eigen::Isometry3d T_wc = gen.T_world_cam(0, t);
    r.render(gen.scene(), state, T_wc.inverse(), 1.0f, false, &region.all);
    const Eigen::Isometry3d T_start = gen.T_world_cam(0, t - 0.008).inverse() * T_wc;
    const Eigen::Isometry3d T_end = gen.T_world_cam(0, t + 0.008).inverse() * T_wc;
    cv::Mat a, b;
    const double samples = fast.accumulate(r, T_start, T_end, 0.7f, region, a, false);
    EXPECT_EQ(plain.accumulate(r, T_start, T_end, 0.7f, region, b, false), samples);
    EXPECT_GT(samples, 1.5);  // it blurs
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  }
}
