// The safetensors reader/writer: round trips, half-precision conversion, and malformed files
// rejected with an error naming the file and the tensor.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "nn_test_util.h"
#include "pllvo/common/error.h"
#include "pllvo/nn/safetensors.h"

namespace pllvo::nn {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("pllvo_st_" + std::to_string(::getpid()) + "_" + name);
}

void write_raw(const fs::path& file, const std::string& header, const std::string& data) {
  std::ofstream out(file, std::ios::binary);
  const std::uint64_t n = header.size();
  out.write(reinterpret_cast<const char*>(&n), 8);
  out << header << data;
}

TEST(SafeTensors, RoundTripKeepsDtypesShapesValuesAndMetadata) {
  SafeTensors st;
  const std::vector<float> f = {1.5f, -2.0f, 3.25f, 0.0f, 1e-3f, 65504.0f};
  const std::vector<std::int64_t> i = {-1, 0, 7, std::numeric_limits<std::int64_t>::max()};
  st.set_f32("a.weight", {2, 3}, f.data());
  st.set_f16("b", {6}, f.data());
  st.set_i64("c", {4}, i.data());
  st.set_f32("empty", {0, 256}, nullptr);
  st.metadata()["config"] = R"({"n": 1})";
  const auto file = temp_file("rt.safetensors");
  st.save(file);
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));

  std::ifstream in(file, std::ios::binary);
  std::uint64_t header = 0;
  in.read(reinterpret_cast<char*>(&header), 8);
  EXPECT_EQ(header % 8, 0u) << "header padded to 8 bytes";

  const auto back = SafeTensors::load(file);
  EXPECT_EQ(back.names(), (std::vector<std::string>{"a.weight", "b", "c", "empty"}));
  EXPECT_EQ(back.at("a.weight").shape, (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(back.floats("a.weight"), f);
  EXPECT_EQ(back.at("b").dtype, DType::F16);
  const auto h = back.floats("b");
  for (std::size_t k = 0; k < f.size(); ++k) EXPECT_NEAR(h[k], f[k], std::abs(f[k]) * 1e-3f) << k;
  EXPECT_EQ(h[0], 1.5f);  // exactly representable
  EXPECT_EQ(back.ints("c"), i);
  EXPECT_EQ(back.at("empty").numel(), 0);
  EXPECT_EQ(back.metadata().at("config"), R"({"n": 1})");
  fs::remove(file);
}

TEST(SafeTensors, HalfConversionIsExactAndRoundsToNearestEven) {
  // Every finite half converts to float and back unchanged.
  for (std::uint32_t bits = 0; bits < 0x10000; ++bits) {
    const auto h = static_cast<std::uint16_t>(bits);
    if ((h & 0x7c00u) == 0x7c00u && (h & 0x3ffu)) continue;  // NaN payloads
    ASSERT_EQ(float_to_half(half_to_float(h)), h) << std::hex << bits;
  }
  EXPECT_EQ(half_to_float(0x3c00), 1.0f);
  EXPECT_EQ(half_to_float(0x0001), std::ldexp(1.0f, -24));  // smallest subnormal
  EXPECT_EQ(half_to_float(0xfc00), -std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(half_to_float(float_to_half(std::nanf("")))));
  EXPECT_EQ(float_to_half(1.0f + std::ldexp(1.0f, -11)), 0x3c00);      // halfway: to even
  EXPECT_EQ(float_to_half(1.0f + 3 * std::ldexp(1.0f, -11)), 0x3c02);  // halfway: to even (up)
  EXPECT_EQ(float_to_half(70000.0f), 0x7c00);                           // overflow to inf
  EXPECT_EQ(float_to_half(std::ldexp(1.0f, -26)), 0x0000);              // underflow to zero
}

TEST(SafeTensors, ReadsTheSharedF16Weights) {
  const auto st = SafeTensors::load(test::superpoint_vector("superpoint_random_weights.safetensors"));
  EXPECT_EQ(st.size(), 24u);
  EXPECT_EQ(st.at("conv1a.weight").dtype, DType::F16);
  EXPECT_EQ(st.at("convDb.weight").shape, (std::vector<std::int64_t>{256, 256, 1, 1}));
  EXPECT_NE(st.metadata().at("format").find("RANDOM"), std::string::npos);
}

TEST(SafeTensors, MalformedFilesNameFileAndTensor) {
  const auto file = temp_file("bad.safetensors");
  const auto expect_error = [&](const std::string& header, const std::string& data, const std::string& key,
                                const std::string& text) {
    write_raw(file, header, data);
    try {
      SafeTensors::load(file);
      ADD_FAILURE() << "accepted: " << header;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file.string());
      EXPECT_EQ(e.key(), key) << e.what();
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"x": {"dtype": "BF16", "shape": [1], "data_offsets": [0, 2]}})", "ab", "x", "not supported");
  expect_error(R"({"x": {"dtype": "F32", "shape": [2], "data_offsets": [0, 4]}})", "abcd", "x", "do not hold [2] F32");
  expect_error(R"({"x": {"dtype": "F32", "shape": [2], "data_offsets": [0, 8]}})", "abcd", "x", "truncated");
  expect_error(R"({"x": {"dtype": "F32", "shape": [-1], "data_offsets": [0, 4]}})", "abcd", "x", "negative");
  expect_error(R"({"__metadata__": {"a": 1}})", "", "__metadata__.a", "not a string");
  expect_error(R"({"x": {"dtype": "F32"}})", "", "x", "needs dtype, shape and data_offsets");

  write_raw(file, "{not json", "");
  EXPECT_THROW(SafeTensors::load(file), InputError);
  std::ofstream(file, std::ios::binary) << "abc";
  EXPECT_THROW(SafeTensors::load(file), InputError);
  EXPECT_THROW(SafeTensors::load(temp_file("missing.safetensors")), InputError);

  SafeTensors st;
  const float v = 1;
  st.set_f32("x", {1}, &v);
  try {
    st.check_shape("x", {2});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "x");
    EXPECT_NE(std::string(e.what()).find("shape [1], expected [2]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(st.ints("x"), InputError);
  EXPECT_THROW(st.at("y"), InputError);
  fs::remove(file);
}

}  // namespace
}  // namespace pllvo::nn
