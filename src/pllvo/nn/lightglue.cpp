#include "pllvo/nn/lightglue.h"
#include "pllvo/nn/runtime.h"

#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <set>

#include <ATen/core/Tensor.h>
#include <ATen/ops/_softmax.h>
#include <ATen/ops/addcmul.h>
#include <ATen/ops/arange.h>
#include <ATen/ops/bmm.h>
#include <ATen/ops/cat.h>
#include <ATen/ops/empty.h>
#include <ATen/ops/gelu.h>
#include <ATen/ops/layer_norm.h>
#include <ATen/ops/linear.h>
#include <ATen/ops/log_sigmoid.h>
#include <ATen/ops/log_softmax.h>
#include <ATen/ops/mm.h>
#include <ATen/ops/mul.h>
#include <ATen/ops/softmax.h>
#include <c10/core/InferenceMode.h>

#include "pllvo/common/error.h"
#include "pllvo/nn/model_files.h"
#include "pllvo/nn/torch_adapter.h"

namespace pllvo::nn {

// ---------------------------------------------------------------------------------------
// The network

namespace {

float confidence_threshold(int layer, int n_layers) {
  const double t = 0.8 + 0.1 * std::exp(-4.0 * layer / n_layers);
  return static_cast<float>(std::clamp(t, 0.0, 1.0));
}

at::Tensor features_tensor(const float* data, std::int64_t rows, std::int64_t cols) {
  at::Tensor t = at::empty({rows, cols}, at::TensorOptions().dtype(at::kFloat));
  if (rows * cols > 0) std::memcpy(t.data_ptr<float>(), data, sizeof(float) * static_cast<std::size_t>(rows * cols));
  return t;
}

Eigen::MatrixXf to_eigen(const at::Tensor& t) {
  const at::Tensor c = t.contiguous();
  using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(c.data_ptr<float>(), c.size(0), c.size(1));
}

at::Tensor index_tensor(const std::vector<std::int64_t>& rows) {
  at::Tensor index = at::empty({static_cast<std::int64_t>(rows.size())}, at::TensorOptions().dtype(at::kLong));
  if (!rows.empty()) std::memcpy(index.data_ptr<std::int64_t>(), rows.data(), rows.size() * sizeof(std::int64_t));
  return index;
}

// The points of one image still in play: descriptors, rotary encoding (cos, sin [N, 1, dh/2]),
// their original indices, and how many layers each original point went through.
struct PointSet {
  at::Tensor desc, cos, sin;
  std::vector<std::int64_t> index;
  std::vector<int> layers;

  std::int64_t size() const { return desc.size(0); }

  // Adaptive width: keeps the points where `keep` is true; the survivors go on one layer more.
  void prune(const at::Tensor& keep) {
    const at::Tensor k = keep.contiguous();
    const bool* flags = k.data_ptr<bool>();
    std::vector<std::int64_t> rows, kept;
    for (std::int64_t r = 0; r < k.size(0); ++r)
      if (flags[r]) rows.push_back(r), kept.push_back(index[static_cast<std::size_t>(r)]);
    const at::Tensor rows_t = index_tensor(rows);
    desc = desc.index_select(0, rows_t);
    cos = cos.index_select(0, rows_t);
    sin = sin.index_select(0, rows_t);
    index = std::move(kept);
    for (const auto i : index) ++layers[static_cast<std::size_t>(i)];
  }
};

}  // namespace

struct LightGlue::Net {
  struct Linear {
    at::Tensor weight, bias;
    at::Tensor operator()(const at::Tensor& x) const { return at::linear(x, weight, bias); }
  };
  struct Ffn {
    Linear fc0, fc3;
    at::Tensor norm_weight, norm_bias;
  };
  struct SelfBlock {
    // Wqkv with its rows regrouped as [q; k; v] (the official layout interleaves them per
    // feature) and, inside each head of q and k, the features ordered [even | odd], which
    // turns rotate_half into a swap of halves. q.k is unchanged by a common permutation.
    Linear qkv, out_proj;
    Ffn ffn;
  };
  struct CrossBlock {
    Linear qk_v;  // to_qk and to_v stacked: one product per image
    Linear to_out;
    Ffn ffn;
  };
  struct Assignment {
    Linear matchability, final_proj;
  };

