#pragma once
// TUM RGB-D layout: rgb.txt (`timestamp filename`), rgb/*.png colour images, optional
// depth.txt with depth/*.png (16-bit, registered to the colour camera), optional
// groundtruth.txt (TUM trajectory, already T_world_cam). TUM ships no intrinsics file, so
// they come from pllvo's camera YAML (camera/camera_yaml.h).
#include <filesystem>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// Camera YAML: options.camera_yaml, else `camera.yaml` in `root`. Its optional `fps` is the
/// nominal rate, its optional `depth_factor` the depth images' units per metre (default 5000,
/// TUM's). Colour frames are converted to gray. With options.depth, each colour frame takes the
/// depth image of depth.txt nearest in time within options.depth_max_dt (none: no depth).
class TumSequence final : public Sequence {
 public:
  TumSequence(const std::filesystem::path& root, const SequenceOptions& options = {});
  std::string format() const override { return "tum"; }
};

}  // namespace pllvo::io
