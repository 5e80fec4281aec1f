#pragma once
// Procedural indoor scenes: a room (walls, floor, ceiling, shelves with books, boxes, doors,
// windows, posters, ceiling lights) or a corridor, laid out from a seed.
#include <cstdint>

#include "pllvo/synth/scene.h"
#include "pllvo/synth/spec.h"

namespace pllvo::synth {

/// Builds the scene of `spec` (layout room|corridor, texture rich|low). The free space keeps
/// `spec.clearance_m` to every surface; lights are normalised later by the generator.
Scene build_scene(const SceneSpec& spec, uint64_t seed);

}  // namespace pllvo::synth
