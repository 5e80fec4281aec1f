#include "pllvo/synth/truth.h"

#include <algorithm>
#include <cmath>

namespace pllvo::synth {

namespace {

struct Sample {
  Eigen::Vector2d uv;
  double t;
  bool visible;
};

/// Liang-Barsky: the part [l0, l1] of x0 + l (x1 - x0) inside [0, w] x [0, h].
bool clip_to_rect(const Eigen::Vector2d& x0, const Eigen::Vector2d& x1, double w, double h, double& l0,
                  double& l1) {
  l0 = 0, l1 = 1;
  const Eigen::Vector2d d = x1 - x0;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {x0.x(), w - x0.x(), x0.y(), h - x0.y()};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0) l0 = std::max(l0, r);
    else l1 = std::min(l1, r);
  }
  return l0 <= l1;
}

class VisibilityTest {
 public:
  explicit VisibilityTest(const Rasterizer& raster) : ids_(raster.quad_ids()), w_(ids_.cols), h_(ids_.rows) {}

  /// Visible when the edge's own quad is seen within a pixel of the point: a crease or
  /// border shows on a face it bounds, a texture edge on its quad. An occluder, or the quad
  /// facing away, hides it.
  bool operator()(const SceneEdge& e, const Eigen::Vector2d& x) const {
    const int cx = static_cast<int>(std::lround(x.x())), cy = static_cast<int>(std::lround(x.y()));
    for (int dy = -1; dy <= 1; ++dy) {
      const int y = cy + dy;
      if (y < 0 || y >= h_) continue;
      const auto* id = ids_.ptr<int32_t>(y);
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = cx + dx;
        if (xx < 0 || xx >= w_ || id[xx] < 0) continue;
        if (id[xx] == e.quads[0] || id[xx] == e.quads[1]) return true;
      }
    }
    return false;
  }

 private:
  const cv::Mat& ids_;
  int w_, h_;
};

/// Splits the run samples[i..j] into straight pieces (Douglas-Peucker on the distorted points).
void split_run(const std::vector<Sample>& s, int i, int j, const SceneEdge& e, const SegmentOptions& o,
               std::vector<TruthSegment>& out) {
  if (j <= i) return;
  const Eigen::Vector2d a = s[i].uv, b = s[j].uv;
  const Eigen::Vector2d d = b - a;
  const double len = d.norm();
  double worst = 0;
  int k_worst = -1;
  if (len > 0) {
    const Eigen::Vector2d n(-d.y() / len, d.x() / len);
    for (int k = i + 1; k < j; ++k) {
      const double dev = std::abs(n.dot(s[k].uv - a));
      if (dev > worst) worst = dev, k_worst = k;
    }
  }
  if (worst > o.max_deviation_px && k_worst > 0) {
    split_run(s, i, k_worst, e, o, out);
    split_run(s, k_worst, j, e, o, out);
    return;
  }
  if (len < std::max(o.min_length_px, 1e-9)) return;
  TruthSegment seg;
  seg.id = e.id;
  seg.kind = e.kind;
  seg.a = a;
  seg.b = b;
  seg.t0 = s[i].t;
  seg.t1 = s[j].t;
  out.push_back(seg);
}

float sample_bilinear(const cv::Mat& img, const Eigen::Vector2d& p, bool& ok) {
  const double x = p.x(), y = p.y();
  if (x < 0 || y < 0 || x > img.cols - 1 || y > img.rows - 1) {
    ok = false;
    return 0;
  }
  const int x0 = std::min(static_cast<int>(x), img.cols - 2), y0 = std::min(static_cast<int>(y), img.rows - 2);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const float* r0 = img.ptr<float>(y0);
  const float* r1 = img.ptr<float>(y0 + 1);
  const float a = r0[x0] + fx * (r0[x0 + 1] - r0[x0]);
  const float b = r1[x0] + fx * (r1[x0 + 1] - r1[x0]);
  return a + fy * (b - a);
}

}  // namespace