  LightGlueArchitecture arch;
  bool has_input_proj = false;
  Linear input_proj;
  at::Tensor posenc_wr;  // [head_dim / 2, 2]
  std::vector<SelfBlock> self_blocks;
  std::vector<CrossBlock> cross_blocks;
  std::vector<Assignment> assignment;
  std::vector<Linear> token;
  std::vector<float> thresholds;

  // Wqkv row f = head*3*dh + j*3 + s holds q (s=0), k (1) or v (2) of feature j. Returns the
  // rows regrouped as [q; k; v], with q's and k's features ordered [even | odd] inside each head.
  static Linear regroup_qkv(const Linear& qkv, std::int64_t h, std::int64_t dh) {
    const std::int64_t d = h * dh;
    const at::Tensor even_odd = at::cat({at::arange(0, dh, 2), at::arange(1, dh, 2)});
    std::vector<at::Tensor> weights, biases;
    for (int part = 0; part < 3; ++part) {
      at::Tensor w = qkv.weight.view({h, dh, 3, d}).select(2, part);  // [h, dh, d]
      at::Tensor b = qkv.bias.view({h, dh, 3}).select(2, part);       // [h, dh]
      if (part < 2) {
        w = w.index_select(1, even_odd);
        b = b.index_select(1, even_odd);
      }
      weights.push_back(w.reshape({d, d}));
      biases.push_back(b.reshape({d}));
    }
    return {at::cat(weights, 0).contiguous(), at::cat(biases, 0).contiguous()};
  }

  explicit Net(const SafeTensors& raw) {
    const SafeTensors st = with_official_names(raw);
    arch = lightglue_architecture(st);
    if (arch.add_scale_ori)
      throw InputError(st.file(), "posenc.Wr.weight", "add_scale_ori (scale/orientation inputs) is not supported");
    const std::int64_t d = arch.descriptor_dim, h = arch.num_heads, dh = arch.head_dim();
    std::set<std::string> expected;
    const auto tensor = [&](const std::string& name, std::vector<std::int64_t> shape) {
      expected.insert(name);
      return detail::float_tensor(st, name, shape);
    };
    const auto linear = [&](const std::string& prefix, std::int64_t out, std::int64_t in) {
      return Linear{tensor(prefix + ".weight", {out, in}), tensor(prefix + ".bias", {out})};
    };
    const auto ffn = [&](const std::string& prefix) {
      Ffn f;
      f.fc0 = linear(prefix + ".0", 2 * d, 2 * d);
      f.norm_weight = tensor(prefix + ".1.weight", {2 * d});
      f.norm_bias = tensor(prefix + ".1.bias", {2 * d});
      f.fc3 = linear(prefix + ".3", d, 2 * d);
      return f;
    };

    if (arch.input_dim != arch.descriptor_dim) {
      has_input_proj = true;
      input_proj = linear("input_proj", d, arch.input_dim);
    }
    posenc_wr = tensor("posenc.Wr.weight", {dh / 2, 2});
    for (int i = 0; i < arch.n_layers; ++i) {
      const std::string p = "transformers." + std::to_string(i);
      SelfBlock s;
      s.qkv = regroup_qkv(linear(p + ".self_attn.Wqkv", 3 * d, d), h, dh);
      s.out_proj = linear(p + ".self_attn.out_proj", d, d);
      s.ffn = ffn(p + ".self_attn.ffn");
      self_blocks.push_back(std::move(s));

      CrossBlock c;
      const Linear to_qk = linear(p + ".cross_attn.to_qk", d, d), to_v = linear(p + ".cross_attn.to_v", d, d);
      c.qk_v = Linear{at::cat({to_qk.weight, to_v.weight}, 0).contiguous(), at::cat({to_qk.bias, to_v.bias}, 0).contiguous()};
      c.to_out = linear(p + ".cross_attn.to_out", d, d);
      c.ffn = ffn(p + ".cross_attn.ffn");
      cross_blocks.push_back(std::move(c));

      const std::string a = "log_assignment." + std::to_string(i);
      assignment.push_back({linear(a + ".matchability", 1, d), linear(a + ".final_proj", d, d)});
      if (i + 1 < arch.n_layers) token.push_back(linear("token_confidence." + std::to_string(i) + ".token.0", 1, d));
    }
    if (st.contains("confidence_thresholds")) {
      st.check_shape("confidence_thresholds", {arch.n_layers});
      thresholds = st.floats("confidence_thresholds");
      expected.insert("confidence_thresholds");
    } else {
      for (int i = 0; i < arch.n_layers; ++i) thresholds.push_back(confidence_threshold(i, arch.n_layers));
    }
    for (const auto& name : st.names())
      if (!expected.count(name)) throw InputError(st.file(), name, "unexpected tensor (not part of this LightGlue architecture)");
  }

