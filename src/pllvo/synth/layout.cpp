#include "pllvo/synth/layout.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "pllvo/synth/random.h"
#include "pllvo/synth/texture.h"

namespace pllvo::synth {

namespace {

using Vec3 = Eigen::Vector3d;
using textures::Extent;
using TextureMaker = std::function<Texture(const Extent&)>;
const Vec3 kUp = Vec3::UnitZ();

constexpr double kLowBandTop = 0.86;   // boxes below, posters and windows above
constexpr double kHighBandBottom = 0.88;
constexpr double kGap = 0.12;           // between neighbouring wall items
constexpr double kPanelPower = 1.0;     // per ceiling panel (normalised later)
constexpr double kWindowPower = 0.25;   // per m^2 of window at window_light 1

/// Local frame of a wall or object: point = origin + a*right + z*up + d*normal.
struct Frame {
  Vec3 origin, right, normal;
  Vec3 at(double a, double z, double d) const { return origin + a * right + z * kUp + d * normal; }
};

enum Face : unsigned { kFront = 1, kBack = 2, kLeft = 4, kRight = 8, kTop = 16, kBottom = 32 };

/// Axis-aligned box in frame f: a in [a0, a1], z in [z0, z1], d in [d0, d1].
void add_box(SceneBuilder& b, const Frame& f, double a0, double a1, double z0, double z1, double d0, double d1,
             unsigned faces, const TextureMaker& front, const TextureMaker& other, double density) {
  const double w = a1 - a0, h = z1 - z0, dep = d1 - d0;
  const Vec3 c = f.at(0.5 * (a0 + a1), 0.5 * (z0 + z1), 0.5 * (d0 + d1));
  auto ext = [&](double x, double y) { return Extent{x, y, density}; };
  if (faces & kFront) b.add_facing(c + 0.5 * dep * f.normal, f.normal, kUp, w, h, front(ext(w, h)));
  if (faces & kBack) b.add_facing(c - 0.5 * dep * f.normal, -f.normal, kUp, w, h, other(ext(w, h)));
  if (faces & kLeft) b.add_facing(c - 0.5 * w * f.right, -f.right, kUp, dep, h, other(ext(dep, h)));
  if (faces & kRight) b.add_facing(c + 0.5 * w * f.right, f.right, kUp, dep, h, other(ext(dep, h)));
  if (faces & kTop) b.add_facing(c + 0.5 * h * kUp, kUp, -f.normal, w, dep, other(ext(w, dep)));
  if (faces & kBottom) b.add_facing(c - 0.5 * h * kUp, -kUp, f.normal, w, dep, other(ext(w, dep)));
}

struct Interval {
  double a0, a1;
};

struct Wall {
  Frame frame;
  double length = 0;
  double protrusion = 0;  ///< deepest item on this wall
  std::vector<Interval> low, high;
};

bool is_free(const std::vector<Interval>& used, double a0, double a1) {
  for (const auto& iv : used)
    if (a0 < iv.a1 + kGap && a1 > iv.a0 - kGap) return false;
  return true;
}

/// Finds a free stretch [a0, a0 + width) on the wall in the given bands and reserves it.
bool reserve(Wall& wall, Random& rng, double width, bool low, bool high, double& a0) {
  if (width > wall.length - 0.3) return false;
  for (int attempt = 0; attempt < 40; ++attempt) {
    a0 = rng.uniform(0.15, wall.length - 0.15 - width);
    if ((low && !is_free(wall.low, a0, a0 + width)) || (high && !is_free(wall.high, a0, a0 + width))) continue;
    if (low) wall.low.push_back({a0, a0 + width});
    if (high) wall.high.push_back({a0, a0 + width});
    return true;
  }
  return false;
}

class RoomBuilder {
 public:
  RoomBuilder(const SceneSpec& spec, uint64_t seed)
      : spec_(spec), rng_(derive_seed(seed, 0x7363656e65ULL)), low_(spec.texture == "low") {}

