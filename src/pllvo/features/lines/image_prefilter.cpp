#include "pllvo/features/lines/image_prefilter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace pllvo::lines {

void PrefilterConfig::load(const ConfigNode& node) {
  node.get("enabled", enabled);
  node.get("bright_percentile", bright_percentile);
  node.get("dark_level", dark_level);
  node.get("target_level", target_level);
  node.get("max_gain", max_gain);
  node.get("clean_noise_sigma", clean_noise_sigma);
  node.get("sigma_per_noise", sigma_per_noise);
  node.get("max_sigma", max_sigma);
  node.get("gradient_per_noise", gradient_per_noise);
  node.get("noise_row_step", noise_row_step);
  node.reject_unknown_keys();
  if (bright_percentile <= 0.0 || bright_percentile > 1.0)
    throw InputError(node.file(), node.path("bright_percentile"), "must be in (0, 1]");
  if (max_gain < 1.0) throw InputError(node.file(), node.path("max_gain"), "must be >= 1");
  if (noise_row_step < 1) throw InputError(node.file(), node.path("noise_row_step"), "must be >= 1");
}

double estimate_noise_sigma(const cv::Mat& gray, int row_step) {
  CV_Assert(gray.type() == CV_8UC1);
  if (gray.rows < 3 || gray.cols < 3) return 0.0;
  // |mask response| <= 16 * 255 = 4080: an exact histogram gives the median in linear time.
  std::vector<int> hist(4096, 0);
  long count = 0;
  row_step = std::max(1, row_step);
  for (int y = 1; y < gray.rows - 1; y += row_step) {
    const uchar* a = gray.ptr<uchar>(y - 1);
    const uchar* b = gray.ptr<uchar>(y);
    const uchar* c = gray.ptr<uchar>(y + 1);
    for (int x = 1; x < gray.cols - 1; ++x) {
      const int v = a[x - 1] - 2 * a[x] + a[x + 1] - 2 * (b[x - 1] - 2 * b[x] + b[x + 1]) + c[x - 1] -
                    2 * c[x] + c[x + 1];
      ++hist[std::abs(v)];
      ++count;
    }
  }
  const long half = count / 2;
  long acc = 0;
  int median = 0;
  for (int i = 0; i < static_cast<int>(hist.size()); ++i) {
    acc += hist[i];
    if (acc > half) {
      median = i;
      break;
    }
  }
  // For white noise of std s the response has std 6 s (sum of squared weights = 36), and the
  // median of |N(0, (6s)^2)| is 0.6745 * 6 s. Half a grey level corrects the integer median.
  const double med = median > 0 ? median + 0.5 : 0.0;
  return med / (0.6745 * 6.0);
}

namespace {
// Intensity at the given percentile (0..1) from an 8-bit histogram.
double percentile(const std::array<long, 256>& hist, long total, double q) {
  const long target = static_cast<long>(std::ceil(q * static_cast<double>(total)));
  long acc = 0;
  for (int i = 0; i < 256; ++i) {
    acc += hist[i];
    if (acc >= target) return i;
  }
  return 255;
}
}  // namespace

PrefilterResult prefilter_for_lines(const cv::Mat& gray, const PrefilterConfig& config, double base_sigma,
                                    int base_gradient_threshold) {
  CV_Assert(gray.type() == CV_8UC1);
  PrefilterResult r;
  r.image = gray;
  r.blur_sigma = base_sigma;
  r.gradient_threshold = base_gradient_threshold;
  if (!config.enabled) return r;

  std::array<long, 256> hist{};
  long total = 0;
  for (int y = 0; y < gray.rows; y += config.noise_row_step) {
    const uchar* row = gray.ptr<uchar>(y);
    for (int x = 0; x < gray.cols; ++x) ++hist[row[x]];
    total += gray.cols;
  }
  r.bright_level = percentile(hist, total, config.bright_percentile);
  const double noise_in = estimate_noise_sigma(gray, config.noise_row_step);

  if (r.bright_level < config.dark_level) {
    const double low = percentile(hist, total, 0.01);
    const double range = std::max(1.0, r.bright_level - low);
    r.gain = std::clamp(config.target_level / range, 1.0, config.max_gain);
    if (r.gain > 1.0) {
      cv::Mat stretched;
      gray.convertTo(stretched, CV_8U, r.gain, -r.gain * low);
      r.image = stretched;
    }
  }
  r.noise_sigma = noise_in * r.gain;

  const double excess = std::max(0.0, r.noise_sigma - config.clean_noise_sigma);
  r.blur_sigma = std::min(config.max_sigma, base_sigma + config.sigma_per_noise * excess);
  r.blur_sigma = std::max(r.blur_sigma, base_sigma);
  const double noise_floor = config.gradient_per_noise * r.noise_sigma / std::max(0.5, r.blur_sigma);
  r.gradient_threshold = std::max(base_gradient_threshold, static_cast<int>(std::lround(noise_floor)));
  return r;
}

}  // namespace pllvo::lines
