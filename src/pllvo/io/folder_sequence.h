#pragma once
// A user's own camera: a folder of images plus pllvo's camera YAML.
//   camera.yaml        intrinsics (camera/camera_yaml.h), optional `fps`, `depth_factor`
//   images.txt         optional `timestamp path` lines (seconds, paths relative to the folder)
//   images/            the images, when there is no images.txt (else the folder itself)
//   depth/             optional (RGB-D): per image a 16-bit PNG of the same name, registered to
//                      the camera; metres = value / the YAML's depth_factor (required then)
//   groundtruth.txt    optional TUM trajectory (T_world_cam)
#include <filesystem>

#include "pllvo/io/sequence.h"

namespace pllvo::io {

/// Without images.txt, the images (png, jpg, jpeg, pgm, ppm, bmp, tif, tiff) of images/ -- or of
/// the folder itself when it has no images/ -- are taken sorted by file name, and frame i is
/// stamped i / fps with the YAML's `fps` (required then).
class FolderSequence final : public Sequence {
 public:
  FolderSequence(const std::filesystem::path& root, const SequenceOptions& options = {});
  std::string format() const override { return "folder"; }
};

}  // namespace pllvo::io