  Scene build() {
    const double L = spec_.length_m, W = spec_.width_m, H = spec_.height_m;
    const bool corridor = spec_.layout == "corridor";
    add_shell(L, W, H);
    add_ceiling_lights(L, W, H);
    // Windows go on the outer walls: the two long walls of a room, the end walls of a corridor.
    std::vector<int> window_walls = corridor ? std::vector<int>{0, 1} : std::vector<int>{2, 3};
    for (int i = 0; i < spec_.doors; ++i) place_on_random_wall(&RoomBuilder::add_door, corridor ? std::vector<int>{2, 3} : all_walls());
    for (int i = 0; i < spec_.windows; ++i) place_on_random_wall(&RoomBuilder::add_window, window_walls);
    for (int i = 0; i < spec_.shelves; ++i) place_on_random_wall(&RoomBuilder::add_shelf, all_walls());
    for (int i = 0; i < spec_.wall_boxes; ++i) place_on_random_wall(&RoomBuilder::add_box_stack, all_walls());
    for (int i = 0; i < spec_.posters; ++i) place_on_random_wall(&RoomBuilder::add_poster, all_walls());
    const double floor_top = add_floor_boxes(L, W);

    Scene scene = builder_.finish();
    scene.ambient = {0.1, 0.003};
    // Free space: clearance from every wall item, the floor boxes and the ceiling panels.
    const double c = spec_.clearance_m;
    Box3 box;
    box.min = Vec3(-L / 2 + walls_[1].protrusion + c, -W / 2 + walls_[3].protrusion + c, std::max(floor_top + c, 0.9));
    box.max = Vec3(L / 2 - walls_[0].protrusion - c, W / 2 - walls_[2].protrusion - c, H - 0.01 - c);
    for (int a = 0; a < 3; ++a)
      if (box.min[a] > box.max[a]) box.min[a] = box.max[a] = 0.5 * (box.min[a] + box.max[a]);
    scene.free_space = box;
    scene.has_preferred_yaw = corridor;
    scene.preferred_yaw = 0;
    return scene;
  }

 private:
  using Placer = bool (RoomBuilder::*)(Wall&);
  static std::vector<int> all_walls() { return {0, 1, 2, 3}; }

  void place_on_random_wall(Placer placer, const std::vector<int>& candidates) {
    for (int attempt = 0; attempt < 8; ++attempt) {
      Wall& wall = walls_[candidates[rng_.integer(0, static_cast<int>(candidates.size()) - 1)]];
      if ((this->*placer)(wall)) return;
    }
  }

  TextureMaker paint(double base, double noise = 0.01) {
    return [this, base, noise](const Extent& e) { return textures::paint(e, rng_, base, noise); };
  }

  // ---- shell: walls (x = +L/2, x = -L/2, y = +W/2, y = -W/2), floor and ceiling
  void add_shell(double L, double W, double H) {
    const Vec3 centres[4] = {{L / 2, 0, 0}, {-L / 2, 0, 0}, {0, W / 2, 0}, {0, -W / 2, 0}};
    const Vec3 normals[4] = {-Vec3::UnitX(), Vec3::UnitX(), -Vec3::UnitY(), Vec3::UnitY()};
    const double lengths[4] = {W, W, L, L};
    const double density = spec_.texels_per_m;
    for (int i = 0; i < 4; ++i) {
      Wall& w = walls_[i];
      w.length = lengths[i];
      w.frame.normal = normals[i];
      w.frame.right = (-normals[i]).cross(kUp);
      w.frame.origin = centres[i] - 0.5 * lengths[i] * w.frame.right;
      const Extent e{lengths[i], H, density};
      Texture tex;
      if (low_) tex = textures::plain(e, rng_, rng_.uniform(0.68, 0.8));
      else if (i == 2 || rng_.chance(0.3)) tex = textures::concrete_blocks(e, rng_);
      else tex = textures::plaster(e, rng_, rng_.uniform(0.62, 0.78));
      builder_.add_facing(centres[i] + 0.5 * H * kUp, normals[i], kUp, lengths[i], H, std::move(tex));
    }
    const Extent floor{W, L, density};
    Texture floor_tex = low_ ? textures::plain(floor, rng_, 0.42)
                             : (rng_.chance(0.5) ? textures::floor_tiles(floor, rng_, rng_.uniform(0.4, 0.6))
                                                 : textures::wood(floor, rng_, true, rng_.uniform(0.4, 0.55)));
    builder_.add_facing(Vec3::Zero(), kUp, Vec3::UnitX(), W, L, std::move(floor_tex));
    const Extent ceiling{W, L, density * 0.75};
    Texture ceiling_tex = low_ ? textures::plain(ceiling, rng_, 0.82) : textures::ceiling_tiles(ceiling, rng_);
    builder_.add_facing(H * kUp, -kUp, Vec3::UnitX(), W, L, std::move(ceiling_tex));
  }

