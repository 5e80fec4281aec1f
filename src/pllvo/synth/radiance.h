#pragma once
// Scene radiance for one lighting state: each quad's reflectance times the irradiance of
// the lights (baked once per state, so rendering is a texture lookup), stored as
// mip-mapped 16-bit images so distant surfaces are filtered instead of aliased.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "pllvo/synth/scene.h"

namespace pllvo::synth {

/// One mip level inside MipTexture::data: `rows` x `cols` texels, row stride `step`,
/// starting at element `offset`. Each level carries one replicated column and row past its
/// edge, so a bilinear lookup never needs to clamp its second tap.
struct MipLevel {
  int cols = 0, rows = 0, step = 0;
  int64_t offset = 0;
};

/// Mip-mapped 16-bit image: level 0 full resolution, each further level half the size;
/// radiance = value * scale.
struct MipTexture {
  std::vector<uint16_t> data;
  std::vector<MipLevel> levels;
  float scale = 0;

  /// Level `l` as an image (a copy, CV_16U), for inspection and tests.
  cv::Mat level(size_t l) const;
};

struct RadianceState {
  std::vector<MipTexture> quads;  ///< indexed like Scene::quads
  double mean_radiance = 0;       ///< area-weighted mean over non-emissive surfaces
};

/// Irradiance at point `x` with normal `n` in lighting state `state` (ambient + lights).
double irradiance(const Scene& scene, int state, const Eigen::Vector3d& x, const Eigen::Vector3d& n);

/// Factor on every light (and the ambient term) that makes the area-weighted mean radiance
/// of the non-emissive surfaces in state 0 equal `target` (so exposure does not depend on
/// how many lamps a scene has).
double light_normalisation(const Scene& scene, double target = 0.3);

RadianceState bake_radiance(const Scene& scene, int state, double light_scale);

}  // namespace pllvo::synth
