#include "pllvo/nn/safetensors.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "pllvo/common/error.h"

static_assert(std::endian::native == std::endian::little, "safetensors data is little-endian");

namespace pllvo::nn {
namespace {

constexpr std::uint64_t kMaxHeaderBytes = 100u << 20;

DType parse_dtype(const std::filesystem::path& file, const std::string& name, const std::string& s) {
  if (s == "F32") return DType::F32;
  if (s == "F16") return DType::F16;
  if (s == "I64") return DType::I64;
  throw InputError(file, name, "dtype " + s + " is not supported (F32, F16, I64)");
}

std::int64_t product(const std::vector<std::int64_t>& shape) {
  std::int64_t n = 1;
  for (auto d : shape) n *= d;
  return n;
}

std::vector<char> read_all(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "cannot open the file");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::size_t>(in.tellg());
  in.seekg(0);
  std::vector<char> data(size);
  if (size > 0 && !in.read(data.data(), static_cast<std::streamsize>(size)))
    throw InputError(file, "cannot read the file");
  return data;
}

StoredTensor parse_entry(const std::filesystem::path& file, const std::string& name,
                         const nlohmann::json& entry, const char* data, std::uint64_t data_size) {
  if (!entry.is_object() || !entry.contains("dtype") || !entry.contains("shape") ||
      !entry.contains("data_offsets"))
    throw InputError(file, name, "header entry needs dtype, shape and data_offsets");
  StoredTensor t;
  if (!entry["dtype"].is_string()) throw InputError(file, name, "dtype is not a string");
  t.dtype = parse_dtype(file, name, entry["dtype"].get<std::string>());
  const auto& shape = entry["shape"];
  if (!shape.is_array()) throw InputError(file, name, "shape is not an array");
  for (const auto& d : shape) {
    if (!d.is_number_integer() || d.get<std::int64_t>() < 0)
      throw InputError(file, name, "shape holds a non-integer or negative size");
    t.shape.push_back(d.get<std::int64_t>());
  }
  const auto& off = entry["data_offsets"];
  if (!off.is_array() || off.size() != 2 || !off[0].is_number_unsigned() || !off[1].is_number_unsigned())
    throw InputError(file, name, "data_offsets must be two non-negative integers");
  const auto begin = off[0].get<std::uint64_t>();
  const auto end = off[1].get<std::uint64_t>();
  const auto expected = static_cast<std::uint64_t>(product(t.shape)) * dtype_size(t.dtype);
  if (end < begin || end - begin != expected)
    throw InputError(file, name, "data_offsets [" + std::to_string(begin) + ", " + std::to_string(end) +
                                     "] do not hold " + shape_string(t.shape) + " " + dtype_name(t.dtype));
  if (end > data_size) throw InputError(file, name, "data_offsets run past the end of the file (truncated?)");
  t.bytes.resize(expected);
  if (expected > 0) std::memcpy(t.bytes.data(), data + begin, expected);
  return t;
}

}  // namespace

std::string dtype_name(DType dtype) {
  switch (dtype) {
    case DType::F32: return "F32";
    case DType::F16: return "F16";
    case DType::I64: return "I64";
  }
  return "?";
}

std::size_t dtype_size(DType dtype) {
  switch (dtype) {
    case DType::F32: return 4;
    case DType::F16: return 2;
    case DType::I64: return 8;
  }
  return 0;
}

std::string shape_string(const std::vector<std::int64_t>& shape) {
  std::ostringstream s;
  s << '[';
  for (std::size_t i = 0; i < shape.size(); ++i) s << (i ? ", " : "") << shape[i];
  s << ']';
  return s.str();
}

float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu;
  std::uint32_t mantissa = h & 0x3ffu;
  std::uint32_t bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // inf / NaN
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112u) << 23) | (mantissa << 13);
  } else if (mantissa == 0) {
    bits = sign;  // signed zero
  } else {
    // Subnormal half: normalise the mantissa into a normal float.
    int e = -1;
    do {
      ++e;
      mantissa <<= 1;
    } while ((mantissa & 0x400u) == 0);
    bits = sign | static_cast<std::uint32_t>(112 - e) << 23 | ((mantissa & 0x3ffu) << 13);
  }
  return std::bit_cast<float>(bits);
}

