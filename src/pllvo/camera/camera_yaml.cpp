#include "pllvo/camera/camera_yaml.h"

#include <fstream>

namespace pllvo::camera {

CameraPtr make_camera(const std::string& distortion_model, int width, int height,
                      const PinholeIntrinsics& k, const std::vector<double>& distortion) {
  if (distortion_model == "radtan" || distortion_model == "radial-tangential" ||
      distortion_model == "plumb_bob")
    return std::make_shared<PinholeRadtan>(width, height, k, distortion);
  if (distortion_model == "none") return std::make_shared<PinholeRadtan>(width, height, k);
  if (distortion_model == "equidistant" || distortion_model == "kannala-brandt" ||
      distortion_model == "fisheye")
    return std::make_shared<KannalaBrandt>(width, height, k, distortion);
  throw InputError("unknown distortion model '" + distortion_model +
                   "' (expected radtan, equidistant or none)");
}

CameraPtr camera_from_yaml(const ConfigNode& node) {
  const auto model = node.has("model") ? node.require<std::string>("model") : "pinhole";
  if (model != "pinhole")
    throw InputError(node.file(), node.path("model"), "unknown camera model '" + model + "'");
  PinholeIntrinsics k;
  k.fx = node.require<double>("fx");
  k.fy = node.require<double>("fy");
  k.cx = node.require<double>("cx");
  k.cy = node.require<double>("cy");
  const int w = node.require<int>("width"), h = node.require<int>("height");
  std::string dist_model = "none";
  node.get("distortion_model", dist_model);
  std::vector<double> dist;
  node.get("distortion", dist);
  if (dist_model == "radtan" && dist.size() == 5 && dist[4] == 0.0) dist.resize(4);
  try {
    return make_camera(dist_model, w, h, k, dist);
  } catch (const InputError& e) {
    throw InputError(node.file(), node.path("distortion"), e.what());
  }
}

CameraPtr load_camera_yaml(const std::filesystem::path& file) {
  return camera_from_yaml(ConfigNode::load_file(file));
}

void save_camera_yaml(const CameraModel& camera, const std::filesystem::path& file) {
  const auto& k = camera.intrinsics();
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "model" << YAML::Value << "pinhole";
  out << YAML::Key << "width" << YAML::Value << camera.width();
  out << YAML::Key << "height" << YAML::Value << camera.height();
  out << YAML::Key << "fx" << YAML::Value << k.fx << YAML::Key << "fy" << YAML::Value << k.fy;
  out << YAML::Key << "cx" << YAML::Value << k.cx << YAML::Key << "cy" << YAML::Value << k.cy;
  out << YAML::Key << "distortion_model" << YAML::Value
      << (camera.name() == "kannala-brandt" ? "equidistant" : "radtan");
  out << YAML::Key << "distortion" << YAML::Value << YAML::Flow << camera.distortion();
  out << YAML::EndMap;
  std::ofstream f(file);
  if (!f) throw InputError(file, "cannot write");
  f << out.c_str() << "\n";
}

}  // namespace pllvo::camera