  void add_ceiling_lights(double L, double W, double H) {
    const int count = spec_.ceiling_lights;
    if (count <= 0) return;
    const int nx = std::max(1, static_cast<int>(std::lround(std::sqrt(count * L / W))));
    const int ny = (count + nx - 1) / nx;
    int placed = 0;
    for (int iy = 0; iy < ny && placed < count; ++iy)
      for (int ix = 0; ix < nx && placed < count; ++ix, ++placed) {
        const Vec3 c((ix + 0.5) / nx * L - L / 2, (iy + 0.5) / ny * W - W / 2, H - 0.01);
        builder_.add_facing(c, -kUp, Vec3::UnitX(), 0.6, 0.6,
                            textures::light_panel(Extent{0.6, 0.6, 100}, rng_, 4.7));
        Light light;
        light.position = c - 0.05 * kUp;
        light.direction = -kUp;
        light.power = kPanelPower;
        light.on = {true, false};
        builder_.add_light(light);
        // Light reflected off the floor and walls brightens the ceiling around each lamp.
        Light bounce;
        bounce.position = c - 0.9 * kUp;
        bounce.power = 0.12 * kPanelPower;
        bounce.on = {true, false};
        builder_.add_light(bounce);
      }
  }

  // ---- wall items; each returns false when the wall has no room for it
  bool add_door(Wall& wall) {
    const double width = rng_.uniform(0.85, 1.0), height = std::min(2.05, spec_.height_m - 0.2), frame = 0.07;
    double a0;
    if (!reserve(wall, rng_, width + 2 * frame, true, true, a0)) return false;
    a0 += frame;
    const Frame& f = wall.frame;
    builder_.add_facing(f.at(a0 + width / 2, height / 2, 0.01), f.normal, kUp, width, height,
                        low_ ? textures::paint(Extent{width, height, 150}, rng_, rng_.uniform(0.3, 0.5))
                             : textures::door(Extent{width, height, 250}, rng_));
    const auto frame_tex = paint(rng_.chance(0.5) ? 0.85 : 0.25);
    const unsigned faces = kFront | kLeft | kRight | kTop | kBottom;
    add_box(builder_, f, a0 - frame, a0, 0, height, 0, 0.03, faces & ~kBottom, frame_tex, frame_tex, 150);
    add_box(builder_, f, a0 + width, a0 + width + frame, 0, height, 0, 0.03, faces & ~kBottom, frame_tex, frame_tex, 150);
    add_box(builder_, f, a0 - frame, a0 + width + frame, height, height + frame, 0, 0.03, faces, frame_tex, frame_tex,
            150);
    const auto handle = paint(0.15);
    add_box(builder_, f, a0 + width - 0.17, a0 + width - 0.05, 1.0, 1.03, 0.01, 0.06, faces, handle, handle, 300);
    wall.protrusion = std::max(wall.protrusion, 0.06);
    return true;
  }

