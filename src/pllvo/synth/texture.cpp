#include "pllvo/synth/texture.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pllvo::synth::textures {

cv::Size Extent::texels() const {
  return {std::max(2, static_cast<int>(std::lround(width_m * texels_per_m))),
          std::max(2, static_cast<int>(std::lround(height_m * texels_per_m)))};
}

namespace {

int texels(double metres, double density, int min_value = 1) {
  return std::max(min_value, static_cast<int>(std::lround(metres * density)));
}

/// Smooth noise in about [-1, 1] with features of `cell` texels.
cv::Mat value_noise(cv::Size size, double cell, Random& rng, double stretch_x = 1.0) {
  const double cx = std::max(1.0, cell * stretch_x), cy = std::max(1.0, cell);
  const int gw = std::max(2, static_cast<int>(std::ceil(size.width / cx)) + 1);
  const int gh = std::max(2, static_cast<int>(std::ceil(size.height / cy)) + 1);
  cv::Mat grid(gh, gw, CV_32F);
  for (int r = 0; r < gh; ++r) {
    auto* g = grid.ptr<float>(r);
    for (int c = 0; c < gw; ++c) g[c] = static_cast<float>(rng.uniform(-1.0, 1.0));
  }
  cv::Mat out;
  cv::resize(grid, out, size, 0, 0, cell > 12 ? cv::INTER_CUBIC : cv::INTER_LINEAR);
  return out;
}

/// Fractal noise: octaves from `largest` down to `smallest` texels, amplitude x `persistence`
/// per halving, normalised so the octave amplitudes sum to 1.
cv::Mat fbm(cv::Size size, Random& rng, double largest, double smallest, double persistence = 0.6,
            double stretch_x = 1.0) {
  cv::Mat sum = cv::Mat::zeros(size, CV_32F);
  double amp = 1.0, total = 0.0;
  for (double cell = largest; cell >= smallest * 0.999; cell *= 0.5) {
    sum += value_noise(size, cell, rng, stretch_x) * amp;
    total += amp;
    amp *= persistence;
  }
  if (total > 0) sum *= 1.0 / total;
  return sum;
}

void add_edge(Texture& t, double x0, double y0, double x1, double y1, EdgeKind kind) {
  const double w = t.image.cols, h = t.image.rows;
  t.edges.push_back({Eigen::Vector2d(x0 / w, y0 / h), Eigen::Vector2d(x1 / w, y1 / h), kind});
}

/// Fills texels [x0, x1) x [y0, y1) (clipped) and lists the rectangle's four borders.
void fill_rect(Texture& t, int x0, int y0, int x1, int y1, double value, bool list_edges = true) {
  const cv::Rect r = cv::Rect(x0, y0, x1 - x0, y1 - y0) & cv::Rect(0, 0, t.image.cols, t.image.rows);
  if (r.empty()) return;
  t.image(r).setTo(value);
  if (!list_edges) return;
  add_edge(t, r.x, r.y, r.x + r.width, r.y, EdgeKind::texture_step);
  add_edge(t, r.x + r.width, r.y, r.x + r.width, r.y + r.height, EdgeKind::texture_step);
  add_edge(t, r.x + r.width, r.y + r.height, r.x, r.y + r.height, EdgeKind::texture_step);
  add_edge(t, r.x, r.y + r.height, r.x, r.y, EdgeKind::texture_step);
}

/// Lines `width` texels wide of `value` every `spacing` texels (vertical ones from column
/// first_x, horizontal ones from row first_y, none within `width` of the border), each listed
/// as a thin-line edge along its centre: tile grout, ceiling grids.
void grid_lines(Texture& t, int first_x, int first_y, int spacing, int width, double value) {
  const int w = t.image.cols, h = t.image.rows;
  for (int x0 = first_x; x0 < w - width; x0 += spacing) {
    if (x0 < width) continue;
    fill_rect(t, x0 - width / 2, 0, x0 - width / 2 + width, h, value, false);
    add_edge(t, x0 - width / 2 + 0.5 * width, 0, x0 - width / 2 + 0.5 * width, h, EdgeKind::texture_line);
  }
  for (int y0 = first_y; y0 < h - width; y0 += spacing) {
    if (y0 < width) continue;
    fill_rect(t, 0, y0 - width / 2, w, y0 - width / 2 + width, value, false);
    add_edge(t, 0, y0 - width / 2 + 0.5 * width, w, y0 - width / 2 + 0.5 * width, EdgeKind::texture_line);
  }
}

/// Blends `value` into `img` with the anti-aliased coverage of what `draw` paints (255) into
/// an 8-bit mask of the region `roi`; `draw` gets the mask and the ROI's offset.
template <typename Draw>
void blend_coverage(cv::Mat& img, cv::Rect roi, double value, Draw draw) {
  roi &= cv::Rect(0, 0, img.cols, img.rows);
  if (roi.empty()) return;
  cv::Mat mask = cv::Mat::zeros(roi.size(), CV_8U);
  draw(mask, cv::Point(roi.x, roi.y));
  cv::Mat region = img(roi);
  for (int r = 0; r < roi.height; ++r) {
    const auto* m = mask.ptr<uint8_t>(r);
    auto* p = region.ptr<float>(r);
    for (int c = 0; c < roi.width; ++c) {
      const float a = m[c] * (1.f / 255.f);
      p[c] = p[c] * (1.f - a) + static_cast<float>(value) * a;
    }
  }
}

constexpr int kShift = 8;  // sub-texel precision of polygon vertices

/// Polygon given in continuous texel coordinates (texel centres at +0.5).
void blend_polygon(cv::Mat& img, const std::vector<Eigen::Vector2d>& pts, double value) {
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (const auto& p : pts) {
    x0 = std::min(x0, p.x()), y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
  }
  const cv::Rect roi(cv::Point(static_cast<int>(x0) - 2, static_cast<int>(y0) - 2),
                     cv::Point(static_cast<int>(x1) + 3, static_cast<int>(y1) + 3));
  blend_coverage(img, roi, value, [&](cv::Mat& mask, cv::Point off) {
    std::vector<cv::Point> poly;
    for (const auto& p : pts)
      poly.emplace_back(static_cast<int>(std::lround((p.x() - 0.5 - off.x) * (1 << kShift))),
                        static_cast<int>(std::lround((p.y() - 0.5 - off.y) * (1 << kShift))));
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(255), cv::LINE_AA, kShift);
  });
}