std::vector<TruthSegment> visible_segments(const Scene& scene, const Eigen::Isometry3d& T_cam_world,
                                           const camera::CameraModel& camera, const Rasterizer& raster,
                                           const SegmentOptions& o) {
  const IdealView& view = raster.view();
  const VisibilityTest visible(raster);
  std::vector<TruthSegment> out;
  std::vector<Sample> samples;
  for (const auto& e : scene.edges) {
    const Eigen::Vector3d A = T_cam_world * e.a, B = T_cam_world * e.b;
    if (A.z() < o.near_m && B.z() < o.near_m) continue;
    double ta = 0, tb = 1;
    if (A.z() < o.near_m) ta = (o.near_m - A.z()) / (B.z() - A.z());
    if (B.z() < o.near_m) tb = (o.near_m - A.z()) / (B.z() - A.z());
    const Eigen::Vector3d P0 = A + ta * (B - A), P1 = A + tb * (B - A);
    const Eigen::Vector2d x0 = view.project(P0), x1 = view.project(P1);
    double l0, l1;
    if (!clip_to_rect(x0, x1, view.width - 1, view.height - 1, l0, l1)) continue;
    const double len = (l1 - l0) * (x1 - x0).norm();
    const int n = std::clamp(static_cast<int>(std::ceil(len)), 1, 20000);
    samples.clear();
    for (int k = 0; k <= n; ++k) {
      // Image fraction l -> 3-D fraction s (perspective-correct interpolation).
      const double l = l0 + (l1 - l0) * k / n;
      const double w0 = (1 - l) / P0.z(), w1 = l / P1.z();
      const double s = w1 / (w0 + w1);
      const Eigen::Vector3d P = P0 + s * (P1 - P0);
      Sample smp{Eigen::Vector2d::Zero(), ta + s * (tb - ta), false};
      if (camera.project(P, smp.uv) && camera.in_image(smp.uv))
        smp.visible = visible(e, view.project(P));
      samples.push_back(smp);
    }
    for (int i = 0; i <= n;) {
      if (!samples[i].visible) {
        ++i;
        continue;
      }
      int j = i;
      while (j + 1 <= n && samples[j + 1].visible) ++j;
      split_run(samples, i, j, e, o, out);
      i = j + 1;
    }
  }
  return out;
}

void measure_contrast(const cv::Mat& clean, std::vector<TruthSegment>& segments) {
  for (auto& seg : segments) {
    const Eigen::Vector2d d = seg.b - seg.a;
    const double len = d.norm();
    if (len <= 0) continue;
    const Eigen::Vector2d n(-d.y() / len, d.x() / len);
    const int m = std::clamp(static_cast<int>(len / 4), 3, 32);
    const bool line = seg.kind == EdgeKind::texture_line;
    const double off = line ? 3.0 : 2.0;
    double plus = 0, minus = 0, centre = 0;
    int count = 0;
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector2d p = seg.a + (k + 0.5) / m * d;
      bool ok = true;
      const float vp = sample_bilinear(clean, p + off * n, ok), vm = sample_bilinear(clean, p - off * n, ok);
      const float vc = sample_bilinear(clean, p, ok);
      if (!ok) continue;
      plus += vp, minus += vm, centre += vc;
      ++count;
    }
    if (count == 0) continue;
    seg.contrast = static_cast<float>(line ? std::abs(centre - 0.5 * (plus + minus)) / count
                                           : std::abs(plus - minus) / count);
  }
}

cv::Mat depth_image(const Scene& scene, const Eigen::Isometry3d& T_cam_world, const LensModel& lens,
                    const Rasterizer& raster) {
  // Each quad's plane in the camera frame: n . X = dist.
  std::vector<Eigen::Vector4d> planes(scene.quads.size());
  for (size_t i = 0; i < scene.quads.size(); ++i) {
    const Eigen::Vector3d n = T_cam_world.linear() * scene.quads[i].normal();
    planes[i] << n, n.dot(T_cam_world * scene.quads[i].origin);
  }
  const cv::Mat& xy = lens.ideal_coordinates();
  const cv::Mat& bearings = lens.bearings();
  const cv::Mat& ids = raster.quad_ids();
  cv::Mat depth(xy.size(), CV_32F, cv::Scalar(0));
  for (int v = 0; v < xy.rows; ++v) {
    const auto* p = xy.ptr<cv::Vec2f>(v);
    const auto* b = bearings.ptr<cv::Vec3f>(v);
    auto* z = depth.ptr<float>(v);
    for (int u = 0; u < xy.cols; ++u) {
      const int xi = static_cast<int>(std::lround(p[u][0])), yi = static_cast<int>(std::lround(p[u][1]));
      if (xi < 0 || yi < 0 || xi >= ids.cols || yi >= ids.rows) continue;
      const int id = ids.at<int32_t>(yi, xi);
      if (id < 0) continue;
      const Eigen::Vector4d& pl = planes[id];
      const double denom = pl[0] * b[u][0] + pl[1] * b[u][1] + pl[2] * b[u][2];
      if (std::abs(denom) < 1e-12) continue;
      const double depth_z = pl[3] / denom * b[u][2];
      if (depth_z > 0) z[u] = static_cast<float>(depth_z);
    }
  }
  return depth;
}

}  // namespace pllvo::synth
