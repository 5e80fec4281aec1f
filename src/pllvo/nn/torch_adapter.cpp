#include "pllvo/nn/torch_adapter.h"

#include <cstring>

#include <ATen/ops/empty.h>

namespace pllvo::nn::detail {

at::Tensor float_tensor(const SafeTensors& st, const std::string& name, const std::vector<std::int64_t>& shape) {
  st.check_shape(name, shape);
  const auto values = st.floats(name);
  auto t = at::empty(shape, at::TensorOptions().dtype(at::kFloat));
  if (!values.empty()) std::memcpy(t.data_ptr<float>(), values.data(), values.size() * sizeof(float));
  return t;
}

std::vector<float> to_vector(const at::Tensor& t) {
  const auto c = t.to(at::kFloat).contiguous();
  std::vector<float> out(static_cast<std::size_t>(c.numel()));
  if (!out.empty()) std::memcpy(out.data(), c.data_ptr<float>(), out.size() * sizeof(float));
  return out;
}

}  // namespace pllvo::nn::detail