  bool add_window(Wall& wall) {
    const double width = rng_.uniform(1.0, 1.8), z0 = 0.96, z1 = std::min(2.25, spec_.height_m - 0.35);
    const double frame = 0.06;
    double a0;
    if (!reserve(wall, rng_, width + 2 * frame, false, true, a0)) return false;
    a0 += frame;
    const Frame& f = wall.frame;
    builder_.add_facing(f.at(a0 + width / 2, (z0 + z1) / 2, 0.003), f.normal, kUp, width, z1 - z0,
                        textures::window_view(Extent{width, z1 - z0, 120}, rng_, 2.5));
    const auto tex = paint(rng_.chance(0.6) ? 0.88 : 0.3);
    const unsigned side = kFront | kLeft | kRight | kTop | kBottom;
    add_box(builder_, f, a0 - frame, a0, z0 - frame, z1 + frame, 0, 0.05, side, tex, tex, 150);
    add_box(builder_, f, a0 + width, a0 + width + frame, z0 - frame, z1 + frame, 0, 0.05, side, tex, tex, 150);
    add_box(builder_, f, a0, a0 + width, z0 - frame, z0, 0, 0.09, kFront | kTop | kBottom, tex, tex, 150);
    add_box(builder_, f, a0, a0 + width, z1, z1 + frame, 0, 0.05, kFront | kTop | kBottom, tex, tex, 150);
    const double am = a0 + width / 2, zm = z0 + 0.6 * (z1 - z0), bar = 0.02;
    add_box(builder_, f, am - bar, am + bar, z0, z1, 0, 0.03, kFront | kLeft | kRight, tex, tex, 150);
    add_box(builder_, f, a0, am - bar, zm - bar, zm + bar, 0, 0.03, kFront | kTop | kBottom, tex, tex, 150);
    add_box(builder_, f, am + bar, a0 + width, zm - bar, zm + bar, 0, 0.03, kFront | kTop | kBottom, tex, tex, 150);
    // Daylight through the window: a cosine emitter well behind the pane, so that the
    // walls and ceiling next to the window are not lit like by a bare bulb.
    Light light;
    light.position = f.at(a0 + width / 2, (z0 + z1) / 2, -1.5);
    light.direction = f.normal;
    light.power = kWindowPower * spec_.window_light * width * (z1 - z0);
    light.on = {true, true};
    builder_.add_light(light);
    wall.protrusion = std::max(wall.protrusion, 0.09);
    return true;
  }

  bool add_shelf(Wall& wall) {
    const double width = rng_.uniform(0.8, 1.6), height = std::min(rng_.uniform(1.6, 2.1), spec_.height_m - 0.4);
    const double depth = rng_.uniform(0.3, 0.42), panel = 0.02;
    double a0;
    if (!reserve(wall, rng_, width, true, true, a0)) return false;
    const Frame& f = wall.frame;
    const auto wood = paint(rng_.uniform(0.25, 0.75), 0.02);
    add_box(builder_, f, a0, a0 + panel, 0, height, 0, depth, kFront | kLeft | kRight | kTop, wood, wood, 150);
    add_box(builder_, f, a0 + width - panel, a0 + width, 0, height, 0, depth, kFront | kLeft | kRight | kTop, wood,
            wood, 150);
    builder_.add_facing(f.at(a0 + width / 2, height / 2, 0.003), f.normal, kUp, width - 2 * panel, height,
                        textures::paint(Extent{width - 2 * panel, height, 100}, rng_, rng_.uniform(0.2, 0.6), 0.01));
    const int boards = rng_.integer(4, 5);
    const double spacing = (height - 0.1) / boards;
    for (int k = 0; k <= boards; ++k) {
      const double z = std::min(0.08 + k * spacing, height - panel);
      add_box(builder_, f, a0 + panel, a0 + width - panel, z, z + panel, 0, depth, kFront | kTop | kBottom, wood, wood,
              150);
      if (k < boards) add_books(f, a0 + panel, a0 + width - panel, z + panel, spacing - panel, depth);
    }
    wall.protrusion = std::max(wall.protrusion, depth);
    return true;
  }

  void add_books(const Frame& f, double a0, double a1, double z, double room, double depth) {
    double a = a0 + rng_.uniform(0.01, 0.15);
    while (a < a1 - 0.15) {
      const double w = std::min(rng_.uniform(0.15, 0.6), a1 - a - 0.01);
      const double h = std::min(rng_.uniform(0.17, 0.3), room - 0.04);
      const double dep = std::min(rng_.uniform(0.17, 0.24), depth - 0.04);
      if (h < 0.1 || w < 0.08) break;
      const auto side = paint(rng_.uniform(0.2, 0.8), 0.02);
      const TextureMaker front = [this](const Extent& e) {
        return low_ ? textures::paint(e, rng_, rng_.uniform(0.2, 0.8)) : textures::books(e, rng_);
      };
      add_box(builder_, f, a, a + w, z, z + h, depth - 0.02 - dep, depth - 0.02, kFront | kLeft | kRight | kTop, front,
              side, 400);
      a += w + rng_.uniform(0.03, 0.25);
    }
  }

