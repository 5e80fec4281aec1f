#include "pllvo/features/lines/line_detector.h"

#include <algorithm>
#include <cmath>

#include <opencv2/ximgproc/edge_drawing.hpp>

#include "pllvo/common/error.h"
#include "pllvo/features/lines/collinear_merge.h"
#include "pllvo/features/lines/line_fit.h"

namespace pllvo::lines {

namespace {
int gradient_operator_code(const std::string& name) {
  using ED = cv::ximgproc::EdgeDrawing;
  if (name == "prewitt") return ED::PREWITT;
  if (name == "sobel") return ED::SOBEL;
  if (name == "scharr") return ED::SCHARR;
  if (name == "lsd") return ED::LSD;
  return -1;
}

cv::ximgproc::EdgeDrawing::Params to_params(const EdgeDrawingConfig& c, double sigma, int gradient_threshold) {
  cv::ximgproc::EdgeDrawing::Params p;
  p.EdgeDetectionOperator = gradient_operator_code(c.gradient_operator);
  p.GradientThresholdValue = gradient_threshold;
  p.AnchorThresholdValue = c.anchor_threshold;
  p.ScanInterval = c.scan_interval;
  p.MinPathLength = c.min_path_length;
  p.Sigma = static_cast<float>(sigma);
  p.SumFlag = c.sum_flag;
  p.NFAValidation = c.nfa_validation;
  p.MinLineLength = c.min_line_length;
  p.LineFitErrorThreshold = c.line_fit_error_threshold;
  p.MaxDistanceBetweenTwoLines = c.max_distance_between_two_lines;
  p.MaxErrorThreshold = c.max_error_threshold;
  return p;
}

void check_gray(const cv::Mat& gray) {
  if (gray.empty()) throw InputError("line detection: empty image");
  if (gray.type() != CV_8UC1) throw InputError("line detection: expected an 8-bit single-channel image");
}

// Offset (in [-0.5, 0.5] px) of the peak of a parabola through three equally spaced samples.
double parabola_peak(double gm, double g0, double gp) {
  const double den = gm - 2.0 * g0 + gp;
  if (!(g0 >= gm && g0 >= gp) || den >= 0.0) return 0.0;
  return std::clamp(0.5 * (gm - gp) / den, -0.5, 0.5);
}

// Whether the image gradient at (x, y) (3x3 Sobel) is within the angle whose cosine is
// `min_cos` of the unit normal n (either sign).
bool gradient_along(const cv::Mat& image, int x, int y, const Eigen::Vector2d& n, double min_cos) {
  const uchar* r0 = image.ptr<uchar>(y - 1) + x;
  const uchar* r1 = image.ptr<uchar>(y) + x;
  const uchar* r2 = image.ptr<uchar>(y + 1) + x;
  const double gx = (r0[1] + 2.0 * r1[1] + r2[1]) - (r0[-1] + 2.0 * r1[-1] + r2[-1]);
  const double gy = (r2[-1] + 2.0 * r2[0] + r2[1]) - (r0[-1] + 2.0 * r0[0] + r0[1]);
  const double dot = std::abs(gx * n.x() + gy * n.y());
  return dot >= min_cos * std::sqrt(gx * gx + gy * gy);
}

// The edge pixels that support `seg`: pixels of EdgeDrawing's edge map inside a band of
// half-width `band` around the segment (extended by `band` past its ends), found by walking the
// segment along its major axis, so the cost is proportional to the segment's length. Each pixel
// is moved to the gradient peak across the edge, along the image axis closer to the segment's
// normal (as in Devernay's sub-pixel Canny). With max_angle_rad > 0, only pixels whose image
// gradient is within that angle of the segment's normal count.
std::vector<Eigen::Vector2d> subpixel_support(const LineSegment& seg, const cv::Mat& edges, const cv::Mat& grad,
                                              const cv::Mat& image, double band, double max_angle_rad,
                                              double* mean_grad) {
  std::vector<Eigen::Vector2d> pts;
  const Eigen::Vector2d d = seg.end - seg.start;
  const Eigen::Vector2d normal = seg.normal();
  const double min_cos = max_angle_rad > 0 ? std::cos(max_angle_rad) : -1.0;
  const bool along_x = std::abs(d.x()) >= std::abs(d.y());
  // Parametrise the segment by its major coordinate m: minor = a + b m.
  const double m0 = along_x ? seg.start.x() : seg.start.y(), m1 = along_x ? seg.end.x() : seg.end.y();
  const double n0 = along_x ? seg.start.y() : seg.start.x();
  const double slope = along_x ? d.y() / d.x() : d.x() / d.y();
  const double cos_a = 1.0 / std::sqrt(1.0 + slope * slope);  // perpendicular distance per unit of minor offset
  const double ext = band * cos_a;
  const int lo = static_cast<int>(std::ceil(std::min(m0, m1) - ext)), hi = static_cast<int>(std::floor(std::max(m0, m1) + ext));
  const int mmax = along_x ? edges.cols - 2 : edges.rows - 2, nmax = along_x ? edges.rows - 2 : edges.cols - 2;
  const double half = band / cos_a;  // minor-axis half-width of the band
  pts.reserve(static_cast<size_t>(std::max(0, hi - lo + 1)));
  double gsum = 0.0;
  for (int m = std::max(lo, 1); m <= std::min(hi, mmax); ++m) {
    const double n_line = n0 + slope * (m - m0);
    const int nlo = std::max(1, static_cast<int>(std::ceil(n_line - half)));
    const int nhi = std::min(nmax, static_cast<int>(std::floor(n_line + half)));
    for (int n = nlo; n <= nhi; ++n) {
      const int x = along_x ? m : n, y = along_x ? n : m;
      if (!edges.ptr<uchar>(y)[x]) continue;
      if (min_cos > -1.0 && !gradient_along(image, x, y, normal, min_cos)) continue;
      const ushort* row = grad.ptr<ushort>(y);
      const double g0 = row[x];
      gsum += g0;
      // The segment's normal is closer to the minor axis: refine along it.
      if (along_x) {
        const double gm = grad.ptr<ushort>(y - 1)[x], gp = grad.ptr<ushort>(y + 1)[x];
        pts.emplace_back(x, y + parabola_peak(gm, g0, gp));
      } else {
        pts.emplace_back(x + parabola_peak(row[x - 1], g0, row[x + 1]), y);
      }
    }
  }
  *mean_grad = pts.empty() ? 0.0 : gsum / static_cast<double>(pts.size());
  return pts;
}

// Refits seg on its support by total least squares, twice dropping the support points that the
// current fit leaves farther than a shrinking distance (band, then band / 2), so pixels of a
// crossing or adjacent edge inside the band do not tilt the line. The extent is then taken over
// every support point within `band` of the final line: the last pixels before a corner, which
// blur pulls off the line, still count for the endpoints.
SupportedSegment refine(const LineSegment& seg, const std::vector<Eigen::Vector2d>& support, double band) {
  SupportedSegment out{seg, {}};
  if (support.size() < 2) return out;
  std::vector<Eigen::Vector2d> pts = support;
  LineFit fit = fit_line_tls(pts);
  for (double reject : {band, 0.5 * band}) {
    const Eigen::Vector2d n(-fit.direction.y(), fit.direction.x());
    const auto before = pts.size();
    pts.erase(std::remove_if(pts.begin(), pts.end(),
                             [&](const Eigen::Vector2d& p) { return std::abs(n.dot(p - fit.centroid)) > reject; }),
              pts.end());
    if (pts.size() < 2) return out;
    if (pts.size() != before) fit = fit_line_tls(pts);
  }
  const Eigen::Vector2d n(-fit.direction.y(), fit.direction.x());
  pts.clear();
  for (const auto& p : support)
    if (std::abs(n.dot(p - fit.centroid)) <= band) pts.push_back(p);
  out.segment = segment_from_fit(fit, pts, seg);
  out.support = std::move(pts);
  return out;
}
}  // namespace

void EdgeDrawingConfig::load(const ConfigNode& node) {
  node.get("gradient_operator", gradient_operator);
  node.get("gradient_threshold", gradient_threshold);
  node.get("anchor_threshold", anchor_threshold);
  node.get("scan_interval", scan_interval);
  node.get("min_path_length", min_path_length);
  node.get("sigma", sigma);
  node.get("sum_flag", sum_flag);
  node.get("nfa_validation", nfa_validation);
  node.get("min_line_length", min_line_length);
  node.get("line_fit_error_threshold", line_fit_error_threshold);
  node.get("max_distance_between_two_lines", max_distance_between_two_lines);
  node.get("max_error_threshold", max_error_threshold);
  node.reject_unknown_keys();
  if (gradient_operator_code(gradient_operator) < 0)
    throw InputError(node.file(), node.path("gradient_operator"), "expected prewitt, sobel, scharr or lsd");
  if (gradient_threshold < 1) throw InputError(node.file(), node.path("gradient_threshold"), "must be >= 1");
  if (sigma <= 0.0) throw InputError(node.file(), node.path("sigma"), "must be > 0");
}

EdgeDrawingConfig EdgeDrawingConfig::opencv_defaults() {
  EdgeDrawingConfig c;
  c.nfa_validation = true;
  return c;
}

void LineDetectorConfig::load(const ConfigNode& node) {
  prefilter.load(node.child("prefilter"));
  edge_drawing.load(node.child("edge_drawing"));
  node.get("subpixel_refinement", subpixel_refinement);
  node.get("support_distance_px", support_distance_px);
  node.get("support_max_angle_deg", support_max_angle_deg);
  node.get("merge_collinear", merge_collinear);
  node.get("merge_max_angle_deg", merge_max_angle_deg);
  node.get("merge_max_distance_px", merge_max_distance_px);
  node.get("merge_max_gap_px", merge_max_gap_px);
  node.get("min_length_px", min_length_px);
  node.get("min_gradient_ratio", min_gradient_ratio);
  node.get("max_lines", max_lines);
  node.reject_unknown_keys();
  if (support_distance_px <= 0.0) throw InputError(node.file(), node.path("support_distance_px"), "must be > 0");
  if (min_length_px < 0.0) throw InputError(node.file(), node.path("min_length_px"), "must be >= 0");
  if (max_lines < 0) throw InputError(node.file(), node.path("max_lines"), "must be >= 0");
}

LineDetector::LineDetector(LineDetectorConfig config)
    : config_(std::move(config)), ed_(cv::ximgproc::createEdgeDrawing()) {}
LineDetector::~LineDetector() = default;
LineDetector::LineDetector(LineDetector&&) noexcept = default;
LineDetector& LineDetector::operator=(LineDetector&&) noexcept = default;

std::vector<LineSegment> LineDetector::detect(const cv::Mat& gray) {
  check_gray(gray);
  stats_ = {};
  const auto& edc = config_.edge_drawing;
  PrefilterResult pre = prefilter_for_lines(gray, config_.prefilter, edc.sigma, edc.gradient_threshold);
  ed_->setParams(to_params(edc, pre.blur_sigma, pre.gradient_threshold));
  ed_->detectEdges(pre.image);
  std::vector<cv::Vec4f> raw;
  ed_->detectLines(raw);
  stats_.edlines_count = static_cast<int>(raw.size());

  // Merge first, on EDLines' own endpoints (cheap), so that only the merged segments long enough
  // to be kept are refined; the refinement then collects the edge pixels along the whole merged
  // segment, whichever piece they came from.
  std::vector<SupportedSegment> pieces;
  pieces.reserve(raw.size());
  for (const auto& r : raw) pieces.push_back({LineSegment({r[0], r[1]}, {r[2], r[3]}), {}});
  if (config_.merge_collinear) {
    const CollinearMergeConfig mc{config_.merge_max_angle_deg * M_PI / 180.0, config_.merge_max_distance_px,
                                  config_.merge_max_gap_px};
    stats_.merged_count = merge_collinear_segments(pieces, mc);
  }

  std::vector<LineSegment> lines;
  lines.reserve(pieces.size());
  if (config_.subpixel_refinement) {
    cv::Mat edges, grad;
    ed_->getEdgeImage(edges);
    ed_->getGradientImage(grad);
    const double min_response = config_.min_gradient_ratio * pre.gradient_threshold;
    // The refit moves endpoints by at most about the band width.
    const double min_before = config_.min_length_px - 2.0 * config_.support_distance_px;
    for (const auto& p : pieces) {
      if (p.segment.length() < min_before) continue;
      double mean_grad = 0.0;
      auto support = subpixel_support(p.segment, edges, grad, pre.image, config_.support_distance_px,
                                      config_.support_max_angle_deg * M_PI / 180.0, &mean_grad);
      SupportedSegment refined = refine(p.segment, support, config_.support_distance_px);
      if (refined.segment.length() < config_.min_length_px || mean_grad < min_response) continue;
      refined.segment.response = mean_grad / pre.gain;
      lines.push_back(refined.segment);
    }
  } else {
    for (const auto& p : pieces)
      if (p.segment.length() >= config_.min_length_px) lines.push_back(p.segment);
  }
  std::stable_sort(lines.begin(), lines.end(),
                   [](const LineSegment& a, const LineSegment& b) { return a.length() > b.length(); });
  if (config_.max_lines > 0 && static_cast<int>(lines.size()) > config_.max_lines) lines.resize(config_.max_lines);
  for (size_t i = 0; i < lines.size(); ++i) lines[i].id = static_cast<int>(i);

  pre.image = cv::Mat();
  stats_.prefilter = pre;
  stats_.output_count = static_cast<int>(lines.size());
  return lines;
}

std::vector<LineSegment> detect_edlines_plain(const cv::Mat& gray, const EdgeDrawingConfig& config) {
  check_gray(gray);
  auto ed = cv::ximgproc::createEdgeDrawing();
  ed->setParams(to_params(config, config.sigma, config.gradient_threshold));
  ed->detectEdges(gray);
  std::vector<cv::Vec4f> raw;
  ed->detectLines(raw);
  std::vector<LineSegment> lines;
  lines.reserve(raw.size());
  for (const auto& r : raw) lines.emplace_back(Eigen::Vector2d(r[0], r[1]), Eigen::Vector2d(r[2], r[3]),
                                               static_cast<int>(lines.size()));
  return lines;
}

}  // namespace pllvo::lines