std::string random_text(Random& rng, int min_chars, int max_chars) {
  static const char kLetters[] = "ABCDEFGHIJKLMNOPRSTUVWXYZabcdefghijklmnoprstuvwxyz0123456789";
  const int n = rng.integer(min_chars, max_chars);
  std::string s;
  int word = rng.integer(2, 8);
  for (int i = 0; i < n; ++i) {
    if (word-- == 0 && i + 1 < n) {
      s += ' ';
      word = rng.integer(2, 8);
      continue;
    }
    s += kLetters[rng.integer(0, static_cast<int>(sizeof(kLetters)) - 2)];
  }
  return s;
}

/// Text whose cap height is about `height` texels, left-aligned at (x, baseline y),
/// clipped to `max_width`.
void blend_text(cv::Mat& img, Random& rng, double x, double y, double height, double max_width,
                double value, int min_chars, int max_chars) {
  const int font = rng.chance(0.5) ? cv::FONT_HERSHEY_SIMPLEX : cv::FONT_HERSHEY_DUPLEX;
  const double scale = height / 22.0;  // Hershey simplex cap height is ~22 units at scale 1
  const int thickness = std::max(1, static_cast<int>(std::lround(height / 9.0)));
  std::string text = random_text(rng, min_chars, max_chars);
  int baseline = 0;
  while (text.size() > 1 && cv::getTextSize(text, font, scale, thickness, &baseline).width > max_width)
    text.pop_back();
  const cv::Size ts = cv::getTextSize(text, font, scale, thickness, &baseline);
  const cv::Rect roi(static_cast<int>(x) - 2, static_cast<int>(y - ts.height) - 2 - thickness,
                     ts.width + 4 + thickness, ts.height + baseline + 4 + 2 * thickness);
  blend_coverage(img, roi, value, [&](cv::Mat& mask, cv::Point off) {
    cv::putText(mask, text, cv::Point(static_cast<int>(x) - off.x, static_cast<int>(y) - off.y), font,
                scale, cv::Scalar(255), thickness, cv::LINE_AA);
  });
}

Texture make(cv::Size size, double value) {
  Texture t;
  t.image = cv::Mat(size, CV_32F, cv::Scalar(value));
  return t;
}

