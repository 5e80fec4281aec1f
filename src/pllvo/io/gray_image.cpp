#include "pllvo/io/gray_image.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pllvo/common/error.h"

namespace pllvo::io {

namespace fs = std::filesystem;

namespace {
std::string size_text(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }
}  // namespace

cv::Mat read_gray_image(const fs::path& file, cv::Size expected) {
  if (!fs::is_regular_file(file)) throw InputError(file, "image file not found");
  cv::Mat raw;
  try {
    raw = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(file, "cannot decode the image: " + e.msg);
  }
  if (raw.empty()) throw InputError(file, "cannot read the image (corrupt or not an image format OpenCV reads)");

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

}  // namespace pllvo::io
