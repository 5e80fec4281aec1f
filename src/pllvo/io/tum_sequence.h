#pragma once
// TUM RGB-D layout: rgb.txt (`timestamp filename`), rgb/*.png colour images, optional
// groundtruth.txt (TUM trajectory, already T_world_cam). TUM ships no intrinsics file, so
// they come from pllvo's camera YAML (camera/camera_yaml.h).
#include <filesystem>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// Camera YAML: options.camera_yaml, else `camera.yaml` in `root`. Its optional `fps` is the
/// nominal rate. Colour frames are converted to gray. depth.txt is not read.
class TumSequence final : public Sequence {
 public:
  TumSequence(const std::filesystem::path& root, const SequenceOptions& options = {});
  std::string format() const override { return "tum"; }
};

}  // namespace pllvo::io
