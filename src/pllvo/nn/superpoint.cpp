#include "pllvo/nn/superpoint.h"

#include <array>
#include <cmath>
#include <cstring>
#include <set>

#include <ATen/core/Tensor.h>
#include <ATen/ops/conv2d.h>
#include <ATen/ops/empty.h>
#include <ATen/ops/max_pool2d.h>
#include <ATen/ops/mkldnn_convolution.h>
#include <ATen/ops/mkldnn_reorder_conv2d_weight.h>
#include <ATen/ops/softmax.h>
#include <c10/core/InferenceMode.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"
#include "pllvo/nn/model_files.h"
#include "pllvo/nn/torch_adapter.h"

namespace pllvo::nn {

SuperPointConfig SuperPointConfig::from_yaml(const ConfigNode& node) {
  SuperPointConfig c;
  std::string weights;
  node.get("weights", weights);
  c.weights = weights;
  node.get("nms_radius", c.nms_radius);
  node.get("detection_threshold", c.detection_threshold);
  node.get("remove_borders", c.remove_borders);
  node.get("max_keypoints", c.max_keypoints);
  node.get("downscale", c.downscale);
  node.get("conv_layout", c.conv_layout);
  node.reject_unknown_keys();
  if (const auto [key, what] = c.problem(); !key.empty()) throw InputError(node.file(), node.path(key), what);
  return c;
}

std::pair<std::string, std::string> SuperPointConfig::problem() const {
  if (nms_radius < 0) return {"nms_radius", "must be >= 0"};
  if (!(detection_threshold >= 0.0f)) return {"detection_threshold", "must be >= 0"};
  if (remove_borders < 0) return {"remove_borders", "must be >= 0"};
  if (!(downscale >= 1.0)) return {"downscale", "must be >= 1"};
  if (conv_layout != "mkldnn" && conv_layout != "channels_last" && conv_layout != "nchw")
    return {"conv_layout", "must be nchw, channels_last or mkldnn"};
  return {};
}

void SuperPointConfig::validate() const {
  if (const auto [key, what] = problem(); !key.empty()) throw InputError("SuperPoint setting " + key + ": " + what);
}

namespace {

// A `config` JSON in the metadata (written by scripts/convert_weights.py) must agree with the tensors.
void check_metadata_config(const SafeTensors& st, int descriptor_dim) {
  const auto it = st.metadata().find("config");
  if (it == st.metadata().end()) return;
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(it->second);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(st.file(), "__metadata__.config", std::string("malformed JSON: ") + e.what());
  }
  if (config.contains("descriptor_dim") && config["descriptor_dim"] != descriptor_dim)
    throw InputError(st.file(), "__metadata__.config.descriptor_dim",
                     "says " + config["descriptor_dim"].dump() + " but convDb.weight has " + std::to_string(descriptor_dim) + " rows");
}

}  // namespace

// The network. Layer names and shapes are those of superpoint_v1.pth.
struct SuperPoint::Net {
  struct Conv {
    at::Tensor weight, bias;
    std::int64_t padding = 0;
  };
  Conv conv1a, conv1b, conv2a, conv2b, conv3a, conv3b, conv4a, conv4b, convPa, convPb, convDa, convDb;
  int descriptor_dim = 256;

  explicit Net(const SafeTensors& st) {
    const auto& db = st.at("convDb.weight");
    if (db.shape.size() != 4) throw InputError(st.file(), "convDb.weight", "shape " + shape_string(db.shape) + ", expected [D, 256, 1, 1]");
    descriptor_dim = static_cast<int>(db.shape[0]);
    check_metadata_config(st, descriptor_dim);
    std::set<std::string> expected;
    const auto load = [&](Conv& c, const std::string& name, std::int64_t out, std::int64_t in, std::int64_t k) {
      c.weight = detail::float_tensor(st, name + ".weight", {out, in, k, k});
      c.bias = detail::float_tensor(st, name + ".bias", {out});
      c.padding = k / 2;
      expected.insert({name + ".weight", name + ".bias"});
    };
    load(conv1a, "conv1a", 64, 1, 3);
    load(conv1b, "conv1b", 64, 64, 3);
    load(conv2a, "conv2a", 64, 64, 3);
    load(conv2b, "conv2b", 64, 64, 3);
    load(conv3a, "conv3a", 128, 64, 3);
    load(conv3b, "conv3b", 128, 128, 3);
    load(conv4a, "conv4a", 128, 128, 3);
    load(conv4b, "conv4b", 128, 128, 3);
    load(convPa, "convPa", 256, 128, 3);
    load(convPb, "convPb", 65, 256, 1);
    load(convDa, "convDa", 256, 128, 3);
    load(convDb, "convDb", descriptor_dim, 256, 1);
    for (const auto& name : st.names())
      if (!expected.count(name)) throw InputError(st.file(), name, "unexpected tensor (not a SuperPoint weight)");
  }