void clamp01(cv::Mat& img) {
  cv::max(img, 0.0, img);
  cv::min(img, 1.0, img);
}

}  // namespace

Texture plaster(const Extent& e, Random& rng, double base, double contrast) {
  const cv::Size size = e.texels();
  Texture t = make(size, base);
  t.image += fbm(size, rng, 0.8 * e.texels_per_m, 1.5, 0.65) * contrast;
  // Stains: a darker low-frequency blotch field above a threshold.
  cv::Mat stains = value_noise(size, 0.5 * e.texels_per_m, rng) - 0.45;
  cv::max(stains, 0.0, stains);
  t.image -= stains * (contrast * 0.8);
  clamp01(t.image);
  return t;
}

Texture plain(const Extent& e, Random& rng, double base) {
  const cv::Size size = e.texels();
  Texture t = make(size, base);
  t.image += fbm(size, rng, 0.5 * e.texels_per_m, 2.0, 0.7) * 0.004;
  const double gx = rng.uniform(-0.02, 0.02) / size.width, gy = rng.uniform(-0.02, 0.02) / size.height;
  for (int r = 0; r < size.height; ++r) {
    auto* p = t.image.ptr<float>(r);
    for (int c = 0; c < size.width; ++c) p[c] += static_cast<float>(gx * c + gy * r);
  }
  clamp01(t.image);
  return t;
}

Texture concrete_blocks(const Extent& e, Random& rng) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  Texture t = make(size, 0.0);
  t.image = fbm(size, rng, 0.2 * d, 1.0, 0.7) * 0.04 + 0.58;
  const int bw = texels(0.4, d, 4), bh = texels(0.2, d, 3), m = texels(0.01, d);
  const double mortar = 0.44;
  // Per-block shade, then mortar on top; rows counted from the top edge.
  for (int row = 0; row * bh < size.height; ++row) {
    const int y0 = row * bh, off = (row % 2) ? bw / 2 : 0;
    for (int x0 = -off; x0 < size.width; x0 += bw) {
      const cv::Rect block = cv::Rect(x0, y0, bw, bh) & cv::Rect(0, 0, size.width, size.height);
      if (!block.empty()) t.image(block) += rng.uniform(-0.05, 0.05);
    }
  }
  for (int row = 0; row * bh < size.height; ++row) {
    const int y0 = row * bh, off = (row % 2) ? bw / 2 : 0;
    if (y0 > 0) {
      fill_rect(t, 0, y0, size.width, y0 + m, mortar, false);
      add_edge(t, 0, y0 + 0.5 * m, size.width, y0 + 0.5 * m, EdgeKind::texture_line);
    }
    const int yb = std::min(size.height, y0 + bh);
    for (int x0 = bw - off; x0 < size.width - m; x0 += bw) {
      fill_rect(t, x0, y0 + (y0 > 0 ? m : 0), x0 + m, yb, mortar, false);
      add_edge(t, x0 + 0.5 * m, y0 + (y0 > 0 ? m : 0), x0 + 0.5 * m, yb, EdgeKind::texture_line);
    }
  }
  clamp01(t.image);
  return t;
}

Texture floor_tiles(const Extent& e, Random& rng, double tile_m) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  Texture t = make(size, 0.0);
  t.image = fbm(size, rng, 0.1 * d, 1.0, 0.6) * 0.03;
  const int tile = texels(tile_m, d, 4), g = texels(0.006, d);
  const double shade = rng.uniform(0.45, 0.6);
  for (int y0 = 0; y0 < size.height; y0 += tile)
    for (int x0 = 0; x0 < size.width; x0 += tile) {
      const cv::Rect r = cv::Rect(x0, y0, tile, tile) & cv::Rect(0, 0, size.width, size.height);
      t.image(r) += shade + rng.uniform(-0.06, 0.06);
    }
  grid_lines(t, tile, tile, tile, g, 0.22);  // grout
  clamp01(t.image);
  return t;
}

Texture ceiling_tiles(const Extent& e, Random& rng) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  Texture t = make(size, 0.0);
  t.image = fbm(size, rng, 0.05 * d, 1.0, 0.8) * 0.05 + 0.68;
  const int tile = texels(0.6, d, 4), bar = texels(0.024, d, 2);
  const double bar_value = 0.86;
  // Grid anchored at the texture's centre, as ceilings are laid out from the middle.
  const int ox = (size.width / 2) % tile, oy = (size.height / 2) % tile;
  grid_lines(t, ox, oy, tile, bar, bar_value);
  clamp01(t.image);
  return t;
}

