#include "pllvo/nn/features.h"

#include <cstdint>

#include "pllvo/common/error.h"
#include "pllvo/nn/safetensors.h"

namespace pllvo::nn {

void save_features(const Features& f, const std::filesystem::path& file) {
  const std::int64_t n = f.size();
  if (f.scores.size() != n || f.descriptors.rows() != n)
    throw InternalError("save_features: keypoints, scores and descriptors differ in length");
  SafeTensors out;
  out.set_f32("keypoints", {n, 2}, f.keypoints.data());
  out.set_f32("scores", {n}, f.scores.data());
  out.set_f32("descriptors", {n, f.descriptors.cols()}, f.descriptors.data());
  const std::int64_t size[2] = {f.image_size.x(), f.image_size.y()};
  out.set_i64("image_size", {2}, size);
  out.metadata()["format"] = "pllvo features: keypoints (x, y) pixels, scores, L2-normalised descriptors";
  out.save(file);
}

namespace {
SafeTensors matches_tensors(const Matches& m) {
  SafeTensors out;
  const std::int64_t k = m.size();
  std::vector<std::int64_t> pairs(static_cast<std::size_t>(2 * k));
  for (std::int64_t i = 0; i < k; ++i) {
    pairs[2 * i] = m.pairs(i, 0);
    pairs[2 * i + 1] = m.pairs(i, 1);
  }
  out.set_i64("matches", {k, 2}, pairs.data());
  out.set_f32("scores", {k}, m.scores.data());
  return out;
}
}  // namespace

void save_matches(const Matches& matches, const std::filesystem::path& file) { matches_tensors(matches).save(file); }

Features load_features(const std::filesystem::path& file) {
  const auto st = SafeTensors::load(file);
  const auto& kp = st.at("keypoints");
  if (kp.shape.size() != 2 || kp.shape[1] != 2)
    throw InputError(file, "keypoints", "shape " + shape_string(kp.shape) + ", expected [N, 2]");
  const std::int64_t n = kp.shape[0];
  const std::string score_name = st.contains("scores") ? "scores" : "keypoint_scores";
  if (!st.contains(score_name)) throw InputError(file, "scores", "tensor missing (nor keypoint_scores)");
  st.check_shape(score_name, {n});
  const auto& desc = st.at("descriptors");
  if (desc.shape.size() != 2 || desc.shape[0] != n)
    throw InputError(file, "descriptors", "shape " + shape_string(desc.shape) + ", expected [" +
                                              std::to_string(n) + ", D]");
  st.check_shape("image_size", {2});

  Features f;
  const auto k = st.floats("keypoints");
  f.keypoints = Eigen::Map<const KeypointMatrix>(k.data(), n, 2);
  const auto s = st.floats(score_name);
  f.scores = Eigen::Map<const Eigen::VectorXf>(s.data(), n);
  const auto d = st.floats("descriptors");
  f.descriptors = Eigen::Map<const DescriptorMatrix>(d.data(), n, desc.shape[1]);
  const auto size = st.ints("image_size");
  if (size[0] <= 0 || size[1] <= 0) throw InputError(file, "image_size", "must be positive (width, height)");
  f.image_size = {static_cast<int>(size[0]), static_cast<int>(size[1])};
  return f;
}

}  // namespace pllvo::nn
