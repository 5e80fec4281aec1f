// The lighting modes and the sensor do what they say: brightness, noise level, flicker,
// exposure changes, lights going off, vignetting. Measured on a fixed view of the room so
// that only the lighting changes between frames.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "synth_fixtures.h"

using namespace pllvo::synth;
using namespace pllvo::synth::testing;

namespace {

SequenceSpec lighting_spec(const std::string& mode, double duration = 6.0) {
  SequenceSpec spec = preset("medium_normal");
  spec.lighting.mode = mode;
  spec.duration_s = duration;
  spec.sensor.motion_blur = false;
  return spec;
}

double mean_of(const cv::Mat& img) { return cv::mean(img)[0]; }

struct NoiseStats {
  double measured = 0, predicted = 0;
};

/// Noise of a recorded frame against its noise-free version, over pixels away from 0 and
/// 255, and what the sensor model predicts (shot + read noise + quantisation).
NoiseStats noise_stats(Generator& gen, size_t frame) {
  RenderOptions opt;
  opt.clean = true;
  const RenderedFrame f = gen.render(frame, opt);
  const cv::Mat& clean = f.cameras[0].clean;
  cv::Mat img;
  f.cameras[0].image.convertTo(img, CV_32F);
  const double gain = f.exposure.gain;
  double sum2 = 0, pred2 = 0;
  int n = 0;
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const float cl = clean.at<float>(r, c);
      if (cl < 8 || cl > 240) continue;
      const double d = img.at<float>(r, c) - cl;
      sum2 += d * d;
      const double electrons = cl * gen.spec().sensor.electrons_per_dn / gain;
      const double s = gen.sensor().noise_std_dn(electrons, gain);
      pred2 += s * s + 1.0 / 12.0;
      ++n;
    }
  return {std::sqrt(sum2 / n), std::sqrt(pred2 / n)};
}

}  // namespace

TEST(SynthImageFormation, NormalLightingIsWellExposedWithModestNoise) {
  Generator gen = static_room(lighting_spec("normal"));
  const RenderedFrame f = gen.render(0);
  const double m = mean_of(f.cameras[0].image);
  EXPECT_GT(m, 60);
  EXPECT_LT(m, 170);
  const NoiseStats n = noise_stats(gen, 0);
  std::printf("normal: mean %.1f DN, noise %.2f DN (model %.2f)\n", m, n.measured, n.predicted);
  EXPECT_NEAR(n.measured / n.predicted, 1.0, 0.1);
  EXPECT_GT(n.measured, 0.8);
  EXPECT_LT(n.measured, 4.0);
}

TEST(SynthImageFormation, LowLightIsDarkAndNoisy) {
  Generator normal = static_room(lighting_spec("normal"));
  Generator low = static_room(lighting_spec("low_light"));
  const RenderedFrame fn = normal.render(0), fl = low.render(0);
  const double mn = mean_of(fn.cameras[0].image), ml = mean_of(fl.cameras[0].image);
  EXPECT_LT(ml, 45);
  EXPECT_LT(ml, 0.45 * mn);
  // Exposure and gain at their limits.
  EXPECT_DOUBLE_EQ(fl.exposure.exposure_ms, low.spec().sensor.max_exposure_ms);
  EXPECT_DOUBLE_EQ(fl.exposure.gain, low.spec().sensor.max_gain);
  const NoiseStats nn = noise_stats(normal, 0), nl = noise_stats(low, 0);
  std::printf("low light: mean %.1f DN, noise %.2f DN (model %.2f), exposure %.1f ms, gain %.1f\n", ml, nl.measured,
              nl.predicted, fl.exposure.exposure_ms, fl.exposure.gain);
  EXPECT_NEAR(nl.measured / nl.predicted, 1.0, 0.1);
  // Relative noise (noise over signal) is several times that of normal light.
  EXPECT_GT((nl.measured / ml) / (nn.measured / mn), 3.0);
}