  enum class Layout { Nchw, ChannelsLast, Mkldnn };
  Layout layout = Layout::Mkldnn;

  // Weights in the layout's preferred form, prepared once.
  void prepare(const std::string& name) {
    layout = name == "nchw" ? Layout::Nchw : name == "channels_last" ? Layout::ChannelsLast : Layout::Mkldnn;
    for (Conv* c : {&conv1a, &conv1b, &conv2a, &conv2b, &conv3a, &conv3b, &conv4a, &conv4b, &convPa, &convPb, &convDa, &convDb}) {
      const std::array<std::int64_t, 2> pad{c->padding, c->padding}, one{1, 1};
      if (layout == Layout::Mkldnn) {
        c->weight = at::mkldnn_reorder_conv2d_weight(c->weight.contiguous().to_mkldnn(), pad, one, one, 1);
        c->bias = c->bias.to_mkldnn();
      } else {
        c->weight = c->weight.contiguous(layout == Layout::ChannelsLast ? at::MemoryFormat::ChannelsLast
                                                                                   : at::MemoryFormat::Contiguous);
      }
    }
  }

  at::Tensor conv(const at::Tensor& x, const Conv& c) const {
    const std::array<std::int64_t, 2> stride{1, 1}, pad{c.padding, c.padding}, dilation{1, 1};
    if (layout == Layout::Mkldnn) return at::mkldnn_convolution(x, c.weight, c.bias, pad, stride, dilation, 1);
    return at::conv2d(x, c.weight, c.bias, stride, pad);
  }
  at::Tensor conv_relu(const at::Tensor& x, const Conv& c) const { return conv(x, c).relu_(); }
  static at::Tensor pool(const at::Tensor& x) {
    const std::array<std::int64_t, 2> k{2, 2};
    return at::max_pool2d(x, k, k);
  }

  // image: [1, 1, H, W] float in [0, 1].
  void forward(const at::Tensor& image, SuperPointDense& out) const {
    at::Tensor x = layout == Layout::Mkldnn         ? image.to_mkldnn()
                   : layout == Layout::ChannelsLast ? image.contiguous(at::MemoryFormat::ChannelsLast)
                                                    : image;
    x = conv_relu(x, conv1a);
    x = pool(conv_relu(x, conv1b));
    x = conv_relu(x, conv2a);
    x = pool(conv_relu(x, conv2b));
    x = conv_relu(x, conv3a);
    x = pool(conv_relu(x, conv3b));
    x = conv_relu(x, conv4a);
    x = conv_relu(x, conv4b);

    // Detector head: softmax over 65 channels, dustbin dropped, depth-to-space
    // score[8y + r, 8x + c] = prob[8r + c, y, x].
    const auto dense = [&](const at::Tensor& t) { return layout == Layout::Mkldnn ? t.to_dense() : t.contiguous(); };
    at::Tensor scores = at::softmax(dense(conv(conv_relu(x, convPa), convPb)), 1).slice(1, 0, 64);
    const std::int64_t h = scores.size(2), w = scores.size(3);
    scores = scores.permute({0, 2, 3, 1}).reshape({h, w, 8, 8}).permute({0, 2, 1, 3}).reshape({h * 8, w * 8});
    scores = scores.contiguous();
    out.scores.resize(h * 8, w * 8);
    std::memcpy(out.scores.data(), scores.data_ptr<float>(), sizeof(float) * static_cast<std::size_t>(scores.numel()));

    // Descriptor head, L2-normalised over channels (F.normalize, eps 1e-12), stored cell-major.
    at::Tensor desc = dense(conv(conv_relu(x, convDa), convDb));
    desc = desc.div(desc.norm(2, {1}, true).clamp_min(1e-12));
    desc = desc[0].permute({1, 2, 0}).contiguous();
    out.descriptors.resize(h * w, descriptor_dim);
    std::memcpy(out.descriptors.data(), desc.data_ptr<float>(), sizeof(float) * static_cast<std::size_t>(desc.numel()));
    out.cells_w = static_cast<int>(w);
    out.cells_h = static_cast<int>(h);
  }
};

