#pragma once
// The safetensors format (https://github.com/huggingface/safetensors), read and written
// without any tensor library so that every module can use it:
//   8-byte little-endian header length n, a JSON header of n bytes
//   {name: {"dtype", "shape", "data_offsets": [begin, end]}, "__metadata__": {str: str}},
//   then the raw little-endian C-order data (offsets relative to the end of the header).
// Only the dtypes pllvo stores are supported: F32, F16 and I64. Every error names the
// file and the tensor (or header field) at fault.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace pllvo::nn {

enum class DType { F32, F16, I64 };

std::string dtype_name(DType dtype);
std::size_t dtype_size(DType dtype);
std::string shape_string(const std::vector<std::int64_t>& shape);  ///< "[512, 2]"

/// IEEE half <-> single precision (round to nearest even; subnormals, inf, NaN kept).
float half_to_float(std::uint16_t h);
std::uint16_t float_to_half(float f);

/// One stored tensor: dtype, shape and its raw little-endian bytes.
struct StoredTensor {
  DType dtype = DType::F32;
  std::vector<std::int64_t> shape;
  std::vector<std::byte> bytes;

  std::int64_t numel() const;
};

/// A whole safetensors file in memory: load, inspect, modify, save.
class SafeTensors {
 public:
  /// Reads and validates a file; InputError naming the file (and tensor) when malformed.
  static SafeTensors load(const std::filesystem::path& file);

  /// Writes the file atomically (temporary file + rename): nothing half-written on error.
  /// Tensors are stored in name order; the header is padded with spaces to a multiple of 8.
  void save(const std::filesystem::path& file) const;

  bool contains(const std::string& name) const { return tensors_.count(name) != 0; }
  std::vector<std::string> names() const;
  std::size_t size() const { return tensors_.size(); }

  /// The tensor; InputError "<file>: key '<name>': tensor missing" when absent.
  const StoredTensor& at(const std::string& name) const;

  /// Values as float (F32 or F16 converted exactly) / as int64 (I64). InputError for another dtype.
  std::vector<float> floats(const std::string& name) const;
  std::vector<std::int64_t> ints(const std::string& name) const;

  /// InputError naming the tensor when its shape differs from `expected`.
  void check_shape(const std::string& name, const std::vector<std::int64_t>& expected) const;

  void set(const std::string& name, StoredTensor tensor);
  void set_f32(const std::string& name, std::vector<std::int64_t> shape, const float* data);
  void set_f16(const std::string& name, std::vector<std::int64_t> shape, const float* data);
  void set_i64(const std::string& name, std::vector<std::int64_t> shape, const std::int64_t* data);
  void erase(const std::string& name) { tensors_.erase(name); }

  const std::map<std::string, std::string>& metadata() const { return metadata_; }
  std::map<std::string, std::string>& metadata() { return metadata_; }

  /// The file it was loaded from (empty for an in-memory object); used in error messages.
  const std::filesystem::path& file() const { return file_; }
  void set_file(std::filesystem::path file) { file_ = std::move(file); }

 private:
  std::filesystem::path file_;
  std::map<std::string, StoredTensor> tensors_;
  std::map<std::string, std::string> metadata_;
};

}  // namespace pllvo::nn