  at::Tensor feed_forward(const Ffn& f, const at::Tensor& x, const at::Tensor& message) const {
    at::Tensor y = f.fc0(at::cat({x, message}, 1));
    y = at::layer_norm(y, {y.size(1)}, f.norm_weight, f.norm_bias, 1e-5);
    return x.add(f.fc3(at::gelu(y)));  // exact (erf) GELU
  }

  // x: [N, D]; cos, sin: [N, 1, dh/2] (one value per frequency). Rotary encoding of q and k
  // (features [even | odd] per head, see SelfBlock): out_e = e cos - o sin, out_o = o cos + e sin.
  at::Tensor self_attention(const SelfBlock& s, const at::Tensor& x, const at::Tensor& cos, const at::Tensor& sin) const {
    const std::int64_t n = x.size(0), h = arch.num_heads, dh = arch.head_dim(), d = arch.descriptor_dim, half = dh / 2;
    const at::Tensor qkv = s.qkv(x);  // [N, 3D]
    const auto rotate = [&](std::int64_t offset, const at::Tensor& c, const at::Tensor& sn) {
      const at::Tensor t = qkv.narrow(1, offset, d).view({n, h, dh});
      const at::Tensor e = t.narrow(2, 0, half), o = t.narrow(2, half, half);
      at::Tensor out = at::empty({h, n, dh}, x.options());  // [H, N, dh] for the products
      at::Tensor out_e = out.narrow(2, 0, half).transpose(0, 1), out_o = out.narrow(2, half, half).transpose(0, 1);
      at::mul_out(out_e, e, c).addcmul_(o, sn, -1);
      at::mul_out(out_o, o, c).addcmul_(e, sn, 1);
      return out;
    };
    // The attention scale dh^-0.5 is folded into q's encoding.
    const double scale = 1.0 / std::sqrt(static_cast<double>(dh));
    const at::Tensor q = rotate(0, cos.mul(scale), sin.mul(scale)), k = rotate(d, cos, sin);
    const at::Tensor v = qkv.narrow(1, 2 * d, d).view({n, h, dh}).transpose(0, 1);
    at::Tensor sim = at::bmm(q, k.transpose(1, 2));  // [H, N, N]
    at::_softmax_out(sim, sim, -1, false);  // in place
    const at::Tensor context = at::bmm(sim, v);  // [H, N, dh]
    const at::Tensor message = s.out_proj(context.transpose(0, 1).reshape({n, d}));
    return feed_forward(s.ffn, x, message);
  }