Texture wood(const Extent& e, Random& rng, bool planks, double base) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  Texture t = make(size, base);
  t.image += fbm(size, rng, 0.03 * d, 1.0, 0.7, 12.0) * 0.08;  // grain: long along u
  if (planks) {
    const int joint = texels(0.004, d);
    int y0 = 0;
    while (y0 < size.height) {
      const int h = texels(rng.uniform(0.15, 0.2), d, 4);
      const int y1 = std::min(size.height, y0 + h);
      t.image(cv::Rect(0, y0, size.width, y1 - y0)) += rng.uniform(-0.07, 0.07);
      if (y0 > 0) {
        fill_rect(t, 0, y0, size.width, y0 + joint, base * 0.45, false);
        add_edge(t, 0, y0 + 0.5 * joint, size.width, y0 + 0.5 * joint, EdgeKind::texture_line);
      }
      for (int x0 = texels(rng.uniform(0.2, 1.5), d); x0 < size.width - joint;
           x0 += texels(rng.uniform(1.0, 2.0), d, 8)) {
        const int ya = y0 + (y0 > 0 ? joint : 0);
        fill_rect(t, x0, ya, x0 + joint, y1, base * 0.45, false);
        add_edge(t, x0 + 0.5 * joint, ya, x0 + 0.5 * joint, y1, EdgeKind::texture_line);
      }
      y0 = y1;
    }
  }
  clamp01(t.image);
  return t;
}

Texture poster(const Extent& e, Random& rng) {
  const cv::Size size = e.texels();
  const bool dark = rng.chance(0.3);
  const double bg = dark ? rng.uniform(0.12, 0.3) : rng.uniform(0.75, 0.93);
  const double ink = dark ? rng.uniform(0.8, 0.95) : rng.uniform(0.05, 0.2);
  Texture t = make(size, bg);
  const int W = size.width, H = size.height;
  const int mx = std::max(2, W / 16), my = std::max(2, H / 20);
  int y = my;
  // Title.
  const double title_h = 0.07 * H;
  blend_text(t.image, rng, mx, y + title_h, title_h, W - 2 * mx, ink, 4, 12);
  y += static_cast<int>(1.6 * title_h);
  // Picture: a block of contrasting shade with a triangle and a disc in it.
  const int pic_h = static_cast<int>(rng.uniform(0.35, 0.45) * H);
  const double pic = dark ? rng.uniform(0.45, 0.65) : rng.uniform(0.3, 0.55);
  fill_rect(t, mx, y, W - mx, y + pic_h, pic);
  const double px0 = mx, px1 = W - mx, py0 = y, py1 = y + pic_h;
  const double tri = pic > 0.45 ? rng.uniform(0.05, 0.2) : rng.uniform(0.8, 0.95);
  const std::vector<Eigen::Vector2d> triangle = {
      {px0 + rng.uniform(0.05, 0.3) * (px1 - px0), py1 - rng.uniform(0.08, 0.15) * pic_h},
      {px0 + rng.uniform(0.55, 0.7) * (px1 - px0), py1 - rng.uniform(0.08, 0.15) * pic_h},
      {px0 + rng.uniform(0.3, 0.5) * (px1 - px0), py0 + rng.uniform(0.1, 0.25) * pic_h}};
  blend_polygon(t.image, triangle, tri);
  for (int k = 0; k < 3; ++k)
    add_edge(t, triangle[k].x(), triangle[k].y(), triangle[(k + 1) % 3].x(), triangle[(k + 1) % 3].y(),
             EdgeKind::texture_step);
  const double rad = rng.uniform(0.08, 0.15) * std::min(px1 - px0, double(pic_h));
  blend_coverage(t.image, cv::Rect(0, 0, W, H), 1.0 - tri, [&](cv::Mat& mask, cv::Point) {
    const cv::Point c(static_cast<int>((px0 + 0.8 * (px1 - px0)) * (1 << kShift)),
                      static_cast<int>((py0 + 0.3 * pic_h) * (1 << kShift)));
    cv::circle(mask, c, static_cast<int>(rad * (1 << kShift)), cv::Scalar(255), cv::FILLED, cv::LINE_AA,
               kShift);
  });
  y += pic_h + my;
  // A row of colour blocks.
  const int blocks = rng.integer(2, 4), gap = W / 40;
  const int bw = (W - 2 * mx - (blocks - 1) * gap) / blocks, bh = static_cast<int>(0.08 * H);
  if (y + bh < H - my) {
    for (int b = 0; b < blocks; ++b) {
      double v = rng.uniform(0.1, 0.9);
      if (std::abs(v - bg) < 0.2) v = bg > 0.5 ? v - 0.3 : v + 0.3;
      fill_rect(t, mx + b * (bw + gap), y, mx + b * (bw + gap) + bw, y + bh, v);
    }
    y += bh + my;
  }
  // Lines of text.
  const double line_h = rng.uniform(0.025, 0.04) * H;
  while (y + 1.8 * line_h < H - my) {
    blend_text(t.image, rng, mx, y + line_h, line_h, W - 2 * mx, ink, 10, 60);
    y += static_cast<int>(1.8 * line_h);
  }
  clamp01(t.image);
  return t;
}

