#include "pllvo/features/lines/line_associator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/line_descriptor.hpp>

#include "pllvo/common/error.h"

namespace pllvo::lines {

void LineAssociatorConfig::load(const ConfigNode& node) {
  node.get("point_distance_px", point_distance_px);
  node.get("min_votes", min_votes);
  node.get("vote_ratio", vote_ratio);
  node.get("use_descriptors", use_descriptors);
  node.get("max_descriptor_distance", max_descriptor_distance);
  node.get("descriptor_ratio", descriptor_ratio);
  node.get("min_matches_for_homography", min_matches_for_homography);
  node.get("homography_ransac_px", homography_ransac_px);
  node.get("max_angle_deg", max_angle_deg);
  node.get("max_distance_px", max_distance_px);
  node.reject_unknown_keys();
  if (point_distance_px <= 0.0) throw InputError(node.file(), node.path("point_distance_px"), "must be > 0");
  if (min_votes < 1) throw InputError(node.file(), node.path("min_votes"), "must be >= 1");
  if (min_matches_for_homography < 4)
    throw InputError(node.file(), node.path("min_matches_for_homography"), "must be >= 4");
}

namespace {
// Mean intensity along the segment, offset by `offset` px along its normal (bilinear).
double side_intensity(const cv::Mat& gray, const LineSegment& s, double offset) {
  double sum = 0.0;
  int n = 0;
  for (double t : {0.2, 0.35, 0.5, 0.65, 0.8}) {
    const Eigen::Vector2d p = s.at(t) + offset * s.normal();
    const int x = static_cast<int>(std::floor(p.x())), y = static_cast<int>(std::floor(p.y()));
    if (x < 0 || y < 0 || x + 1 >= gray.cols || y + 1 >= gray.rows) continue;
    const double fx = p.x() - x, fy = p.y() - y;
    sum += (1 - fy) * ((1 - fx) * gray.at<uchar>(y, x) + fx * gray.at<uchar>(y, x + 1)) +
           fy * ((1 - fx) * gray.at<uchar>(y + 1, x) + fx * gray.at<uchar>(y + 1, x + 1));
    ++n;
  }
  return n ? sum / n : 0.0;
}

// The segment oriented with its brighter side on the +normal side.
LineSegment canonical(const cv::Mat& gray, const LineSegment& s) {
  if (side_intensity(gray, s, 2.0) >= side_intensity(gray, s, -2.0)) return s;
  LineSegment r = s;
  std::swap(r.start, r.end);
  return r;
}

Eigen::Vector2d map_point(const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.hnormalized();
}
}  // namespace

cv::Mat compute_lbd_descriptors(const cv::Mat& gray, const std::vector<LineSegment>& lines) {
  if (gray.empty() || gray.type() != CV_8UC1) throw InputError("LBD descriptors: expected an 8-bit gray image");
  if (lines.empty()) return {};
  std::vector<cv::line_descriptor::KeyLine> keylines(lines.size());
  const float image_extent = static_cast<float>(std::max(gray.cols, gray.rows));
  for (size_t i = 0; i < lines.size(); ++i) {
    const LineSegment s = canonical(gray, lines[i]);
    auto& kl = keylines[i];
    kl.startPointX = kl.sPointInOctaveX = static_cast<float>(s.start.x());
    kl.startPointY = kl.sPointInOctaveY = static_cast<float>(s.start.y());
    kl.endPointX = kl.ePointInOctaveX = static_cast<float>(s.end.x());
    kl.endPointY = kl.ePointInOctaveY = static_cast<float>(s.end.y());
    const Eigen::Vector2d d = s.end - s.start;
    kl.angle = static_cast<float>(std::atan2(d.y(), d.x()));
    kl.class_id = static_cast<int>(i);  // unique: compute() keys its output rows on it
    kl.octave = 0;
    kl.pt = cv::Point2f(static_cast<float>(s.midpoint().x()), static_cast<float>(s.midpoint().y()));
    kl.lineLength = static_cast<float>(s.length());
    kl.response = kl.lineLength / image_extent;
    kl.size = static_cast<float>(std::abs(d.x() * d.y()));
    kl.numOfPixels = static_cast<int>(std::max(std::abs(d.x()), std::abs(d.y()))) + 1;
  }
  cv::Mat descriptors;
  cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor()->compute(gray, keylines, descriptors);
  if (descriptors.rows != static_cast<int>(lines.size()))
    throw InternalError("LBD descriptors: OpenCV returned a different number of rows than lines");
  return descriptors;
}

LineAssociator::LineAssociator(LineAssociatorConfig config) : config_(std::move(config)) {}

std::vector<LineMatch> LineAssociator::associate(const std::vector<LineSegment>& lines_a,
                                                 const std::vector<LineSegment>& lines_b,
                                                 const std::vector<PointMatch>& point_matches,
                                                 const cv::Mat& descriptors_a, const cv::Mat& descriptors_b) const {
  const bool have_desc = !descriptors_a.empty() && !descriptors_b.empty();
  if (have_desc && (descriptors_a.rows != static_cast<int>(lines_a.size()) ||
                    descriptors_b.rows != static_cast<int>(lines_b.size())))
    throw InputError("line association: one descriptor row per line is required");
  const int na = static_cast<int>(lines_a.size()), nb = static_cast<int>(lines_b.size());
  std::vector<LineMatch> matches;
  if (na == 0 || nb == 0) return matches;

  // Homography for the geometric check.
  bool have_h = false;
  Eigen::Matrix3d H = Eigen::Matrix3d::Identity();
  if (static_cast<int>(point_matches.size()) >= config_.min_matches_for_homography) {
    std::vector<cv::Point2f> pa, pb;
    for (const auto& m : point_matches) {
      pa.emplace_back(static_cast<float>(m.a.x()), static_cast<float>(m.a.y()));
      pb.emplace_back(static_cast<float>(m.b.x()), static_cast<float>(m.b.y()));
    }
    const cv::Mat h = cv::findHomography(pa, pb, cv::RANSAC, config_.homography_ransac_px);
    if (!h.empty()) {
      cv::cv2eigen(h, H);
      have_h = H.allFinite();
    }
  }
  const double cos_max = std::cos(config_.max_angle_deg * M_PI / 180.0);
  auto geometry_ok = [&](int ia, int ib) {
    if (!have_h) return true;
    const LineSegment& b = lines_b[ib];
    const LineSegment pred(map_point(H, lines_a[ia].start), map_point(H, lines_a[ia].end));
    if (!pred.start.allFinite() || !pred.end.allFinite() || pred.length() <= 0.0) return false;
    if (std::abs(pred.direction().dot(b.direction())) < cos_max) return false;
    if (std::abs(signed_line_distance(pred.midpoint(), b)) > config_.max_distance_px) return false;
    const double t0 = project_along(pred.start, b), t1 = project_along(pred.end, b);
    return std::max(t0, t1) > 0.0 && std::min(t0, t1) < b.length();
  };

  // 1. Point cue: votes[(a, b)].
  std::unordered_map<long, int> votes;
  std::vector<int> near_a, near_b;
  for (const auto& m : point_matches) {
    near_a.clear();
    near_b.clear();
    for (int i = 0; i < na; ++i)
      if (point_segment_distance(m.a, lines_a[i]) <= config_.point_distance_px) near_a.push_back(i);
    if (near_a.empty()) continue;
    for (int j = 0; j < nb; ++j)
      if (point_segment_distance(m.b, lines_b[j]) <= config_.point_distance_px) near_b.push_back(j);
    for (int i : near_a)
      for (int j : near_b) ++votes[static_cast<long>(i) * nb + j];
  }
  // Best and runner-up per line of A; best per line of B.
  std::vector<int> best_b(na, -1), best_votes(na, 0), second_votes(na, 0);
  std::vector<int> best_a(nb, -1), best_a_votes(nb, 0);
  for (const auto& [key, v] : votes) {
    const int i = static_cast<int>(key / nb), j = static_cast<int>(key % nb);
    if (v > best_votes[i]) {
      second_votes[i] = best_votes[i];
      best_votes[i] = v;
      best_b[i] = j;
    } else if (v > second_votes[i]) {
      second_votes[i] = v;
    }
    if (v > best_a_votes[j] || (v == best_a_votes[j] && i < best_a[j])) {
      best_a_votes[j] = v;
      best_a[j] = i;
    }
  }
  std::vector<bool> used_a(na, false), used_b(nb, false);
  for (int i = 0; i < na; ++i) {
    const int j = best_b[i];
    if (j < 0 || best_votes[i] < config_.min_votes) continue;
    if (best_votes[i] < config_.vote_ratio * second_votes[i]) continue;
    if (best_a[j] != i || used_b[j] || !geometry_ok(i, j)) continue;
    LineMatch m;
    m.a = i;
    m.b = j;
    m.cue = AssociationCue::Points;
    m.votes = best_votes[i];
    matches.push_back(m);
    used_a[i] = used_b[j] = true;
  }

  if (!have_desc) return matches;
  cv::Mat dist;  // CV_32S, na x nb
  cv::batchDistance(descriptors_a, descriptors_b, dist, CV_32S, cv::noArray(), cv::NORM_HAMMING);
  for (auto& m : matches) m.descriptor_distance = dist.at<int>(m.a, m.b);

  // 2. Descriptor cue among the lines still free, checked by the homography.
  if (!config_.use_descriptors || !have_h) return matches;
  std::vector<int> nn_of_b(nb, -1);
  for (int j = 0; j < nb; ++j) {
    if (used_b[j]) continue;
    int best = std::numeric_limits<int>::max();
    for (int i = 0; i < na; ++i)
      if (!used_a[i] && dist.at<int>(i, j) < best) best = dist.at<int>(i, j), nn_of_b[j] = i;
  }
  for (int i = 0; i < na; ++i) {
    if (used_a[i]) continue;
    int best = std::numeric_limits<int>::max(), second = best, bj = -1;
    for (int j = 0; j < nb; ++j) {
      if (used_b[j]) continue;
      const int d = dist.at<int>(i, j);
      if (d < best) {
        second = best;
        best = d;
        bj = j;
      } else if (d < second) {
        second = d;
      }
    }
    if (bj < 0 || best > config_.max_descriptor_distance || nn_of_b[bj] != i) continue;
    if (second != std::numeric_limits<int>::max() && best >= config_.descriptor_ratio * second) continue;
    if (!geometry_ok(i, bj)) continue;
    LineMatch m;
    m.a = i;
    m.b = bj;
    m.cue = AssociationCue::Descriptor;
    m.descriptor_distance = best;
    matches.push_back(m);
    used_a[i] = used_b[bj] = true;
  }
  return matches;
}

}  // namespace pllvo::lines