SuperPoint::SuperPoint(SuperPointConfig config) : config_(std::move(config)) {
  config_.validate();
  const auto search = find_weights(config_.weights, superpoint_weight_names());
  if (!search.found)
    throw InputError("SuperPoint weights " + search.not_found_message() +
                     "; there is no fallback for SuperPoint. Set the weights path, or $PLLVO_MODELS, "
                     "or put the file in the repository's models/ (see docs/nn.md)");
  weights_file_ = *search.found;
  net_ = std::make_unique<Net>(SafeTensors::load(weights_file_));
  net_->prepare(config_.conv_layout);
}

SuperPoint::SuperPoint(const SafeTensors& weights, SuperPointConfig config)
    : net_(std::make_unique<Net>(weights)), config_(std::move(config)), weights_file_(weights.file()) {
  config_.validate();
  net_->prepare(config_.conv_layout);
}

SuperPoint::~SuperPoint() = default;
SuperPoint::SuperPoint(SuperPoint&&) noexcept = default;
SuperPoint& SuperPoint::operator=(SuperPoint&&) noexcept = default;

int SuperPoint::descriptor_dim() const { return net_->descriptor_dim; }

SuperPointDense SuperPoint::run_network(const cv::Mat& image) const {
  if (image.empty() || image.channels() != 1 || (image.depth() != CV_8U && image.depth() != CV_32F))
    throw InputError("SuperPoint needs a single-channel 8-bit (or float [0, 1]) grayscale image");
  SuperPointDense out;
  out.image_size = {image.cols, image.rows};
  cv::Mat input = image;
  if (config_.downscale > 1.0) {
    const cv::Size size(static_cast<int>(std::lround(image.cols / config_.downscale)),
                        static_cast<int>(std::lround(image.rows / config_.downscale)));
    cv::resize(image, input, size, 0, 0, cv::INTER_AREA);
    out.scale = {static_cast<float>(image.cols) / static_cast<float>(size.width),
                 static_cast<float>(image.rows) / static_cast<float>(size.height)};
  }
  if (input.cols < 8 || input.rows < 8) throw InputError("SuperPoint needs an image of at least 8 x 8 pixels");

  c10::InferenceMode guard;
  at::Tensor x = at::empty({1, 1, input.rows, input.cols}, at::TensorOptions().dtype(at::kFloat));
  float* dst = x.data_ptr<float>();
  for (int y = 0; y < input.rows; ++y) {
    float* row = dst + static_cast<std::ptrdiff_t>(y) * input.cols;
    if (input.depth() == CV_8U) {
      const auto* src = input.ptr<std::uint8_t>(y);
      for (int c = 0; c < input.cols; ++c) row[c] = static_cast<float>(src[c]) / 255.0f;
    } else {
      std::memcpy(row, input.ptr<float>(y), sizeof(float) * static_cast<std::size_t>(input.cols));
    }
  }
  net_->forward(x, out);
  return out;
}

Features SuperPoint::detect(const cv::Mat& image) const {
  return detect(image, config_.detection_threshold, config_.max_keypoints);
}

Features SuperPoint::detect(const cv::Mat& image, float threshold, int max_keypoints) const {
  const auto dense = run_network(image);
  const auto candidates = find_candidates(dense.scores, config_.nms_radius, config_.remove_borders);
  return extract_features(dense, candidates, select_keypoints(candidates, threshold, max_keypoints));
}

}  // namespace pllvo::nn