  // Cross attention for one image: x [M, D] with its own projections qkv [M, 2D] ([qk | v]) and
  // the other image's, other [N, 2D]. The official code computes sim = qk0 qk1^T once and takes its
  // softmax over each image's points; each image here takes the row softmax of its own product
  // (qk1 qk0^T = sim^T), so that the two images' halves run apart (TwoLanes) and the result does not
  // depend on the thread count.
  at::Tensor cross_attention(const CrossBlock& c, const at::Tensor& x, const at::Tensor& qkv, const at::Tensor& other) const {
    const std::int64_t h = arch.num_heads, dh = arch.head_dim(), d = arch.descriptor_dim;
    const auto heads = [&](const at::Tensor& t, std::int64_t offset) {
      return t.narrow(1, offset, d).view({t.size(0), h, dh}).transpose(0, 1);  // [H, *, dh]
    };
    // Official: both sides times scale**0.5; here one side times scale (same product).
    const at::Tensor qk = heads(qkv, 0).mul(1.0 / std::sqrt(static_cast<double>(dh)));
    at::Tensor sim = at::bmm(qk, heads(other, 0).transpose(1, 2));  // [H, M, N]
    at::_softmax_out(sim, sim, 2, false);                          // over the other image's points, in place
    const at::Tensor m = at::bmm(sim, heads(other, d));            // [H, M, dh]
    const at::Tensor message = c.to_out(m.transpose(0, 1).reshape({m.size(1), d}));
    return feed_forward(c.ffn, x, message);
  }

  // The (M+1) x (N+1) log-assignment matrix (dual softmax + matchability).
  at::Tensor log_assignment(int layer, const at::Tensor& d0, const at::Tensor& d1) const {
    const auto& a = assignment[static_cast<std::size_t>(layer)];
    const double norm = std::pow(static_cast<double>(arch.descriptor_dim), 0.25);
    const at::Tensor md0 = a.final_proj(d0).div(norm), md1 = a.final_proj(d1).div(norm);
    const at::Tensor sim = at::mm(md0, md1.t());
    const at::Tensor z0 = a.matchability(d0), z1 = a.matchability(d1);  // [M, 1], [N, 1]
    const std::int64_t m = sim.size(0), n = sim.size(1);
    at::Tensor scores = at::empty({m + 1, n + 1}, sim.options());
    const at::Tensor certainties = at::log_sigmoid(z0).add(at::log_sigmoid(z1).t());
    scores.slice(0, 0, m).slice(1, 0, n).copy_(at::log_softmax(sim, 1).add(at::log_softmax(sim, 0)).add(certainties));
    scores.slice(0, 0, m).select(1, n).copy_(at::log_sigmoid(z0.neg()).squeeze(1));
    scores.select(0, m).slice(0, 0, n).copy_(at::log_sigmoid(z1.neg()).squeeze(1));
    scores.select(0, m).select(0, n).fill_(0.0f);
    return scores;
  }

  at::Tensor matchability(int layer, const at::Tensor& d) const {
    return assignment[static_cast<std::size_t>(layer)].matchability(d).sigmoid().squeeze(1);
  }

  // Projected descriptors and the rotary encoding p = kn Wr^T (one frequency per feature pair).
  PointSet encode(const Features& f, const at::Tensor& normalized_keypoints) const {
    PointSet p;
    p.desc = features_tensor(f.descriptors.data(), f.size(), arch.input_dim);
    if (has_input_proj) p.desc = input_proj(p.desc);
    const at::Tensor freq = at::mm(normalized_keypoints, posenc_wr.t());  // [N, dh/2]
    p.cos = freq.cos().unsqueeze(1);
    p.sin = freq.sin().unsqueeze(1);
    p.index.resize(static_cast<std::size_t>(f.size()));
    std::iota(p.index.begin(), p.index.end(), 0);
    p.layers.assign(static_cast<std::size_t>(f.size()), 1);
    return p;
  }