TEST(SynthImageFormation, FlickerModulatesBrightnessFrameToFrame) {
  Generator flicker = static_room(lighting_spec("flicker", 3.0));
  Generator normal = static_room(lighting_spec("normal", 3.0));
  std::vector<double> mf, mn;
  for (size_t i = 0; i < 30; ++i) {
    mf.push_back(mean_of(flicker.render(i).cameras[0].image));
    mn.push_back(mean_of(normal.render(i).cameras[0].image));
  }
  auto rel_std = [](const std::vector<double>& v) {
    double m = 0, s = 0;
    for (double x : v) m += x;
    m /= v.size();
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / v.size()) / m;
  };
  std::printf("flicker: frame brightness varies %.1f%% (normal %.2f%%)\n", 100 * rel_std(mf), 100 * rel_std(mn));
  EXPECT_GT(rel_std(mf), 0.1);
  EXPECT_LT(rel_std(mn), 0.01);
  // The light level reported per frame explains the brightness.
  for (size_t i = 0; i < 30; ++i)
    EXPECT_NEAR(mf[i] / mn[i], flicker.exposure().frame(i).light_level, 0.05 * flicker.exposure().frame(i).light_level);
}

TEST(SynthImageFormation, SuddenExposureChangesJumpAndGradualOnesCreep) {
  Generator sudden = static_room(lighting_spec("exposure_sudden", 10.0));
  Generator gradual = static_room(lighting_spec("exposure_gradual", 10.0));
  double max_jump_sudden = 1, max_step_gradual = 1, lo = 1e9, hi = 0;
  double prev_s = -1, prev_g = -1;
  for (size_t i = 0; i < sudden.num_frames(); i += 2) {
    const double ms = mean_of(sudden.render(i).cameras[0].image);
    const double mg = mean_of(gradual.render(i).cameras[0].image);
    if (prev_s > 0) {
      max_jump_sudden = std::max(max_jump_sudden, std::max(ms / prev_s, prev_s / ms));
      max_step_gradual = std::max(max_step_gradual, std::max(mg / prev_g, prev_g / mg));
    }
    lo = std::min(lo, mg), hi = std::max(hi, mg);
    prev_s = ms, prev_g = mg;
  }
  EXPECT_GT(max_jump_sudden, 1.8);
  EXPECT_LT(max_step_gradual, 1.35);
  EXPECT_GT(hi / lo, 3.0);
}

TEST(SynthImageFormation, LightOffDarkensThenAutoExposureRecoversWithNoise) {
  SequenceSpec spec = lighting_spec("light_off", 6.0);
  spec.lighting.light_off_at = 0.5;  // at 3 s
  Generator gen = static_room(spec);
  const size_t before = 55, right_after = 61, late = gen.num_frames() - 1;
  const RenderedFrame f0 = gen.render(before), f1 = gen.render(right_after), f2 = gen.render(late);
  const double m0 = mean_of(f0.cameras[0].image), m1 = mean_of(f1.cameras[0].image), m2 = mean_of(f2.cameras[0].image);
  std::printf("light off: mean %.1f -> %.1f -> %.1f DN (gain %.2f at the end)\n", m0, m1, m2, f2.exposure.gain);
  EXPECT_LT(m1, 0.35 * m0);
  EXPECT_GT(m2, 2.0 * m1);               // auto exposure brings it back up...
  EXPECT_GT(f2.exposure.gain, 1.5);      // ...with gain, so the image is noisier
  EXPECT_GT(noise_stats(gen, late).measured, 1.5 * noise_stats(gen, before).measured);
}

TEST(SynthImageFormation, VignettingDarkensTheCornersAsModelled) {
  SceneBuilder b;
  const int q = b.add_facing(Eigen::Vector3d(0, 3, 1.5), -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 20, 20,
                             [] {
                               Texture t;
                               t.image = cv::Mat(8, 8, CV_32F, cv::Scalar(0.5));
                               return t;
                             }());
  (void)q;
  Scene scene = b.finish();
  SequenceSpec spec = quiet_spec();
  spec.sensor.vignetting = 0.5;
  Generator gen(spec, scene, std::make_shared<StaticPath>(camera_facing_wall()));
  RenderOptions opt;
  opt.clean = true;
  opt.noise = false;
  const cv::Mat clean = gen.render(0, opt).cameras[0].clean;
  // On a fronto-parallel wall the irradiance is uniform, so the image follows the vignetting map.
  const cv::Mat& v = gen.sensor().vignetting();
  const double centre = clean.at<float>(240, 376) / v.at<float>(240, 376);
  for (auto [r, c] : {std::pair{5, 5}, std::pair{5, 746}, std::pair{474, 5}, std::pair{474, 746}, std::pair{240, 5}}) {
    EXPECT_LT(v.at<float>(r, c), 0.85);
    EXPECT_NEAR(clean.at<float>(r, c) / v.at<float>(r, c), centre, 0.02 * centre);
  }
}