  bool add_box_stack(Wall& wall) {
    const double width = rng_.uniform(0.3, 0.7), depth = rng_.uniform(0.3, 0.5);
    double a0;
    if (!reserve(wall, rng_, width, true, false, a0)) return false;
    const Frame& f = wall.frame;
    const TextureMaker tex = [this](const Extent& e) {
      return low_ ? textures::paint(e, rng_, rng_.uniform(0.3, 0.6)) : textures::cardboard(e, rng_);
    };
    const unsigned faces = kFront | kLeft | kRight | kTop;
    const double h1 = rng_.uniform(0.25, 0.45);
    add_box(builder_, f, a0, a0 + width, 0, h1, 0.02, 0.02 + depth, faces, tex, tex, 250);
    if (rng_.chance(0.5)) {  // a smaller box on top
      const double w2 = width * rng_.uniform(0.5, 0.85), d2 = depth * rng_.uniform(0.6, 0.9);
      const double h2 = std::min(rng_.uniform(0.2, 0.35), kLowBandTop - h1);
      const double off = rng_.uniform(0.0, width - w2);
      add_box(builder_, f, a0 + off, a0 + off + w2, h1, h1 + h2, 0.02, 0.02 + d2, faces, tex, tex, 250);
    }
    wall.protrusion = std::max(wall.protrusion, 0.02 + depth);
    return true;
  }

  bool add_poster(Wall& wall) {
    const bool board = rng_.chance(0.3);
    double width = board ? rng_.uniform(1.2, 2.0) : rng_.uniform(0.4, 0.9);
    double height = board ? rng_.uniform(0.8, 1.1) : width * (rng_.chance(0.7) ? rng_.uniform(1.2, 1.45) : 0.7);
    height = std::min(height, spec_.height_m - 0.25 - kHighBandBottom - 0.1);
    double a0;
    if (!reserve(wall, rng_, width, false, true, a0)) return false;
    const double zmin = kHighBandBottom + 0.1, zmax = spec_.height_m - 0.25 - height;
    const double z0 = zmax > zmin ? rng_.uniform(zmin, std::min(zmax, 1.5)) : zmin;
    const Extent e{width, height, 400};
    Texture tex = low_ ? textures::paint(e, rng_, rng_.chance(0.5) ? 0.3 : 0.92)
                       : (board ? textures::whiteboard(e, rng_) : textures::poster(e, rng_));
    builder_.add_facing(wall.frame.at(a0 + width / 2, z0 + height / 2, board ? 0.012 : 0.005), wall.frame.normal, kUp,
                        width, height, std::move(tex));
    wall.protrusion = std::max(wall.protrusion, 0.012);
    return true;
  }

  /// Low boxes in the middle of the floor; returns the highest top.
  double add_floor_boxes(double L, double W) {
    struct Placed {
      double x, y, r;
    };
    std::vector<Placed> placed;
    double top = 0;
    for (int i = 0; i < spec_.floor_boxes; ++i) {
      const double w = rng_.uniform(0.3, 0.7), dep = rng_.uniform(0.3, 0.7), h = rng_.uniform(0.2, 0.5);
      const double r = 0.5 * std::hypot(w, dep);
      for (int attempt = 0; attempt < 30; ++attempt) {
        const double mx = L / 2 - 1.0 - r, my = W / 2 - 1.0 - r;
        if (mx <= 0 || my <= 0) break;
        const double x = rng_.uniform(-mx, mx), y = rng_.uniform(-my, my);
        bool clash = false;
        for (const auto& p : placed) clash = clash || std::hypot(p.x - x, p.y - y) < p.r + r + 0.2;
        if (clash) continue;
        const double yaw = rng_.uniform(0, M_PI);
        Frame f{Vec3(x, y, 0), Vec3(std::cos(yaw), std::sin(yaw), 0), Vec3(-std::sin(yaw), std::cos(yaw), 0)};
        const TextureMaker tex = [this](const Extent& e) {
          return low_ ? textures::paint(e, rng_, rng_.uniform(0.3, 0.6)) : textures::cardboard(e, rng_);
        };
        add_box(builder_, f, -w / 2, w / 2, 0, h, -dep / 2, dep / 2, kFront | kBack | kLeft | kRight | kTop, tex, tex,
                250);
        placed.push_back({x, y, r});
        top = std::max(top, h);
        break;
      }
    }
    return top;
  }

  const SceneSpec& spec_;
  Random rng_;
  bool low_;
  SceneBuilder builder_;
  Wall walls_[4];
};

}  // namespace

Scene build_scene(const SceneSpec& spec, uint64_t seed) { return RoomBuilder(spec, seed).build(); }

}  // namespace pllvo::synth