  // The transformer layers with adaptive depth and width; returns the index of the last layer run.
  // Each image's half of a layer runs on its lane; they meet for the cross projections and after
  // the layer (exit and pruning look at both).
  int run_layers(PointSet& p0, PointSet& p1, const LightGlueConfig& config, TwoLanes& lanes, LightGlueTrace* trace) const {
    const std::int64_t total = static_cast<std::int64_t>(p0.layers.size() + p1.layers.size());
    const std::array<PointSet*, 2> points{&p0, &p1};
    std::array<at::Tensor, 2> qkv;  // cross attention's [qk | v] of each image
    int layer = 0;
    for (; layer < arch.n_layers; ++layer) {
      if (p0.size() == 0 || p1.size() == 0) break;
      const SelfBlock& self = self_blocks[static_cast<std::size_t>(layer)];
      const CrossBlock& cross = cross_blocks[static_cast<std::size_t>(layer)];
      lanes.run([&](int i) {
        PointSet& p = *points[static_cast<std::size_t>(i)];
        p.desc = self_attention(self, p.desc, p.cos, p.sin);
        qkv[static_cast<std::size_t>(i)] = cross.qk_v(p.desc);
      });
      lanes.run([&](int i) {
        PointSet& p = *points[static_cast<std::size_t>(i)];
        p.desc = cross_attention(cross, p.desc, qkv[static_cast<std::size_t>(i)], qkv[static_cast<std::size_t>(1 - i)]);
      });
      if (trace && layer == 0) {
        trace->desc0_after_layer0 = to_eigen(p0.desc);
        trace->desc1_after_layer0 = to_eigen(p1.desc);
      }
      if (layer == arch.n_layers - 1) break;  // no exit or pruning after the last layer

      at::Tensor token0, token1;
      const float threshold = thresholds[static_cast<std::size_t>(layer)];
      if (config.depth_confidence > 0.0f) {
        token0 = token[layer](p0.desc).sigmoid().squeeze(1);
        token1 = token[layer](p1.desc).sigmoid().squeeze(1);
        // Share of confident points; pruned points count as confident (denominator M + N).
        const auto unsure = token0.lt(threshold).sum().item<std::int64_t>() + token1.lt(threshold).sum().item<std::int64_t>();
        if (1.0f - static_cast<float>(unsure) / static_cast<float>(total) > config.depth_confidence) break;
      }
      if (config.width_confidence > 0.0f) {
        const float min_matchability = 1.0f - config.width_confidence;
        for (auto [points, tok] : {std::pair{&p0, &token0}, std::pair{&p1, &token1}}) {
          if (points->size() <= config.pruning_keypoint_threshold) continue;
          at::Tensor keep = matchability(layer, points->desc).gt(min_matchability);
          if (tok->defined()) keep = keep.logical_or(tok->le(threshold));  // unsure points are never pruned
          points->prune(keep);
        }
      }
    }
    return std::min(layer, arch.n_layers - 1);
  }
};

namespace {

// (kp - size/2) / (max(W, H)/2), as the official normalize_keypoints.
at::Tensor normalize_keypoints(const Features& f) {
  at::Tensor kn = features_tensor(f.keypoints.data(), f.size(), 2);
  const float w = static_cast<float>(f.image_size.x()), h = static_cast<float>(f.image_size.y());
  float* p = kn.data_ptr<float>();
  const float scale = std::max(w, h) / 2.0f;
  for (int i = 0; i < f.size(); ++i) {
    p[2 * i] = (p[2 * i] - w / 2.0f) / scale;
    p[2 * i + 1] = (p[2 * i + 1] - h / 2.0f) / scale;
  }
  return kn;
}

void check_features(const Features& f, int input_dim, const char* which) {
  if (f.image_size.x() <= 0 || f.image_size.y() <= 0)
    throw InputError(std::string("LightGlue: ") + which + " has no image size (needed to normalise keypoints)");
  if (f.size() > 0 && f.descriptors.cols() != input_dim)
    throw InputError(std::string("LightGlue: ") + which + " has " + std::to_string(f.descriptors.cols()) +
                     "-dimensional descriptors; these weights expect " + std::to_string(input_dim));
  if (f.descriptors.rows() != f.size()) throw InputError(std::string("LightGlue: ") + which + ": descriptor count differs from keypoint count");
}

struct FilteredMatches {
  std::vector<int> m0, m1;
  std::vector<float> s0, s1;
};

// Official filter_matches on the (M+1) x (N+1) log-assignment: mutual argmax of the inner
// block; scores exp(row max) for every mutual pair; valid when mutual and score > threshold.
FilteredMatches filter_matches(const at::Tensor& scores, float threshold) {
  const at::Tensor c = scores.contiguous();
  const std::int64_t m = c.size(0) - 1, n = c.size(1) - 1, stride = c.size(1);
  const float* s = c.data_ptr<float>();
  std::vector<int> best0(static_cast<std::size_t>(m), 0), best1(static_cast<std::size_t>(n), 0);
  std::vector<float> max0(static_cast<std::size_t>(m), -INFINITY), max1(static_cast<std::size_t>(n), -INFINITY);
  for (std::int64_t i = 0; i < m; ++i) {
    for (std::int64_t j = 0; j < n; ++j) {
      const float v = s[i * stride + j];
      if (v > max0[i]) max0[i] = v, best0[i] = static_cast<int>(j);  // first index wins ties, as torch.max
      if (v > max1[j]) max1[j] = v, best1[j] = static_cast<int>(i);
    }
  }
  FilteredMatches f;
  f.m0.assign(static_cast<std::size_t>(m), -1);
  f.m1.assign(static_cast<std::size_t>(n), -1);
  f.s0.assign(static_cast<std::size_t>(m), 0.0f);
  f.s1.assign(static_cast<std::size_t>(n), 0.0f);
  if (n == 0) return f;
  std::vector<char> valid0(static_cast<std::size_t>(m), 0);
  for (std::int64_t i = 0; i < m; ++i) {
    if (best1[best0[i]] != i) continue;  // not mutual
    f.s0[i] = std::exp(max0[i]);
    valid0[i] = f.s0[i] > threshold;
    if (valid0[i]) f.m0[i] = best0[i];
  }
  if (m == 0) return f;
  for (std::int64_t j = 0; j < n; ++j) {
    const int i = best1[j];
    if (best0[i] != j) continue;
    f.s1[j] = f.s0[i];
    if (valid0[i]) f.m1[j] = i;
  }
  return f;
}

}  // namespace

// ---------------------------------------------------------------------------------------

void save_lightglue_result(const LightGlueResult& r, const std::filesystem::path& file) {
  SafeTensors out;
  const auto ints = [&](const std::string& name, const Eigen::VectorXi& v) {
    const std::vector<std::int64_t> values(v.data(), v.data() + v.size());
    out.set_i64(name, {v.size()}, values.data());
  };
  const std::int64_t k = r.matches.size();
  std::vector<std::int64_t> pairs(static_cast<std::size_t>(2 * k));
  for (std::int64_t i = 0; i < k; ++i) {
    pairs[2 * i] = r.matches.pairs(i, 0);
    pairs[2 * i + 1] = r.matches.pairs(i, 1);
  }
  out.set_i64("matches", {k, 2}, pairs.data());
  out.set_f32("scores", {k}, r.matches.scores.data());
  const std::int64_t stop = r.stop;
  out.set_i64("stop", {1}, &stop);
  ints("matches0", r.matches0);
  ints("matches1", r.matches1);
  out.set_f32("matching_scores0", {r.matching_scores0.size()}, r.matching_scores0.data());
  out.set_f32("matching_scores1", {r.matching_scores1.size()}, r.matching_scores1.data());
  ints("prune0", r.prune0);
  ints("prune1", r.prune1);
  out.metadata()["format"] = "pllvo LightGlue matches (names as the official outputs)";
  out.save(file);
}

LightGlue::LightGlue(LightGlueConfig config) : config_(std::move(config)) {
  config_.validate();
  const auto search = find_weights(config_.weights, lightglue_weight_names());
  if (!search.found) throw InputError("LightGlue weights " + search.not_found_message());
  weights_file_ = *search.found;
  net_ = std::make_unique<Net>(load_weights_with_overrides(weights_file_, config_.weight_overrides));
}

LightGlue::LightGlue(const SafeTensors& weights, LightGlueConfig config)
    : net_(std::make_unique<Net>(weights)), config_(std::move(config)), weights_file_(weights.file()) {
  config_.validate();
}

LightGlue::~LightGlue() = default;
LightGlue::LightGlue(LightGlue&&) noexcept = default;
LightGlue& LightGlue::operator=(LightGlue&&) noexcept = default;

const LightGlueArchitecture& LightGlue::architecture() const { return net_->arch; }

LightGlueResult LightGlue::match(const Features& f0, const Features& f1, LightGlueTrace* trace) const {
  const Net& net = *net_;
  check_features(f0, net.arch.input_dim, "image 0");
  check_features(f1, net.arch.input_dim, "image 1");
  c10::InferenceMode guard;
  TwoLanes lanes;

  const at::Tensor kn0 = normalize_keypoints(f0), kn1 = normalize_keypoints(f1);
  PointSet p0 = net.encode(f0, kn0), p1 = net.encode(f1, kn1);
  if (trace) {
    // As the official encoding: each frequency repeated for its pair, [N, dh].
    const std::int64_t dh = net.arch.head_dim();
    const auto pairs = [&](const at::Tensor& t) {
      return to_eigen(t.squeeze(1).unsqueeze(2).expand({t.size(0), dh / 2, 2}).reshape({t.size(0), dh}));
    };
    trace->keypoints_normalized0 = to_eigen(kn0);
    trace->keypoints_normalized1 = to_eigen(kn1);
    trace->posenc_cos0 = pairs(p0.cos);
    trace->posenc_sin0 = pairs(p0.sin);
    trace->posenc_cos1 = pairs(p1.cos);
    trace->posenc_sin1 = pairs(p1.sin);
  }
  const int last = net.run_layers(p0, p1, config_, lanes, trace);

  LightGlueResult r;
  const std::int64_t m = f0.size(), n = f1.size();
  r.stop = last + 1;
  r.matches0 = Eigen::VectorXi::Constant(m, -1);
  r.matches1 = Eigen::VectorXi::Constant(n, -1);
  r.matching_scores0 = Eigen::VectorXf::Zero(m);
  r.matching_scores1 = Eigen::VectorXf::Zero(n);
  const bool pruning = config_.width_confidence > 0.0f;
  r.prune0 = pruning ? Eigen::Map<const Eigen::VectorXi>(p0.layers.data(), m).eval() : Eigen::VectorXi::Constant(m, net.arch.n_layers);
  r.prune1 = pruning ? Eigen::Map<const Eigen::VectorXi>(p1.layers.data(), n).eval() : Eigen::VectorXi::Constant(n, net.arch.n_layers);
  r.matches.pairs.resize(0, 2);
  if (p0.size() == 0 || p1.size() == 0) return r;

  const at::Tensor scores = net.log_assignment(last, p0.desc, p1.desc);
  if (trace && trace->want_log_assignment) trace->log_assignment = to_eigen(scores);
  const auto fm = filter_matches(scores, config_.filter_threshold);
  // Back to the original indices (the identity without pruning).
  for (std::size_t i = 0; i < fm.m0.size(); ++i) {
    r.matching_scores0(p0.index[i]) = fm.s0[i];
    if (fm.m0[i] >= 0) r.matches0(p0.index[i]) = static_cast<int>(p1.index[static_cast<std::size_t>(fm.m0[i])]);
  }
  for (std::size_t j = 0; j < fm.m1.size(); ++j) {
    r.matching_scores1(p1.index[j]) = fm.s1[j];
    if (fm.m1[j] >= 0) r.matches1(p1.index[j]) = static_cast<int>(p0.index[static_cast<std::size_t>(fm.m1[j])]);
  }
  const auto k = (r.matches0.array() >= 0).count();
  r.matches.pairs.resize(k, 2);
  r.matches.scores.resize(k);
  for (Eigen::Index i = 0, row = 0; i < m; ++i) {
    if (r.matches0(i) < 0) continue;
    r.matches.pairs.row(row) << static_cast<int>(i), r.matches0(i);
    r.matches.scores(row++) = r.matching_scores0(i);
  }
  return r;
}

}  // namespace pllvo::nn