std::uint16_t float_to_half(float f) {
  const std::uint32_t x = std::bit_cast<std::uint32_t>(f);
  const std::uint16_t sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
  const std::uint32_t abs = x & 0x7fffffffu;
  if (abs >= 0x7f800000u)  // inf or NaN (NaN keeps a non-zero mantissa)
    return sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u);
  if (abs >= 0x477ff000u) return sign | 0x7c00u;  // rounds to >= 65520: overflow to inf
  if (abs < 0x38800000u) {
    // Result is subnormal (or zero): shift the full mantissa, round to nearest even.
    if (abs < 0x33000000u) return sign;  // below half the smallest subnormal
    const std::uint32_t e = abs >> 23;
    const std::uint32_t m = (abs & 0x7fffffu) | 0x800000u;
    const std::uint32_t shift = 126 - e;  // 14 + (113 - e) - 1
    std::uint32_t value = m >> shift;
    const std::uint32_t rest = m & ((1u << shift) - 1);
    const std::uint32_t halfway = 1u << (shift - 1);
    if (rest > halfway || (rest == halfway && (value & 1u))) ++value;
    return sign | static_cast<std::uint16_t>(value);
  }
  // Normal: rebias the exponent, round the 13 dropped bits to nearest even.
  std::uint32_t value = ((abs >> 13) - (112u << 10));
  const std::uint32_t rest = abs & 0x1fffu;
  if (rest > 0x1000u || (rest == 0x1000u && (value & 1u))) ++value;
  return sign | static_cast<std::uint16_t>(value);
}

std::int64_t StoredTensor::numel() const { return product(shape); }

SafeTensors SafeTensors::load(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw InputError(file, "file not found");
  const auto raw = read_all(file);
  if (raw.size() < 8) throw InputError(file, "not a safetensors file (shorter than its 8-byte header length)");
  std::uint64_t n = 0;
  std::memcpy(&n, raw.data(), 8);
  if (n > kMaxHeaderBytes || n > raw.size() - 8)
    throw InputError(file, "not a safetensors file (header length " + std::to_string(n) + " is impossible)");
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(raw.begin() + 8, raw.begin() + 8 + static_cast<std::ptrdiff_t>(n));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("malformed safetensors JSON header: ") + e.what());
  }
  if (!header.is_object()) throw InputError(file, "safetensors header is not a JSON object");

  SafeTensors out;
  out.file_ = file;
  const char* data = raw.data() + 8 + n;
  const std::uint64_t data_size = raw.size() - 8 - n;
  for (const auto& [name, entry] : header.items()) {
    if (name == "__metadata__") {
      if (!entry.is_object()) throw InputError(file, name, "must be an object of strings");
      for (const auto& [key, value] : entry.items()) {
        if (!value.is_string()) throw InputError(file, "__metadata__." + key, "value is not a string");
        out.metadata_[key] = value.get<std::string>();
      }
      continue;
    }
    out.tensors_[name] = parse_entry(file, name, entry, data, data_size);
  }
  return out;
}

