#pragma once
// Loading dataset images as the 8-bit grayscale the front end works on.
#include <filesystem>

#include <opencv2/core.hpp>

namespace pllvo::io {

/// Reads `file` as CV_8UC1: colour is converted with OpenCV's BGR weights, 16-bit is scaled
/// by 255/65535 (full range to full range). No EXIF rotation is applied. InputError naming
/// the file when it is missing, unreadable or of an unsupported pixel type, and when
/// `expected` is non-empty and the image has another size.
cv::Mat read_gray_image(const std::filesystem::path& file, cv::Size expected = {});

}  // namespace pllvo::io
