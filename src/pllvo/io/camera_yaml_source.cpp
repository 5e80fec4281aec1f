#include "pllvo/io/camera_yaml_source.h"

#include "pllvo/camera/camera_yaml.h"
#include "pllvo/common/error.h"
#include "pllvo/common/yaml_config.h"

namespace pllvo::io {

namespace fs = std::filesystem;

DatasetCamera load_dataset_camera(const fs::path& root, const SequenceOptions& options, const std::string& why) {
  DatasetCamera out;
  out.file = options.camera_yaml.empty() ? root / "camera.yaml" : options.camera_yaml;
  if (!fs::is_regular_file(out.file))
    throw InputError(out.file, "camera YAML not found (" + why +
                                   "): put camera.yaml in the dataset folder or pass --camera-yaml; "
                                   "see docs/datasets.md for the format");
  const ConfigNode node = ConfigNode::load_file(out.file);
  out.camera = camera::camera_from_yaml(node);
  node.get("fps", out.fps);
  if (!(out.fps >= 0)) throw InputError(out.file, std::string("fps"), "must be positive");
  node.get("depth_factor", out.depth_factor);
  if (!(out.depth_factor >= 0)) throw InputError(out.file, std::string("depth_factor"), "must be positive");
  return out;
}

}  // namespace pllvo::io