void SafeTensors::save(const std::filesystem::path& file) const {
  nlohmann::json header = nlohmann::json::object();
  std::uint64_t offset = 0;
  for (const auto& [name, t] : tensors_) {
    header[name] = {{"dtype", dtype_name(t.dtype)},
                    {"shape", t.shape},
                    {"data_offsets", {offset, offset + t.bytes.size()}}};
    offset += t.bytes.size();
  }
  if (!metadata_.empty()) header["__metadata__"] = metadata_;
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');
  const std::uint64_t n = text.size();

  const auto tmp = std::filesystem::path(file.string() + ".tmp");
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(file, "cannot write the file");
    out.write(reinterpret_cast<const char*>(&n), 8);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    for (const auto& [name, t] : tensors_)
      out.write(reinterpret_cast<const char*>(t.bytes.data()), static_cast<std::streamsize>(t.bytes.size()));
    if (!out.flush()) {
      out.close();
      std::filesystem::remove(tmp);
      throw InputError(file, "cannot write the file (disk full?)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw InputError(file, "cannot write the file: " + ec.message());
  }
}

std::vector<std::string> SafeTensors::names() const {
  std::vector<std::string> out;
  out.reserve(tensors_.size());
  for (const auto& kv : tensors_) out.push_back(kv.first);
  return out;
}

const StoredTensor& SafeTensors::at(const std::string& name) const {
  const auto it = tensors_.find(name);
  if (it == tensors_.end()) throw InputError(file_, name, "tensor missing");
  return it->second;
}

std::vector<float> SafeTensors::floats(const std::string& name) const {
  const auto& t = at(name);
  std::vector<float> out(static_cast<std::size_t>(t.numel()));
  if (t.dtype == DType::F32) {
    if (!out.empty()) std::memcpy(out.data(), t.bytes.data(), t.bytes.size());
  } else if (t.dtype == DType::F16) {
    for (std::size_t i = 0; i < out.size(); ++i) {
      std::uint16_t h;
      std::memcpy(&h, t.bytes.data() + 2 * i, 2);
      out[i] = half_to_float(h);
    }
  } else {
    throw InputError(file_, name, "dtype " + dtype_name(t.dtype) + ", expected F32 or F16");
  }
  return out;
}

std::vector<std::int64_t> SafeTensors::ints(const std::string& name) const {
  const auto& t = at(name);
  if (t.dtype != DType::I64) throw InputError(file_, name, "dtype " + dtype_name(t.dtype) + ", expected I64");
  std::vector<std::int64_t> out(static_cast<std::size_t>(t.numel()));
  if (!out.empty()) std::memcpy(out.data(), t.bytes.data(), t.bytes.size());
  return out;
}

void SafeTensors::check_shape(const std::string& name, const std::vector<std::int64_t>& expected) const {
  const auto& t = at(name);
  if (t.shape != expected)
    throw InputError(file_, name, "shape " + shape_string(t.shape) + ", expected " + shape_string(expected));
}

void SafeTensors::set(const std::string& name, StoredTensor tensor) {
  if (name.empty() || name == "__metadata__") throw InternalError("safetensors: invalid tensor name '" + name + "'");
  if (tensor.bytes.size() != static_cast<std::size_t>(tensor.numel()) * dtype_size(tensor.dtype))
    throw InternalError("safetensors: tensor '" + name + "' byte size does not match its shape");
  tensors_[name] = std::move(tensor);
}

void SafeTensors::set_f32(const std::string& name, std::vector<std::int64_t> shape, const float* data) {
  StoredTensor t{DType::F32, std::move(shape), {}};
  t.bytes.resize(static_cast<std::size_t>(t.numel()) * 4);
  if (!t.bytes.empty()) std::memcpy(t.bytes.data(), data, t.bytes.size());
  set(name, std::move(t));
}

void SafeTensors::set_f16(const std::string& name, std::vector<std::int64_t> shape, const float* data) {
  StoredTensor t{DType::F16, std::move(shape), {}};
  const auto n = static_cast<std::size_t>(t.numel());
  t.bytes.resize(n * 2);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t h = float_to_half(data[i]);
    std::memcpy(t.bytes.data() + 2 * i, &h, 2);
  }
  set(name, std::move(t));
}

void SafeTensors::set_i64(const std::string& name, std::vector<std::int64_t> shape, const std::int64_t* data) {
  StoredTensor t{DType::I64, std::move(shape), {}};
  t.bytes.resize(static_cast<std::size_t>(t.numel()) * 8);
  if (!t.bytes.empty()) std::memcpy(t.bytes.data(), data, t.bytes.size());
  set(name, std::move(t));
}

}  // namespace pllvo::nn
