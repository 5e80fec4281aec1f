#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "pllvo/features/lines/image_prefilter.h"

using namespace pllvo::lines;

namespace {
cv::Mat test_image(double level, double contrast, double noise, uint64_t seed) {
  cv::Mat f(240, 320, CV_32F, cv::Scalar(level));
  cv::rectangle(f, cv::Rect(60, 50, 150, 120), cv::Scalar(level + contrast), cv::FILLED);
  cv::Mat n(f.size(), CV_32F);
  cv::RNG(seed).fill(n, cv::RNG::NORMAL, 0.0, noise);
  cv::Mat out;
  cv::Mat(f + n).convertTo(out, CV_8U);
  return out;
}
}  // namespace

TEST(Prefilter, NoiseEstimateIsRobustToEdges) {
  for (double sigma : {2.0, 5.0, 10.0}) {
    const cv::Mat im = test_image(100, 60, sigma, 7);
    EXPECT_NEAR(estimate_noise_sigma(im), sigma, 0.12 * sigma + 0.3) << "sigma " << sigma;
  }
  EXPECT_LT(estimate_noise_sigma(test_image(100, 60, 0.0, 7)), 0.2);
}

TEST(Prefilter, CleanFramesPassUnchanged) {
  const cv::Mat im = test_image(90, 80, 1.5, 1);
  const PrefilterResult r = prefilter_for_lines(im, {}, 1.0, 20);
  EXPECT_EQ(r.gain, 1.0);
  EXPECT_EQ(r.image.data, im.data);  // no copy
  EXPECT_EQ(r.blur_sigma, 1.0);
  EXPECT_EQ(r.gradient_threshold, 20);
}

TEST(Prefilter, DarkFramesAreStretchedAndNoisyFramesSmoothed) {
  const cv::Mat dark = test_image(8, 12, 1.0, 2);  // everything below 30 grey levels
  const PrefilterResult d = prefilter_for_lines(dark, {}, 1.0, 20);
  EXPECT_GT(d.gain, 5.0);
  double lo, hi;
  cv::minMaxLoc(d.image, &lo, &hi);
  EXPECT_GE(hi, 170.0);
  EXPECT_NEAR(d.noise_sigma, 1.0 * d.gain, 0.3 * d.gain);

  const cv::Mat noisy = test_image(100, 60, 12.0, 3);
  const PrefilterResult n = prefilter_for_lines(noisy, {}, 1.0, 20);
  EXPECT_EQ(n.gain, 1.0);
  EXPECT_GT(n.blur_sigma, 2.0);
  // Beyond the largest blur, the gradient threshold rises with the noise.
  const PrefilterResult v = prefilter_for_lines(test_image(100, 80, 20.0, 4), {}, 1.0, 20);
  EXPECT_EQ(v.blur_sigma, PrefilterConfig{}.max_sigma);
  EXPECT_GT(v.gradient_threshold, 25);

  PrefilterConfig off;
  off.enabled = false;
  EXPECT_EQ(prefilter_for_lines(dark, off, 1.0, 20).gain, 1.0);
}
