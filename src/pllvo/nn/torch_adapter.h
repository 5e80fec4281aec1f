#pragma once
// Internal to nn/ (never include it from a public header): the bridge between the
// torch-free SafeTensors container and ATen tensors. Only ATen's per-operator headers
// are used in nn/, which keeps LibTorch's compile cost inside a few .cpp files.
#include <string>
#include <vector>

#include <ATen/core/Tensor.h>

#include "pllvo/nn/safetensors.h"

namespace pllvo::nn::detail {

/// The tensor as a contiguous float32 CPU tensor (F16 converted exactly); InputError
/// naming the file and tensor when it is missing, not floating point, or has another shape.
at::Tensor float_tensor(const SafeTensors& st, const std::string& name, const std::vector<std::int64_t>& shape);

/// Copies a float32 tensor of any layout into a contiguous std::vector.
std::vector<float> to_vector(const at::Tensor& t);

}  // namespace pllvo::nn::detail
