#include "pllvo/io/gray_image.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {
std::string size_text(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

cv::Mat read_unchanged(const fs::path& file) {
  if (!fs::is_regular_file(file)) throw InputError(file, "image file not found");
  cv::Mat raw;
  try {
    raw = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(file, "cannot decode the image: " + e.msg);
  }
  if (raw.empty()) throw InputError(file, "cannot read the image (corrupt or not an image format OpenCV reads)");
  return raw;
}

}  // namespace

cv::Mat read_gray_image(const fs::path& file, cv::Size expected) {
  const cv::Mat raw = read_unchanged(file);

  cv::Mat gray;
  switch (raw.channels()) {
    case 1: gray = raw; break;
    case 3: cv::cvtColor(raw, gray, cv::COLOR_BGR2GRAY); break;
    case 4: cv::cvtColor(raw, gray, cv::COLOR_BGRA2GRAY); break;
    default:
      throw InputError(file, "unsupported image with " + std::to_string(raw.channels()) + " channels");
  }
  if (gray.depth() == CV_16U) {
    cv::Mat scaled;
    gray.convertTo(scaled, CV_8U, 255.0 / 65535.0);
    gray = scaled;
  } else if (gray.depth() != CV_8U) {
    throw InputError(file, "unsupported pixel type (expected 8- or 16-bit integer pixels)");
  }

  if (!expected.empty() && gray.size() != expected)
    throw InputError(file, "image is " + size_text(gray.size()) + " but the calibration says " +
                               size_text(expected));
  return gray;
}

cv::Mat read_depth_image(const fs::path& file, double units_per_metre, cv::Size expected) {
  const cv::Mat raw = read_unchanged(file);
  if (raw.type() != CV_16UC1)
    throw InputError(file, "a depth image must be 16-bit with one channel (got " + std::to_string(raw.channels()) +
                               " channel(s) of " + (raw.depth() == CV_8U ? "8" : "other") + "-bit pixels)");
  if (!expected.empty() && raw.size() != expected)
    throw InputError(file, "depth image is " + size_text(raw.size()) + " but the calibration says " +
                               size_text(expected));
  cv::Mat metres;
  raw.convertTo(metres, CV_32F, 1.0 / units_per_metre);
  return metres;
}

}  // namespace pllvo::io