Texture cardboard(const Extent& e, Random& rng) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  const double base = rng.uniform(0.4, 0.55);
  Texture t = make(size, base);
  t.image += fbm(size, rng, 0.05 * d, 1.0, 0.6) * 0.04;
  const int W = size.width, H = size.height;
  if (rng.chance(0.7)) {  // tape across the top face or the front
    const int tape = std::max(2, texels(0.05, d));
    const int y0 = H / 2 - tape / 2;
    fill_rect(t, 0, y0, W, y0 + tape, base + 0.15, false);
    add_edge(t, 0, y0, W, y0, EdgeKind::texture_step);
    add_edge(t, 0, y0 + tape, W, y0 + tape, EdgeKind::texture_step);
  }
  if (rng.chance(0.6) && W > 20 && H > 20) {  // printed label
    const int lw = static_cast<int>(W * rng.uniform(0.25, 0.45)), lh = static_cast<int>(H * rng.uniform(0.12, 0.2));
    const int x0 = static_cast<int>(W * rng.uniform(0.05, 0.5)), y0 = static_cast<int>(H * rng.uniform(0.05, 0.2));
    fill_rect(t, x0, y0, x0 + lw, y0 + lh, 0.85);
    blend_text(t.image, rng, x0 + 0.08 * lw, y0 + 0.6 * lh, 0.35 * lh, 0.84 * lw, 0.1, 3, 10);
  }
  clamp01(t.image);
  return t;
}

Texture books(const Extent& e, Random& rng) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  Texture t = make(size, 0.3);
  const int W = size.width, H = size.height;
  int x0 = 0;
  double prev = -1;
  while (x0 < W) {
    const int w = std::min(W - x0, texels(rng.uniform(0.02, 0.06), d, 2));
    double v = rng.uniform(0.12, 0.85);
    if (prev >= 0 && std::abs(v - prev) < 0.12) v = prev > 0.5 ? prev - 0.2 : prev + 0.2;
    t.image(cv::Rect(x0, 0, w, H)).setTo(v);
    if (x0 > 0) add_edge(t, x0, 0, x0, H, EdgeKind::texture_step);
    if (w >= 4 && rng.chance(0.5)) {  // label band on the spine
      const int y0 = static_cast<int>(H * rng.uniform(0.6, 0.75)), lh = std::max(2, H / 10);
      fill_rect(t, x0 + 1, y0, x0 + w - 1, y0 + lh, v > 0.5 ? v - 0.35 : v + 0.35);
    }
    prev = v;
    x0 += w;
  }
  t.image += fbm(size, rng, 0.03 * d, 1.0, 0.6) * 0.02;
  clamp01(t.image);
  return t;
}

Texture paint(const Extent& e, Random& rng, double base, double noise) {
  const cv::Size size = e.texels();
  Texture t = make(size, base);
  t.image += fbm(size, rng, 0.1 * e.texels_per_m, 1.0, 0.6) * noise;
  clamp01(t.image);
  return t;
}

