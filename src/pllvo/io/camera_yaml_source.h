#pragma once
// The camera YAML of datasets that ship no calibration of their own (TUM RGB-D, image folders).
#include <filesystem>
#include <string>

#include "pllvo/camera/camera_model.h"
#include "pllvo/io/sequence.h"

namespace pllvo::io {

struct DatasetCamera {
  std::filesystem::path file;  ///< the YAML that was read
  camera::CameraPtr camera;
  double fps = 0;  ///< the YAML's optional `fps` key; 0 when absent
  /// The optional `depth_factor` key: units per metre of the depth images (TUM: 5000); 0 when absent.
  double depth_factor = 0;
};

/// Reads options.camera_yaml, or `camera.yaml` in `root` when none is given. `why` says why the
/// dataset needs one; it goes into the error when the file is missing.
DatasetCamera load_dataset_camera(const std::filesystem::path& root, const SequenceOptions& options,
                                  const std::string& why);

}  // namespace pllvo::io
