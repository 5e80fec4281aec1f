#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/vo/point_frontend.h"
#include "pllvo/vo/point_tracker.h"

namespace pllvo::vo {
namespace {

/// Smooth random texture: blurred noise gives corners everywhere at several scales.
cv::Mat texture(cv::Size size, int seed) {
  cv::RNG rng(seed);
  cv::Mat noise(size, CV_32F);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::Mat smooth;
  cv::GaussianBlur(noise, smooth, cv::Size(0, 0), 2.0);
  cv::normalize(smooth, smooth, 0, 255, cv::NORM_MINMAX);
  cv::Mat out;
  smooth.convertTo(out, CV_8U);
  return out;
}

cv::Mat shifted(const cv::Mat& image, double dx, double dy) {
  const cv::Mat M = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, dy);
  cv::Mat out;
  cv::warpAffine(image, out, M, image.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return out;
}

int rejections(const TrackResult& r) {
  return r.rejected.lk + r.rejected.border + r.rejected.forward_backward + r.rejected.appearance;
}

std::vector<cv::Point2f> grid_points(cv::Size size, int step, int margin) {
  std::vector<cv::Point2f> pts;
  for (int y = margin; y < size.height - margin; y += step)
    for (int x = margin; x < size.width - margin; x += step) pts.emplace_back(x + 0.3f, y + 0.6f);
  return pts;
}

/// Share of `pts` that the tracker follows from `from` to `to` within `tolerance_px` of the true shift.
double share_followed(const PointTracker& tracker, const cv::Mat& from, const cv::Mat& to,
                      const std::vector<cv::Point2f>& pts, cv::Point2f shift, double tolerance_px) {
  const TrackResult r = tracker.track(tracker.build_pyramid(from), tracker.build_pyramid(to), pts);
  int good = 0;
  for (size_t i = 0; i < pts.size(); ++i) good += r.ok[i] && cv::norm(r.points[i] - pts[i] - shift) < tolerance_px;
  return static_cast<double>(good) / static_cast<double>(pts.size());
}

TEST(PointTracker, LocalContrastFollowsAnUnevenClippedExposureJump) {
  // A sudden exposure jump that is not one gain: the right half 1.8x brighter with its
  // highlights clipped (what medium_sudden and uneven flicker do). LK on the images loses
  // the right half; on their local contrast it follows most points.
  cv::Mat a;
  texture({320, 240}, 7).convertTo(a, CV_8U, 0.5, 40);
  const double dx = 2.4, dy = 1.7;
  cv::Mat b = shifted(a, dx, dy);
  cv::Mat bright;
  b(cv::Rect(160, 0, 160, 240)).convertTo(bright, CV_8U, 1.8, 0);
  bright.copyTo(b(cv::Rect(160, 0, 160, 240)));
  KltConfig config;
  const PointTracker tracker(config);
  const auto pts = grid_points(a.size(), 16, 24);
  auto followed = [&](const cv::Mat& from, const cv::Mat& to) {
    return share_followed(tracker, from, to, pts, cv::Point2f(dx, dy), 0.5);
  };
  const double plain = followed(a, b);
  const double local = followed(local_contrast(a, 15), local_contrast(b, 15));
  EXPECT_LT(plain, 0.75);
  EXPECT_GT(local, 0.85);
}

TEST(PointTracker, ContrastFallbackTakesOverOnlyWhenPlainKltLosesMostPoints) {
  // An uneven, clipped jump (the top five sixths 2.2x brighter): with the fallback
  // (klt.contrast_fallback_share 0.3) most points are followed to the right place, without it
  // the brightened part is lost; on an ordinary pair the second try does not run and the
  // result is plain KLT's.
  cv::Mat a;
  texture({320, 240}, 11).convertTo(a, CV_8U, 0.5, 40);
  const double dx = -1.8, dy = 2.2;
  const cv::Mat same_light = shifted(a, dx, dy);
  cv::Mat jump = same_light.clone();
  cv::Mat bright;
  jump(cv::Rect(0, 0, 320, 200)).convertTo(bright, CV_8U, 2.2, 0);
  bright.copyTo(jump(cv::Rect(0, 0, 320, 200)));
  const auto pts = grid_points(a.size(), 16, 24);
  auto correct = [&](const TrackResult& r) {
    int good = 0;
    for (size_t i = 0; i < pts.size(); ++i)
      good += r.ok[i] && std::hypot(r.points[i].x - pts[i].x - dx, r.points[i].y - pts[i].y - dy) < 0.5;
    return static_cast<double>(good) / static_cast<double>(pts.size());
  };
  KltConfig off;
  off.contrast_fallback_share = 0;
  const PointTracker with((KltConfig())), without(off);
  const ImagePyramid pa = with.build_pyramid(a), pj = with.build_pyramid(jump), ps = with.build_pyramid(same_light);
  const TrackResult plain = without.track_with_contrast_fallback(pa, pj, pts);
  const TrackResult retried = with.track_with_contrast_fallback(pa, pj, pts);
  EXPECT_FALSE(plain.contrast_retried);
  EXPECT_LT(correct(plain), 0.3);
  EXPECT_TRUE(retried.contrast_retried);
  EXPECT_GT(correct(retried), 0.85);
  const TrackResult ordinary = with.track_with_contrast_fallback(pa, ps, pts);
  EXPECT_FALSE(ordinary.contrast_retried);
  EXPECT_EQ(ordinary.ok, with.track(pa, ps, pts).ok);
  EXPECT_GT(correct(ordinary), 0.9);
}

TEST(PointTracker, NoiseEstimateFollowsTheAddedNoiseNotTheTexture) {
  // Smooth texture at mid grey plus Gaussian noise of known sigma: the estimate tracks the
  // noise within 15 % and stays low on the clean texture (the denoising switch's input).
  cv::Mat clean;
  texture({376, 240}, 3).convertTo(clean, CV_32F, 0.5, 64);
  cv::Mat clean8;
  clean.convertTo(clean8, CV_8U);
  EXPECT_LT(estimate_noise_sigma(clean8), 1.5);
  cv::RNG rng(5);
  for (const double sigma : {3.0, 8.0, 15.0}) {
    cv::Mat noise(clean.size(), CV_32F), noisy;
    rng.fill(noise, cv::RNG::NORMAL, 0, sigma);
    cv::Mat(clean + noise).convertTo(noisy, CV_8U);
    EXPECT_NEAR(estimate_noise_sigma(noisy), sigma, 0.15 * sigma) << "sigma " << sigma;
  }
}

TEST(PointTracker, SmoothingKeepsTracksThroughLowLightNoise) {
  // Low contrast under noise of sigma 14 (a low-light frame after the brightness gain, each frame
  // its own noise): the NCC check rejects most correct tracks on the raw frames; after the
  // 1.5 px smoothing the VO applies to such frames, most survive.
  cv::Mat base;
  texture({320, 240}, 11).convertTo(base, CV_32F, 0.35, 80);
  const double dx = 3.2, dy = -1.4;
  cv::Mat moved;
  shifted(base, dx, dy).convertTo(moved, CV_32F);
  cv::RNG rng(9);
  auto noisy = [&](const cv::Mat& f) {
    cv::Mat noise(f.size(), CV_32F), out;
    rng.fill(noise, cv::RNG::NORMAL, 0, 14.0);
    cv::Mat(f + noise).convertTo(out, CV_8U);
    return out;
  };
  const cv::Mat a = noisy(base), b = noisy(moved);
  const KltConfig config;
  const PointTracker tracker(config);
  const auto pts = grid_points(a.size(), 16, 24);
  auto followed = [&](const cv::Mat& from, const cv::Mat& to) {
    return share_followed(tracker, from, to, pts, cv::Point2f(dx, dy), 0.75);
  };
  cv::Mat sa, sb;
  cv::GaussianBlur(a, sa, cv::Size(), config.denoise_sigma_px);
  cv::GaussianBlur(b, sb, cv::Size(), config.denoise_sigma_px);
  const double raw = followed(a, b), smoothed = followed(sa, sb);
  EXPECT_GT(estimate_noise_sigma(a), config.denoise_min_noise);
  EXPECT_LT(raw, 0.5);
  EXPECT_GT(smoothed, raw + 0.25);
  RecordProperty("raw_share", std::to_string(raw));
  RecordProperty("smoothed_share", std::to_string(smoothed));
}

TEST(PointTracker, FollowsASubpixelShift) {
  const cv::Mat a = texture({320, 240}, 1);
  const double dx = 3.3, dy = -2.1;
  const cv::Mat b = shifted(a, dx, dy);
  PointTracker tracker{KltConfig{}};
  const auto pa = tracker.build_pyramid(a), pb = tracker.build_pyramid(b);
  const auto pts = grid_points(a.size(), 20, 30);
  const TrackResult r = tracker.track(pa, pb, pts);
  ASSERT_EQ(r.points.size(), pts.size());
  EXPECT_GE(r.tracked(), static_cast<int>(0.95 * pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) {
    if (!r.ok[i]) continue;
    EXPECT_NEAR(r.points[i].x, pts[i].x + dx, 0.1);
    EXPECT_NEAR(r.points[i].y, pts[i].y + dy, 0.1);
    EXPECT_LE(r.fb_error[i], KltConfig{}.fb_threshold_px);
  }
}

// A track followed over many noisy frames drifts; one alignment against the first image does not.
TEST(PointTracker, AlignmentToTheReferenceRemovesAccumulatedDrift) {
  const cv::Mat a = texture({320, 240}, 5);
  const double dx = 7.4, dy = -3.2;
  cv::Mat b = shifted(a, dx, dy), noise(b.size(), CV_16S);
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::NORMAL, 0, 6);  // low-light grain
  cv::Mat b16;
  b.convertTo(b16, CV_16S);
  cv::Mat(b16 + noise).convertTo(b, CV_8U);
  PointTracker tracker{KltConfig{}};
  const auto pa = tracker.build_pyramid(a), pb = tracker.build_pyramid(b);
  const auto reference = grid_points(a.size(), 20, 30);
  std::vector<cv::Point2f> positions;  // where drifted tracks ended: 0.7-1.4 px off the truth
  for (size_t i = 0; i < reference.size(); ++i) {
    const double angle = 0.9 * static_cast<double>(i), off = 0.7 + 0.1 * static_cast<double>(i % 8);
    positions.emplace_back(reference[i].x + dx + off * std::cos(angle), reference[i].y + dy + off * std::sin(angle));
  }
  // The reference as the VO keeps it (no derivatives); LK computes them itself.
  const auto ok = tracker.align(tracker.reference_levels(a, 1), pb, reference, positions, 1, 3.0);
  ASSERT_EQ(ok.size(), reference.size());
  int aligned = 0;
  double sum_sq = 0;
  for (size_t i = 0; i < reference.size(); ++i) {
    if (!ok[i]) continue;
    ++aligned;
    const double ex = positions[i].x - reference[i].x - dx, ey = positions[i].y - reference[i].y - dy;
    sum_sq += ex * ex + ey * ey;
  }
  EXPECT_GE(aligned, static_cast<int>(0.95 * reference.size()));
  const double rms = std::sqrt(sum_sq / std::max(aligned, 1));
  EXPECT_LT(rms, 0.25);  // from 0.7-1.4 px
  RecordProperty("aligned_rms_px", std::to_string(rms));
}

// A position farther from its reference's patch than the shift allowed is not moved: it is
// another point (a wrong link), or the track lost its point.
TEST(PointTracker, AlignmentRefusesLargeCorrections) {
  const cv::Mat a = texture({320, 240}, 6);
  const cv::Mat b = shifted(a, 2.0, 1.0);
  PointTracker tracker{KltConfig{}};
  const auto pa = tracker.build_pyramid(a), pb = tracker.build_pyramid(b);
  const auto reference = grid_points(a.size(), 20, 30);
  std::vector<cv::Point2f> positions;
  for (const auto& p : reference) positions.emplace_back(p.x + 2.0f + 5.0f, p.y + 1.0f);  // 5 px off
  const std::vector<cv::Point2f> before = positions;
  const auto ok = tracker.align(pa.levels(), pb, reference, positions, 1, 2.0);
  for (size_t i = 0; i < reference.size(); ++i) {
    EXPECT_FALSE(ok[i]) << i;
    EXPECT_EQ(positions[i], before[i]) << i;
  }
  std::vector<cv::Point2f> wrong_size(reference.size() - 1);
  EXPECT_THROW(tracker.align(pa.levels(), pb, reference, wrong_size, 1, 2.0), InternalError);
}

TEST(PointTracker, ForwardBackwardCheckRejectsOccludedPoints) {
  const cv::Mat a = texture({320, 240}, 2);
  cv::Mat b = shifted(a, 2.0, 1.0);
  // An unrelated texture covers the middle of the second image (an occluder).
  const cv::Rect occluder(100, 70, 120, 100);
  texture({320, 240}, 99)(occluder).copyTo(b(occluder));
  PointTracker tracker{KltConfig{}};
  const auto pts = grid_points(a.size(), 10, 20);
  const TrackResult r = tracker.track(tracker.build_pyramid(a), tracker.build_pyramid(b), pts);
  int inside = 0, inside_rejected = 0, outside = 0, outside_kept = 0;
  const cv::Rect core(occluder.x + 15, occluder.y + 15, occluder.width - 30, occluder.height - 30);
  for (size_t i = 0; i < pts.size(); ++i) {
    const cv::Point2f target = pts[i] + cv::Point2f(2.0f, 1.0f);
    if (core.contains(target)) {
      ++inside;
      inside_rejected += !r.ok[i];
      if (r.ok[i]) EXPECT_LT(cv::norm(r.points[i] - target), 1.5) << "accepted a wrong track at " << pts[i];
    } else if (!(occluder + cv::Size(20, 20) - cv::Point(10, 10)).contains(target)) {
      ++outside;
      outside_kept += r.ok[i];
      if (r.ok[i]) EXPECT_LT(cv::norm(r.points[i] - target), 0.2);
    }
  }
  ASSERT_GT(inside, 20);
  EXPECT_GE(inside_rejected, 0.9 * inside);
  EXPECT_GE(outside_kept, 0.95 * outside);
  // Every dropped track has exactly one reason; an occluder fails the consistency checks
  // (forward-backward or appearance), not the image border.
  EXPECT_EQ(rejections(r), static_cast<int>(pts.size()) - r.tracked());
  EXPECT_EQ(r.rejected.border, 0);
  EXPECT_GE(r.rejected.forward_backward + r.rejected.appearance + r.rejected.lk, inside_rejected);
  EXPECT_GT(r.rejected.forward_backward + r.rejected.appearance, 0);
}

TEST(PointTracker, DropsPointsLeavingTheImage) {
  const cv::Mat a = texture({320, 240}, 3);
  const cv::Mat b = shifted(a, 25.0, 0.0);
  KltConfig config;
  PointTracker tracker{config};
  const std::vector<cv::Point2f> pts = {{300.f, 120.f}, {100.f, 120.f}};
  const TrackResult r = tracker.track(tracker.build_pyramid(a), tracker.build_pyramid(b), pts);
  EXPECT_FALSE(r.ok[0]);  // would land at x = 325, outside
  EXPECT_TRUE(r.ok[1]);
  EXPECT_EQ(rejections(r), 1);
  EXPECT_EQ(r.rejected.lk + r.rejected.border, 1);  // LK may already give up at the edge
}

TEST(PointTracker, PredictionReachesMotionBeyondThePyramid) {
  const cv::Mat a = texture({320, 240}, 4);
  const cv::Mat b = shifted(a, 45.0, 30.0);
  KltConfig config;
  config.levels = 1;  // search range ~ 2 * window: far less than 54 px
  PointTracker tracker{config};
  const auto pa = tracker.build_pyramid(a), pb = tracker.build_pyramid(b);
  std::vector<cv::Point2f> pts = {{100.f, 80.f}, {150.f, 100.f}, {200.f, 120.f}, {120.f, 150.f}};
  const TrackResult blind = tracker.track(pa, pb, pts);
  std::vector<cv::Point2f> predicted;
  for (const auto& p : pts) predicted.push_back(p + cv::Point2f(43.5f, 31.0f));
  const TrackResult guided = tracker.track(pa, pb, pts, &predicted);
  EXPECT_EQ(guided.tracked(), 4);
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(guided.points[i].x, pts[i].x + 45.0, 0.1);
    EXPECT_NEAR(guided.points[i].y, pts[i].y + 30.0, 0.1);
  }
  for (size_t i = 0; i < pts.size(); ++i)
    if (blind.ok[i]) EXPECT_LT(cv::norm(blind.points[i] - (pts[i] + cv::Point2f(45, 30))), 1.0);
}

TEST(PointTracker, BlankImagesTrackNothingAndDoNotThrow) {
  const cv::Mat black(240, 320, CV_8UC1, cv::Scalar(0)), grey(240, 320, CV_8UC1, cv::Scalar(128));
  PointTracker tracker{KltConfig{}};
  const auto pts = grid_points(black.size(), 40, 20);
  const TrackResult r = tracker.track(tracker.build_pyramid(black), tracker.build_pyramid(grey), pts);
  EXPECT_EQ(r.tracked(), 0);
  EXPECT_EQ(r.rejected.lk, static_cast<int>(pts.size()));  // no gradient: LK itself refuses
}

TEST(PointTracker, CornerRatioTellsCornersFromPlainEdges) {
  // Bright quadrant x > 100, y > 80 on a dark ground, smoothed like a camera image, plus noise.
  cv::Mat img(160, 200, CV_8U, cv::Scalar(60));
  img(cv::Rect(100, 80, 100, 80)).setTo(160);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 1.0);
  cv::Mat noise(img.size(), CV_16S);
  cv::randn(noise, 0, 2);
  cv::Mat noisy;
  img.convertTo(noisy, CV_16S);
  noisy += noise;
  noisy.convertTo(img, CV_8U);
  const double corner = corner_ratio(img, {100, 80}, 21);
  const double vertical_edge = corner_ratio(img, {100, 130}, 21);
  const double horizontal_edge = corner_ratio(img, {160, 80}, 21);
  EXPECT_GT(corner, 0.2);
  EXPECT_LT(vertical_edge, 0.05);
  EXPECT_LT(horizontal_edge, 0.05);
  // On a flat patch only the noise is left: isotropic, so the ratio is large but says nothing
  // about edges; a flat window without noise has no gradient at all.
  EXPECT_EQ(corner_ratio(cv::Mat(50, 50, CV_8U, cv::Scalar(90)), {25, 25}, 21), 0.0);
}

}  // namespace
}  // namespace pllvo::vo
