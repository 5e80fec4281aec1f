#pragma once
// Procedural textures for indoor surfaces. Each returns the reflectance image (CV_32F,
// values in [0, 1]) of a surface of `width_m` x `height_m` metres at `texels_per_m`, and
// the exact straight edges drawn in it (tile grout, poster shapes, ...). Shapes are drawn
// on texel boundaries or with anti-aliased coverage, so each edge's 50% level lies on
// the listed segment.
#include "pllvo/synth/random.h"
#include "pllvo/synth/scene.h"

namespace pllvo::synth::textures {

struct Extent {
  double width_m, height_m, texels_per_m;
  cv::Size texels() const;
};

/// Painted plaster: multi-scale noise and a few stains.
Texture plaster(const Extent& e, Random& rng, double base = 0.7, double contrast = 0.06);
/// Almost uniform paint (low-texture walls): faint noise and a slow gradient.
Texture plain(const Extent& e, Random& rng, double base = 0.72);
/// Concrete block wall (0.4 x 0.2 m blocks, offset rows, mortar lines).
Texture concrete_blocks(const Extent& e, Random& rng);
/// Floor tiles of `tile_m` with dark grout and per-tile shade.
Texture floor_tiles(const Extent& e, Random& rng, double tile_m = 0.5);
/// Suspended ceiling: 0.6 m acoustic tiles in a bright T-bar grid.
Texture ceiling_tiles(const Extent& e, Random& rng);
/// Wood grain along u; `planks` adds plank joints (floors) every 0.15-0.2 m.
Texture wood(const Extent& e, Random& rng, bool planks, double base = 0.5);
/// Poster: blocks of colour, a picture with a triangle, a title and lines of text.
Texture poster(const Extent& e, Random& rng);
/// Cardboard with a tape strip and a printed label.
Texture cardboard(const Extent& e, Random& rng);
/// A row of book spines (vertical step edges between books of different shade).
Texture books(const Extent& e, Random& rng);
/// Painted metal or laminate: uniform shade with fine noise.
Texture paint(const Extent& e, Random& rng, double base, double noise = 0.01);
/// Daylight seen through a window (emissive): sky gradient and blurred buildings.
Texture window_view(const Extent& e, Random& rng, double radiance);
/// Ceiling light panel: emits `radiance` when on; switched off, its diffuser reflects the
/// remaining light like any surface.
Texture light_panel(const Extent& e, Random& rng, double radiance);
/// Whiteboard with faint marker strokes.
Texture whiteboard(const Extent& e, Random& rng);
/// Door leaf: wood with two inset panels.
Texture door(const Extent& e, Random& rng);
/// Checkerboard of `square_m` squares (aligned to texels) starting dark at the top left;
/// every inner grid line is listed as a step edge.
Texture checker(const Extent& e, double square_m, double dark = 0.1, double bright = 0.9);

}  // namespace pllvo::synth::textures