Texture window_view(const Extent& e, Random& rng, double radiance) {
  const cv::Size size = e.texels();
  Texture t = make(size, 0.0);
  const int W = size.width, H = size.height;
  const double horizon = rng.uniform(0.55, 0.7) * H;
  for (int r = 0; r < H; ++r) {
    const float v = r < horizon ? static_cast<float>(1.0 - 0.25 * r / horizon) : 0.45f;
    t.image.row(r).setTo(v);
  }
  for (int b = rng.integer(2, 5); b > 0; --b) {  // out-of-focus buildings
    const int bw = static_cast<int>(W * rng.uniform(0.1, 0.35));
    const int x0 = static_cast<int>(W * rng.uniform(-0.1, 0.9));
    const int top = static_cast<int>(horizon - H * rng.uniform(0.1, 0.4));
    fill_rect(t, x0, top, x0 + bw, static_cast<int>(horizon) + 1, rng.uniform(0.35, 0.6), false);
  }
  t.image += fbm(size, rng, 0.2 * e.texels_per_m, 2.0, 0.6) * 0.05;
  cv::GaussianBlur(t.image, t.image, cv::Size(), std::max(1.0, 0.02 * e.texels_per_m));
  clamp01(t.image);
  t.emissive = true;
  t.emission = {radiance, radiance};
  return t;
}

Texture light_panel(const Extent& e, Random& rng, double radiance) {
  const cv::Size size = e.texels();
  Texture t = make(size, 0.5);
  const int border = texels(0.03, e.texels_per_m, 2);
  fill_rect(t, border, border, size.width - border, size.height - border, 0.85);
  t.image += fbm(size, rng, 0.1 * e.texels_per_m, 2.0, 0.6) * 0.01;
  clamp01(t.image);
  t.emissive = true;
  t.emission = {radiance, -1.0};
  return t;
}

Texture whiteboard(const Extent& e, Random& rng) {
  const cv::Size size = e.texels();
  const double d = e.texels_per_m;
  Texture t = make(size, 0.62);
  const int border = texels(0.02, d, 2);
  fill_rect(t, border, border, size.width - border, size.height - border, 0.88);
  t.image += fbm(size, rng, 0.2 * d, 2.0, 0.6) * 0.01;
  const int strokes = rng.integer(3, 8);
  for (int s = 0; s < strokes; ++s) {
    const double x = rng.uniform(0.1, 0.7) * size.width, y = rng.uniform(0.15, 0.85) * size.height;
    blend_text(t.image, rng, x, y, rng.uniform(0.03, 0.06) * d, 0.3 * size.width, rng.uniform(0.15, 0.4), 3, 15);
  }
  clamp01(t.image);
  return t;
}

Texture door(const Extent& e, Random& rng) {
  // Grain along the door's height: draw with u and v swapped, then transpose.
  const Extent rotated{e.height_m, e.width_m, e.texels_per_m};
  Texture t = wood(rotated, rng, false, rng.uniform(0.35, 0.6));
  cv::Mat img = t.image.t();
  t.image = img;
  const int W = img.cols, H = img.rows;
  const int m = W / 6;
  const double shade = -0.07;
  for (const auto& [ya, yb] : {std::pair{H / 12, H / 2 - H / 24}, std::pair{H / 2 + H / 24, H - H / 12}}) {
    cv::Mat panel = t.image(cv::Rect(m, ya, W - 2 * m, yb - ya));
    panel += shade;
    add_edge(t, m, ya, W - m, ya, EdgeKind::texture_step);
    add_edge(t, W - m, ya, W - m, yb, EdgeKind::texture_step);
    add_edge(t, W - m, yb, m, yb, EdgeKind::texture_step);
    add_edge(t, m, yb, m, ya, EdgeKind::texture_step);
  }
  clamp01(t.image);
  return t;
}

Texture checker(const Extent& e, double square_m, double dark, double bright) {
  const cv::Size size = e.texels();
  const int sq = texels(square_m, e.texels_per_m, 1);
  Texture t = make(size, bright);
  for (int r = 0; r * sq < size.height; ++r)
    for (int c = 0; c * sq < size.width; ++c)
      if ((r + c) % 2 == 0) fill_rect(t, c * sq, r * sq, (c + 1) * sq, (r + 1) * sq, dark, false);
  for (int x = sq; x < size.width; x += sq) add_edge(t, x, 0, x, size.height, EdgeKind::texture_step);
  for (int y = sq; y < size.height; y += sq) add_edge(t, 0, y, size.width, y, EdgeKind::texture_step);
  return t;
}

}  // namespace pllvo::synth::textures
